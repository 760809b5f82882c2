#include "Faults.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <stdio_ext.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <vector>

#include <mpi.h>

#include <Teuchos_CommHelpers.hpp>

#include "Parameters.hpp"

namespace bc::core {

namespace fs = std::filesystem;

namespace {
volatile std::sig_atomic_t g_signal = 0;

extern "C" void onSignal(int sig) {
  if (g_signal != 0) {
    // A second signal: the user insists. End now with the conventional status.
    std::signal(sig, SIG_DFL);
    std::raise(sig);
    return;
  }
  g_signal = sig;
}
}  // namespace

Interrupted::Interrupted(int signal) : std::runtime_error("interrupted by " + signalName(signal)), signal_(signal) {}

std::string systemReason() { return errno ? std::strerror(errno) : "unknown reason"; }

OutputFile::~OutputFile() {
  if (file_) std::fclose(file_);
}

void OutputFile::fail(const std::string& what) {
  const std::string reason = systemReason();
  if (file_) std::fclose(file_);
  file_ = nullptr;
  throw OutputError("cannot " + what + " " + path_ + ": " + reason, reason);
}

void OutputFile::failLink() {
  throw OutputError("cannot write " + path_ + ": it is a symbolic link (results files are not written through links)",
                    "a symbolic link");
}

void OutputFile::open(const fs::path& path, bool append, bool exclusive) {
  if (file_) close();
  path_ = path.string();
  errno = 0;
  // Never through a symbolic link in the last component: a link planted where a results file goes
  // would send the writes elsewhere.
  const int fd = ::open(
      path_.c_str(),
      O_WRONLY | O_CREAT | O_NOFOLLOW | O_CLOEXEC | (append ? O_APPEND : O_TRUNC) | (exclusive ? O_EXCL : 0), 0644);
  if (fd < 0) {
    if (errno == ELOOP) failLink();
    if (errno == EEXIST && exclusive)
      throw OutputError("cannot write " + path_ +
                            ": the file exists (beamcontact writes through this name and "
                            "never replaces a file it finds there; remove it if it is a leftover of an interrupted "
                            "write)",
                        "the file exists");
    fail("open");
  }
  file_ = fdopen(fd, append ? "a" : "w");
  if (!file_) {
    ::close(fd);
    fail("open");
  }
}

void OutputFile::write(const std::string& text) {
  if (!file_) throw OutputError("cannot write " + path_ + ": the file is not open", "the file is not open");
  errno = 0;
  const long before = std::ftell(file_);
  if (std::fwrite(text.data(), 1, text.size(), file_) != text.size() || std::fflush(file_) != 0) {
    // What part of the text reached the file goes again, so the file ends with a whole row.
    // The stream's buffer is dropped first, so closing it writes nothing more.
    const int saved = errno;
    __fpurge(file_);
    if (before >= 0 && ftruncate(fileno(file_), before) != 0) {
    }
    errno = saved;
    fail("write");
  }
}

long OutputFile::length() const {
  if (!file_) return -1;
  std::fflush(file_);
  struct stat st {};
  return fstat(fileno(file_), &st) == 0 ? static_cast<long>(st.st_size) : -1;
}

bool OutputFile::stillAtItsPath() const {
  if (!file_) return false;
  struct stat open {
  }, named{};
  if (fstat(fileno(file_), &open) != 0 || ::stat(path_.c_str(), &named) != 0) return false;
  return open.st_dev == named.st_dev && open.st_ino == named.st_ino;
}

void OutputFile::truncateTo(long length) noexcept {
  if (!file_ || length < 0) return;
  __fpurge(file_);
  if (ftruncate(fileno(file_), length) != 0) {
  }
}

void OutputFile::close() {
  if (!file_) return;
  errno = 0;
  std::FILE* f = file_;
  file_ = nullptr;
  if (std::fclose(f) != 0) {
    const std::string reason = systemReason();
    throw OutputError("cannot write " + path_ + ": " + reason, reason);
  }
}

void writeFileAtomically(const fs::path& path, const std::string& text) {
  const fs::path tmp = path.string() + ".tmp";
  {
    OutputFile f;
    try {
      f.open(tmp, false, true);
      f.write(text);
      f.close();
    } catch (const OutputError& e) {
      // Named by the file the caller asked for; the reason is the one the failed call gave. The
      // temporary file goes only when this call created it.
      std::error_code ignored;
      if (e.reason() != "the file exists") fs::remove(tmp, ignored);
      else throw;
      throw OutputError("cannot write " + path.string() + ": " + e.reason(), e.reason());
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw OutputError("cannot write " + path.string() + ": " + ec.message(), ec.message());
  }
}

void installSignalHandlers(bool restartCalls) {
  struct sigaction action {};
  action.sa_handler = onSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = restartCalls ? SA_RESTART : 0;
  for (int sig : {SIGTERM, SIGINT, SIGHUP}) sigaction(sig, &action, nullptr);
  std::signal(SIGXFSZ, SIG_IGN);
  // Output piped into a program that ends early (| head): the run goes on and records its status
  // instead of dying silently with "running" in status.txt.
  std::signal(SIGPIPE, SIG_IGN);
}

int receivedSignal() { return g_signal; }

int receivedSignalOnAnyRank(const Comm& comm) {
  int mine = g_signal, any = 0;
  Teuchos::reduceAll(comm, Teuchos::REDUCE_MAX, mine, Teuchos::outArg(any));
  return any;
}

std::string signalName(int signal) {
  switch (signal) {
    case SIGTERM: return "SIGTERM";
    case SIGINT: return "SIGINT";
    case SIGHUP: return "SIGHUP";
    case SIGKILL: return "SIGKILL";
    default: return "signal " + std::to_string(signal);
  }
}

namespace {
// A plain array, not a std::string: it is read by an exit handler, after static objects may have been
// destroyed.
char g_foreignNote[4096] = {0};
}  // namespace

void setForeignCodeNote(const std::string& note) {
  std::snprintf(g_foreignNote, sizeof g_foreignNote, "%s", note.c_str());
}
std::string foreignCodeNote() { return g_foreignNote; }

void runForeignCode(const std::string& who, const std::string& failure, const std::function<void()>& work) {
  try {
    work();
  } catch (const InputError& e) {
    throw InputError(who + ": " + e.what());
  } catch (const std::exception& e) {
    throw InputError(who + " " + failure + ": " + e.what());
  } catch (...) {
    throw InputError(who + " " + failure + ": it threw an exception that is not a std::exception");
  }
}

std::string nonStandardExceptionMessage() {
  std::string m = "an exception that is not a std::exception was thrown";
  if (g_foreignNote[0]) m += std::string(" (") + g_foreignNote + ")";
  return m;
}

namespace {
char g_statusFile[4096] = {0};
}  // namespace

void setStatusFile(const std::string& path) { std::snprintf(g_statusFile, sizeof g_statusFile, "%s", path.c_str()); }

bool rewriteInPlace(const fs::path& path, const std::string& text) noexcept {
  const int fd = ::open(path.c_str(), O_WRONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return false;
  const bool ok = pwrite(fd, text.data(), text.size(), 0) == static_cast<ssize_t>(text.size()) &&
                  ftruncate(fd, static_cast<off_t>(text.size())) == 0;
  return ::close(fd) == 0 && ok;
}

void recordFailureInStatus(const std::string& text) noexcept {
  if (!g_statusFile[0]) return;
  // The first line replaced; the lines after it (warnings, notes, provenance) kept.
  std::string rest;
  try {
    std::ifstream f(g_statusFile);
    std::string line;
    if (std::getline(f, line))
      while (std::getline(f, line)) rest += line + "\n";
  } catch (...) {
  }
  rewriteInPlace(g_statusFile, text + "\n" + rest);
}

namespace {
// BEAMCONTACT_INJECT_FAULT="place:rank" (tests only): an error at `place` on that rank alone.
const std::string& injectedFault() {
  static const std::string spec = [] {
    const char* v = std::getenv("BEAMCONTACT_INJECT_FAULT");
    return std::string(v ? v : "");
  }();
  return spec;
}
}  // namespace

bool faultInjection() { return !injectedFault().empty(); }

namespace {
int worldRank() {
  int rank = 0, initialized = 0;
  MPI_Initialized(&initialized);
  if (initialized) MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}
}  // namespace

bool faultAt(const char* place) {
  const std::string& spec = injectedFault();
  if (spec.empty()) return false;
  const auto colon = spec.find(':');
  if (spec.substr(0, colon) != place) return false;
  return colon == std::string::npos || std::atoi(spec.c_str() + colon + 1) == worldRank();
}

void injectFault(const char* place) {
  if (!faultAt(place)) return;
  throw std::runtime_error(std::string("injected fault at ") + place + " on rank " + std::to_string(worldRank()));
}

std::string oneLine(const std::exception& e) {
  if (isOutOfMemory(e)) return outOfMemoryText(e);
  const std::string what = e.what();
  return what.substr(0, what.find('\n'));
}

void collectively(const Comm& comm, const std::function<void()>& work) {
  // kind: 0 none, 1 input, 2 output, 3 interrupted, 4 other, 5 out of memory.
  int kind = 0, signal = 0;
  std::string message;
  try {
    work();
  } catch (const InputError& e) {
    kind = 1, message = e.what();
  } catch (const OutputError& e) {
    kind = 2, message = e.what();
  } catch (const Interrupted& e) {
    kind = 3, message = e.what(), signal = e.signal();
  } catch (const std::exception& e) {
    kind = isOutOfMemory(e) ? 5 : 4, message = isOutOfMemory(e) ? outOfMemoryText(e) : e.what();
  } catch (...) {
    kind = 4, message = nonStandardExceptionMessage();
  }
  const int size = comm.getSize();
  int first = kind ? comm.getRank() : size, failed = size;
  Teuchos::reduceAll(comm, Teuchos::REDUCE_MIN, first, Teuchos::outArg(failed));
  if (failed == size) return;
  int header[3] = {kind, signal, static_cast<int>(message.size())};
  Teuchos::broadcast(comm, failed, 3, header);
  std::vector<char> text(message.begin(), message.end());
  text.resize(header[2]);
  if (header[2] > 0) Teuchos::broadcast(comm, failed, header[2], text.data());
  const std::string agreed(text.begin(), text.end());
  switch (header[0]) {
    case 1: throw InputError(agreed);
    case 2: throw OutputError(agreed);
    case 3: throw Interrupted(header[1]);
    case 5: throw OutOfMemory(agreed);
    default: throw std::runtime_error(agreed);
  }
}

}  // namespace bc::core
