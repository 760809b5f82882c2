#include "Faults.hpp"

#include <stdio_ext.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <vector>

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

void OutputFile::open(const fs::path& path, bool append) {
  if (file_) close();
  path_ = path.string();
  errno = 0;
  file_ = std::fopen(path_.c_str(), append ? "a" : "w");
  if (!file_) fail("open");
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
      f.open(tmp);
      f.write(text);
      f.close();
    } catch (const OutputError& e) {
      // Named by the file the caller asked for; the reason is the one the failed call gave.
      std::error_code ignored;
      fs::remove(tmp, ignored);
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

bool isOutOfMemory(const std::exception& e) {
  if (dynamic_cast<const std::bad_alloc*>(&e)) return true;
  const std::string what = e.what();
  return what.find("Kokkos failed to allocate memory") != std::string::npos ||
         what.find("likely due to insufficient memory") != std::string::npos;
}

std::string outOfMemoryText(const std::exception& e) {
  const std::string what = e.what();
  // A failed allocation of ours says what ran out (OutOfMemory, LinearSolverOutOfMemory).
  if (dynamic_cast<const std::bad_alloc*>(&e) && what != std::bad_alloc().what() && !what.empty() &&
      what.find('\n') == std::string::npos)
    return what.find("out of memory") != std::string::npos ? what : "out of memory: " + what;
  const std::string kLabel = "memory for label \"", kSize = "Allocation of size ";
  std::string detail;
  const auto size = what.find(kSize);
  if (size != std::string::npos) {
    const auto from = size + kSize.size(), to = what.find(" failed", from);
    if (to != std::string::npos && to - from < 40) detail = what.substr(from, to - from);
  }
  const auto label = what.find(kLabel);
  if (label != std::string::npos) {
    const auto from = label + kLabel.size(), to = what.find('"', from);
    if (to != std::string::npos && to - from < 200)
      detail = (detail.empty() ? "" : detail + " ") + "for \"" + what.substr(from, to - from) + "\"";
  }
  if (!detail.empty()) detail = "Kokkos could not allocate " + detail + "; ";
  return "out of memory (" + detail + "the model is too large for this machine's or this process's memory)";
}

void rethrowIfOutOfMemory(const std::exception& e) {
  if (isOutOfMemory(e)) throw OutOfMemory(outOfMemoryText(e));
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
