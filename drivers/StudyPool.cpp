#include "StudyPool.hpp"

#include <fcntl.h>
#include <malloc.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>

#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <map>
#include <stdexcept>

#include "core/Faults.hpp"

extern char** environ;

namespace bc::drivers::study {

namespace fs = std::filesystem;

std::vector<std::string> caseRunCommand(const std::string& program, const fs::path& dir,
                                        const std::vector<std::string>& plugins, bool overwrite) {
  std::vector<std::string> command = {program, "run", (dir / "deck.xml").string(), "--output", dir.string(), "--quiet"};
  if (overwrite) command.push_back("--overwrite");
  for (const auto& p : plugins) {
    command.push_back("--plugin");
    command.push_back(p);
  }
  return command;
}

int exitCodeOf(int status) {
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

pid_t spawnProgram(const std::vector<std::string>& command, const SpawnSetup& setup) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (!setup.log.empty()) {
    posix_spawn_file_actions_addopen(&actions, 1, setup.log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
  }
  for (const auto& [from, to] : setup.descriptors) posix_spawn_file_actions_adddup2(&actions, from, to);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  if (setup.ownGroup) {
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
    posix_spawnattr_setpgroup(&attributes, 0);
  }
  std::vector<std::string> args = command;
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, argv[0], &actions, &attributes, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  if (rc != 0) throw std::runtime_error("cannot start " + command[0] + ": " + std::strerror(rc));
  return pid;
}

namespace {

// A case's folder name in the cases folder ("007").
std::string folderName(const Case& c) { return c.dir.filename().string(); }

// --process-per-case: each case a `beamcontact run` process in a process group of its own (so that a
// Ctrl-C at the terminal reaches the study alone, which then stops its cases with one SIGTERM each:
// two signals would end a case at once), its stdout and stderr in the case's log.txt.
class ProcessPerCase : public CaseLauncher {
 public:
  ProcessPerCase(std::string program, std::vector<std::string> plugins, bool overwrite)
      : program_(std::move(program)), plugins_(std::move(plugins)), overwrite_(overwrite) {}

  void start(Case& c) override {
    SpawnSetup setup;
    setup.log = (c.dir / "log.txt").string();
    setup.ownGroup = true;
    running_[spawnProgram(caseRunCommand(program_, c.dir, plugins_, overwrite_), setup)] = &c;
    ++started_;
  }

  Ended wait() override {
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) return {};
      throw std::runtime_error("waiting for a case process failed: " + std::string(std::strerror(errno)));
    }
    const auto it = running_.find(pid);
    if (it == running_.end()) return {};
    Ended ended{it->second, exitCodeOf(status)};
    running_.erase(it);
    return ended;
  }

  std::size_t running() const override { return running_.size(); }
  void stopRunning() override {
    for (const auto& [pid, c] : running_) kill(pid, SIGTERM);
  }
  void finish() override {}
  int processesStarted() const override { return started_; }
  std::string how() const override { return "process per case"; }

 private:
  std::string program_;
  std::vector<std::string> plugins_;
  bool overwrite_;
  std::map<pid_t, Case*> running_;
  int started_ = 0;
};

// Why a worker's pipe could not be made (`error`: errno), with what to do when the study ran out of
// open files.
std::string pipeFailure(int error) {
  return "cannot make a pipe for a worker: " + std::string(std::strerror(error)) +
         (error == EMFILE ? " (each worker takes 4 of the study's open files: run fewer cases at once with "
                            "--parallel, or raise the limit, ulimit -n)"
                          : "");
}

// Moves descriptor `fd` to 10 or above, closed on exec (so that it is neither 3 nor 4, the numbers a
// worker's pipes take, nor inherited by another worker).
int highDescriptor(int fd) {
  const int high = fcntl(fd, F_DUPFD_CLOEXEC, 10);
  const int saved = errno;
  ::close(fd);
  if (high < 0) throw std::runtime_error(pipeFailure(saved));
  return high;
}

// Raises this process's limit of open files (its soft limit, up to the hard one) to `count` where it is
// lower: the pool holds two pipe ends per worker, and the usual soft limit, 1024, would stop a study
// at --parallel 240 or so ("Too many open files" names it when the hard limit is lower still).
void allowDescriptors(rlim_t count) {
  rlimit limit{};
  if (getrlimit(RLIMIT_NOFILE, &limit) != 0 || limit.rlim_cur >= count) return;
  limit.rlim_cur = limit.rlim_max == RLIM_INFINITY ? count : std::min(count, limit.rlim_max);
  setrlimit(RLIMIT_NOFILE, &limit);
}

// Writes all of `text` to `fd`; false when it cannot (EPIPE: the reader is gone).
bool writeAll(int fd, const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

// The default: a pool of at most `workers` worker processes, each in a process group of its own,
// started when a case needs one and none is idle.
class WorkerPool : public CaseLauncher {
 public:
  WorkerPool(std::string program, fs::path casesDir, std::vector<std::string> plugins, bool overwrite, int workers)
      : program_(std::move(program)),
        casesDir_(std::move(casesDir)),
        plugins_(std::move(plugins)),
        overwrite_(overwrite),
        workers_(workers) {
    allowDescriptors(4 * workers + 64);
  }

  // An exception leaves the workers: their requests' pipes closed, they end after their case.
  ~WorkerPool() override {
    for (auto& w : pool_) closeWorker(w);
  }

  void start(Case& c) override {
    Worker* w = nullptr;
    for (auto& candidate : pool_)
      if (!candidate.c) w = &candidate;
    // A worker that is idle takes the case; one that has ended meanwhile (its pipe is closed) is
    // waited for and replaced.
    if (w && !writeAll(w->requests, folderName(c) + "\n")) {
      endWorker(*w);
      w = nullptr;
    }
    if (!w) {
      if (static_cast<int>(pool_.size()) >= workers_)
        throw std::runtime_error("a case was started while every worker was busy");
      w = &startWorker(c);
      if (!writeAll(w->requests, folderName(c) + "\n"))
        throw std::runtime_error("cannot send case " + folderName(c) +
                                 " to the worker process just started: " + std::strerror(errno));
    }
    w->c = &c;
  }

  Ended wait() override {
    std::vector<pollfd> fds;
    for (const auto& w : pool_) fds.push_back({w.replies, POLLIN, 0});
    // A quarter second at most, so that a signal that came just before the wait is seen soon.
    const int ready = poll(fds.data(), fds.size(), 250);
    if (ready < 0) {
      if (errno == EINTR) return {};
      throw std::runtime_error("waiting for the workers failed: " + std::string(std::strerror(errno)));
    }
    for (std::size_t i = 0; i < fds.size(); ++i) {
      if (!fds[i].revents) continue;
      Worker& w = pool_[i];
      char buffer[4096];
      const ssize_t n = ::read(w.replies, buffer, sizeof buffer);
      if (n < 0 && errno == EINTR) return {};
      if (n > 0) {
        w.answer.append(buffer, static_cast<std::size_t>(n));
        const auto end = w.answer.find('\n');
        if (end == std::string::npos) return {};
        const std::string line = w.answer.substr(0, end);
        w.answer.erase(0, end + 1);
        return answered(w, line);
      }
      // The worker has ended (its answers' pipe closed): the case it held, if any, ended with it.
      Case* c = w.c;
      const int code = endWorker(w);
      if (c) return {c, code};
      return {};
    }
    return {};
  }

  std::size_t running() const override {
    std::size_t n = 0;
    for (const auto& w : pool_) n += w.c ? 1 : 0;
    return n;
  }

  void stopRunning() override {
    for (const auto& w : pool_)
      if (w.c) kill(w.pid, SIGTERM);
  }

  void finish() override {
    for (auto& w : pool_) closeWorker(w);
    for (auto& w : pool_) {
      int status = 0;
      while (waitpid(w.pid, &status, 0) < 0 && errno == EINTR) {
      }
    }
    pool_.clear();
  }

  int processesStarted() const override { return started_; }
  std::string how() const override { return "worker pool"; }

 private:
  struct Worker {
    pid_t pid = 0;
    int requests = -1, replies = -1;  // the study's ends of the worker's pipes
    Case* c = nullptr;  // the case it runs; null when idle
    std::string answer;  // what it has written of its answer so far
  };

  // Starts a worker for case `c`: its stdout and stderr at first in c's log.txt (as a case process's
  // would be), so that what starting MPI and Kokkos prints, or why the start failed, is in that log.
  Worker& startWorker(const Case& c) {
    int requests[2], replies[2];
    if (pipe(requests) != 0) throw std::runtime_error(pipeFailure(errno));
    if (pipe(replies) != 0) {
      const int why = errno;
      ::close(requests[0]);
      ::close(requests[1]);
      throw std::runtime_error(pipeFailure(why));
    }
    Worker w;
    const int theirRequests = highDescriptor(requests[0]), theirReplies = highDescriptor(replies[1]);
    w.requests = highDescriptor(requests[1]);
    w.replies = highDescriptor(replies[0]);
    std::vector<std::string> command = {program_, "study-worker", casesDir_.string()};
    if (overwrite_) command.push_back("--overwrite");
    for (const auto& p : plugins_) {
      command.push_back("--plugin");
      command.push_back(p);
    }
    SpawnSetup setup;
    setup.log = (c.dir / "log.txt").string();
    setup.ownGroup = true;
    setup.descriptors = {{theirRequests, 3}, {theirReplies, 4}};
    try {
      w.pid = spawnProgram(command, setup);
    } catch (...) {
      for (int fd : {theirRequests, theirReplies, w.requests, w.replies}) ::close(fd);
      throw;
    }
    ::close(theirRequests);
    ::close(theirReplies);
    ++started_;
    pool_.push_back(w);
    return pool_.back();
  }

  // A worker's answer for its case: "NNN CODE", or "NNN error MESSAGE" (the case could not be run).
  Ended answered(Worker& w, const std::string& line) {
    Case* c = w.c;
    const std::string name = c ? folderName(*c) : "";
    if (!c || line.compare(0, name.size() + 1, name + " ") != 0)
      throw std::runtime_error("a worker answered \"" + line + "\" while it was running " +
                               (c ? "case " + name : std::string("no case")));
    const std::string rest = line.substr(name.size() + 1);
    w.c = nullptr;
    if (rest.rfind("error ", 0) == 0) throw std::runtime_error(rest.substr(6));
    if (rest.empty() || rest.size() > 3 || rest.find_first_not_of("0123456789") != std::string::npos)
      throw std::runtime_error("a worker answered \"" + line + "\" for case " + name + " (expected its exit code)");
    return {c, std::stoi(rest)};
  }

  // Closes the study's ends of worker `w`'s pipes (it ends when it has read all its requests).
  static void closeWorker(Worker& w) {
    for (int* fd : {&w.requests, &w.replies})
      if (*fd >= 0) ::close(*fd), *fd = -1;
  }

  // Waits for worker `w`, which has ended or is ending, and takes it out of the pool; its exit code.
  int endWorker(Worker& w) {
    closeWorker(w);
    int status = 0;
    pid_t pid;
    while ((pid = waitpid(w.pid, &status, 0)) < 0 && errno == EINTR) {
    }
    const int code = pid == w.pid ? exitCodeOf(status) : 128;
    pool_.erase(pool_.begin() + (&w - pool_.data()));
    return code;
  }

  std::string program_;
  fs::path casesDir_;
  std::vector<std::string> plugins_;
  bool overwrite_;
  int workers_;
  std::vector<Worker> pool_;
  int started_ = 0;
};

}  // namespace

std::unique_ptr<CaseLauncher> processPerCase(const std::string& program, const std::vector<std::string>& plugins,
                                             bool overwrite) {
  return std::make_unique<ProcessPerCase>(program, plugins, overwrite);
}

std::unique_ptr<CaseLauncher> workerPool(const std::string& program, const fs::path& casesDir,
                                         const std::vector<std::string>& plugins, bool overwrite, int workers) {
  return std::make_unique<WorkerPool>(program, casesDir, plugins, overwrite, workers);
}

// ---- The worker's side ----

namespace {
constexpr int kRequests = 3, kReplies = 4;

bool isPipe(int fd) {
  struct stat s {};
  return fstat(fd, &s) == 0 && S_ISFIFO(s.st_mode);
}

// Points file descriptors 1 and 2 at `fd` (after writing out what stdout and stderr hold).
void redirectOutput(int fd) {
  std::cout.flush();
  std::cerr.flush();
  std::fflush(stdout);
  std::fflush(stderr);
  dup2(fd, 1);
  dup2(fd, 2);
}

// Whether file descriptor 1 is the file at `path` already (a worker's first case: the study opened
// its log for the worker's start).
bool outputIs(const fs::path& path) {
  struct stat out {
  }, file{};
  return fstat(1, &out) == 0 && ::stat(path.c_str(), &file) == 0 && out.st_dev == file.st_dev &&
         out.st_ino == file.st_ino;
}

// Before a case: the memory the last one freed goes back to the system (the program keeps freed memory,
// main's mallopt) and the process's high-water mark of resident memory is reset to what it holds now
// (Linux: /proc/self/clear_refs), so that a case's summary.csv peak_memory_mb (getrusage's maxrss) is
// this case's peak, not the largest of the worker's cases so far. Best effort: where the system does
// not allow the reset, the peak is the worker's.
void freshMemoryPeak() {
  malloc_trim(0);
  const int fd = ::open("/proc/self/clear_refs", O_WRONLY | O_CLOEXEC);
  if (fd < 0) return;
  if (::write(fd, "5", 1) != 1) {
  }
  ::close(fd);
}

// A request: a case folder's plain name (no path).
bool plainName(const std::string& name) {
  return !name.empty() && name != "." && name != ".." && name.find('/') == std::string::npos &&
         name.find('\0') == std::string::npos;
}
}  // namespace

void prepareWorker() {
  if (!isPipe(kRequests) || !isPipe(kReplies))
    throw std::runtime_error(
        "study-worker runs the cases of a study and is started by beamcontact study (its requests come on file "
        "descriptor 3, its answers go to 4, both pipes); run a deck with beamcontact run");
  fcntl(kRequests, F_SETFD, FD_CLOEXEC);
  fcntl(kReplies, F_SETFD, FD_CLOEXEC);
  // As for a process whose stdout is a file: what a case prints on stdout and on stderr lands in its
  // log in the same order.
  std::setvbuf(stdout, nullptr, _IOFBF, BUFSIZ);
}

int serveCases(const std::string& program, const fs::path& casesDir, const std::vector<std::string>& plugins,
               bool overwrite, const std::function<int(const std::vector<std::string>&)>& runCase) {
  std::FILE* requests = fdopen(kRequests, "r");
  if (!requests) return 3;
  const int nothing = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
  char* line = nullptr;
  std::size_t capacity = 0;
  ssize_t length;
  int code = 0;
  // (A signal does not end the wait for a request: the handlers restart the read.)
  while ((length = getline(&line, &capacity, requests)) >= 0) {
    std::string name(line, static_cast<std::size_t>(length));
    if (!name.empty() && name.back() == '\n') name.pop_back();
    // Stopped by a signal (the study's SIGTERM came after this case's request): no case is started.
    if (core::receivedSignal()) {
      code = 128 + core::receivedSignal();
      break;
    }
    std::string answer;
    if (!plainName(name)) {
      answer = name + " error a worker was asked for \"" + name + "\", which is not a case folder's name";
    } else {
      const fs::path dir = casesDir / name, log = dir / "log.txt";
      // The log as a case process's: created or emptied (a worker's first case: already so, and
      // holding what the worker's start printed).
      const int fd =
          outputIs(log) ? ::dup(1) : ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0644);
      if (fd < 0) {
        answer =
            name + " error cannot write the log of case " + name + " (" + log.string() + "): " + core::systemReason();
      } else {
        redirectOutput(fd);
        ::close(fd);
        freshMemoryPeak();
        const int result = runCase(caseRunCommand(program, dir, plugins, overwrite));
        // Nothing of a run's record is left for the next (the status file an exit() would write).
        core::setStatusFile("");
        redirectOutput(nothing >= 0 ? nothing : 2);
        answer = name + " " + std::to_string(result);
      }
    }
    if (!writeAll(kReplies, answer + "\n")) break;  // the study is gone
  }
  std::free(line);
  if (nothing >= 0) ::close(nothing);
  return code;
}

}  // namespace bc::drivers::study
