// What keeps a run's record true when something goes wrong around the mechanics:
//  - checked output: every write, flush, close and rename is checked, and a failure is an OutputError
//    naming the file and the system's reason (a full disk, a file size limit), never a half-written
//    file that looks complete;
//  - interruption: SIGTERM, SIGINT and SIGHUP set a flag that the solver polls (on every rank, agreed
//    collectively) between Newton iterations, so a run stops at a defined point and says so; a second
//    signal ends the process at once;
//  - collective errors: work done on one rank (rank 0 writes the files) is followed by an agreement, so
//    an error raised there stops every rank with the same message instead of leaving the others waiting
//    in the next collective operation.
#pragma once
#include <cstdio>
#include <filesystem>
#include <functional>
#include <new>
#include <stdexcept>
#include <string>

#include "TpetraTypes.hpp"
#include "linalg/Errors.hpp"

namespace bc::core {

// A results file could not be written (the message names the file and the reason).
class OutputError : public std::runtime_error {
 public:
  explicit OutputError(const std::string& what, std::string reason = "")
      : std::runtime_error(what), reason_(std::move(reason)) {}
  // The system's reason alone (e.g. "No space left on device"), when there is one.
  const std::string& reason() const { return reason_; }

 private:
  std::string reason_;
};

// The run was stopped by a signal (its number is in signal()).
class Interrupted : public std::runtime_error {
 public:
  explicit Interrupted(int signal);
  int signal() const { return signal_; }

 private:
  int signal_;
};

// OutOfMemory, isOutOfMemory, outOfMemoryText and rethrowIfOutOfMemory: linalg/Errors.hpp.

// `e`'s message as one line: a failed allocation's outOfMemoryText, else the first line of what()
// (several lines from a library: the rest is its trace).
std::string oneLine(const std::exception& e);

// A text file written in pieces (CSV rows); every piece is written and flushed at once and checked.
class OutputFile {
 public:
  OutputFile() = default;
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  ~OutputFile();
  // Opens for writing (truncating) or appending; `exclusive`: the file must not exist yet.
  void open(const std::filesystem::path& path, bool append = false, bool exclusive = false);
  void write(const std::string& text);
  void close();
  bool isOpen() const { return file_ != nullptr; }
  // The file's length now (-1 when not open), and a return to that length (best effort, never throws):
  // the rows of a step that could not be written whole in every file are taken back from all of them.
  long length() const;
  // Whether the open file is still the one at its path (not removed, moved or replaced).
  bool stillAtItsPath() const;
  const std::string& path() const { return path_; }
  void truncateTo(long length) noexcept;

 private:
  void fail(const std::string& what);
  [[noreturn]] void failLink();
  std::FILE* file_ = nullptr;
  std::string path_;
};

// Writes `text` to `path` through a temporary file in the same directory and a rename, so the file is
// either the old one or the complete new one. Throws OutputError.
void writeFileAtomically(const std::filesystem::path& path, const std::string& text);
// The system's reason for the last failed call, e.g. "No space left on device".
std::string systemReason();

// Signal handling (call once, after MPI is initialized): SIGTERM, SIGINT and SIGHUP are recorded;
// SIGXFSZ is ignored so that a file size limit makes the write fail (and be reported) instead of
// killing the process. With `restartCalls` false a signal interrupts a blocking call (EINTR), for a
// process that waits on others.
void installSignalHandlers(bool restartCalls = true);
// The signal received so far on this rank (0: none).
int receivedSignal();
// Collective: the signal received on any rank (the largest number), 0 if none.
int receivedSignalOnAnyRank(const Comm& comm);
// "SIGTERM", "SIGINT", ... or "signal N".
std::string signalName(int signal);

// Runs `work` on every rank (on ranks where it has nothing to do it simply returns), then agrees:
// when it threw on any rank, every rank throws the first failing rank's error, of the same kind
// (InputError, OutputError, Interrupted or std::runtime_error).
void collectively(const Comm& comm, const std::function<void()>& work);

// What is said of an exception that is not a std::exception (caught by collectively() and the
// driver): it names the code besides ours that was running, set by the plug-in loader.
void setForeignCodeNote(const std::string& note);
std::string foreignCodeNote();
std::string nonStandardExceptionMessage();
// Runs code besides ours (a plug-in's registration, a plug-in strategy's constructor): whatever it
// throws, of any type, becomes one InputError, "<who>: <message>" for an InputError, else
// "<who> <failure>: <message>" ("... it threw an exception that is not a std::exception").
void runForeignCode(const std::string& who, const std::string& failure, const std::function<void()>& work);

// Tests only: with BEAMCONTACT_INJECT_FAULT="place:rank" in the environment, throws a
// std::runtime_error at `place` on that rank alone (places: "deck", "plugin", "strategy",
// "assembly", "solve", "output"), to show that every rank stops with it.
void injectFault(const char* place);
// Whether BEAMCONTACT_INJECT_FAULT is set (the same on every rank: mpirun passes the environment), so a
// place that needs an agreement of its own only for the hook pays for it only then.
bool faultInjection();
// The same hook for a fault that is not an exception: true at `place` on the rank the spec names
// ("step": Newton's step changed on that rank alone, to show that the ranks stop together).
bool faultAt(const char* place);

// The status file of the run in progress (rank 0; "" when none), for a last word when the process is
// ended from outside the normal path (an exit() in a plug-in): recordFailureInStatus rewrites it in
// place: its first line becomes `text`, the lines after it stay (no allocation of new blocks, never throws).
void setStatusFile(const std::string& path);
void recordFailureInStatus(const std::string& text) noexcept;
// Replaces the content of the existing file `path` by `text` in place: no new file, and no new blocks
// while the text fits the space allocated to it (a full disk). False when that fails too.
bool rewriteInPlace(const std::filesystem::path& path, const std::string& text) noexcept;

}  // namespace bc::core
