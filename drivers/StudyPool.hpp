// How a study's cases run (drivers/Study.hpp). Two ways, each behind a CaseLauncher:
//  - a pool of workers (the default): each worker is the beamcontact program started once as
//    `beamcontact study-worker CASES_DIR [--overwrite] [--plugin LIB]...`; it starts MPI and Kokkos
//    once, then runs case after case as `beamcontact run` would, so a case pays no start-up;
//  - a process per case (--process-per-case): each case is a `beamcontact run` process of its own.
// Either way a case's process runs in a process group of its own, its stdout and stderr go to the
// case's log.txt, and a case whose process dies (a crash, an abort, a signal, a call to exit()) is
// recorded with the exit code its process ended with while the study goes on: in the pool, a new
// worker takes the dead one's place when a case needs it.
//
// A worker's protocol: requests on file descriptor 3, one line each, the name of a case folder in
// CASES_DIR (e.g. "007"). For each the worker runs that folder's deck.xml exactly as
//   beamcontact run CASES_DIR/NNN/deck.xml --output CASES_DIR/NNN --quiet [--overwrite] [--plugin LIB]...
// would (caseRunCommand; the same command line in the run's provenance), with its stdout and stderr
// (file descriptors 1 and 2) in the folder's log.txt, and answers on file descriptor 4 with one line:
// "NNN CODE", CODE the exit code `beamcontact run` would have ended with; or "NNN error MESSAGE" when
// the case could not be run at all (its log cannot be written). Outside its cases the worker's stdout
// and stderr go to /dev/null (what starting MPI and Kokkos prints goes to its first case's log, as it
// would for a process of its own). It ends when the requests' pipe is closed, or, having received
// SIGTERM, SIGINT or SIGHUP, before the next case, with 128 + the signal (no answer: the study records
// that case as a process stopped by the signal).
#pragma once
#include <sys/types.h>

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "StudyDeck.hpp"

namespace bc::drivers::study {

// The command line of `beamcontact run` for the case in folder `dir` (program path first): its deck
// into that folder, quietly; what the per-process path starts and what a worker's run records.
std::vector<std::string> caseRunCommand(const std::string& program, const std::filesystem::path& dir,
                                        const std::vector<std::string>& plugins, bool overwrite);

// How spawnProgram starts a program: its stdout and stderr into the file `log` (created or emptied;
// empty: the study's own), the descriptors to hand over (each first one as the second's number), and
// whether in a process group of its own.
struct SpawnSetup {
  std::string log;
  std::vector<std::pair<int, int>> descriptors;
  bool ownGroup = false;
};
// Starts `command` (program path and arguments, no shell); throws std::runtime_error when it cannot.
pid_t spawnProgram(const std::vector<std::string>& command, const SpawnSetup& setup = {});
// The exit code of a finished process from waitpid's status: 128 + the signal when one ended it.
int exitCodeOf(int status);

// Starts a study's cases and tells when each ends.
class CaseLauncher {
 public:
  struct Ended {
    Case* c = nullptr;  // null: no case ended (a signal arrived, the wait timed out, or an idle worker ended)
    int exitCode = 0;  // the case's exit code as `beamcontact run`'s; 128 + N when signal N ended its process
  };
  virtual ~CaseLauncher() = default;
  // Starts case `c` (its folder and deck prepared); throws std::runtime_error when it cannot.
  virtual void start(Case& c) = 0;
  // Waits for a case to end (a signal interrupts the wait).
  virtual Ended wait() = 0;
  // Cases running now.
  virtual std::size_t running() const = 0;
  // SIGTERM to each running case's process (a run stops at its next Newton iteration, records itself
  // interrupted and ends with 143); nothing else is started after.
  virtual void stopRunning() = 0;
  // Ends what is left once no case runs (a pool's workers: their requests' pipe closed, each waited for).
  virtual void finish() = 0;
  // Processes started so far (workers, or case processes).
  virtual int processesStarted() const = 0;
  // How the cases run, for the study's messages and study.json: "worker pool" or "process per case".
  virtual std::string how() const = 0;
};

// Each case a `beamcontact run` process of its own (`program`: this program's path).
std::unique_ptr<CaseLauncher> processPerCase(const std::string& program, const std::vector<std::string>& plugins,
                                             bool overwrite);
// At most `workers` worker processes, started as cases need them, for the cases in `casesDir`.
std::unique_ptr<CaseLauncher> workerPool(const std::string& program, const std::filesystem::path& casesDir,
                                         const std::vector<std::string>& plugins, bool overwrite, int workers);

// The worker's side. Before MPI starts: checks that file descriptors 3 and 4 are the study's pipes
// (throws std::runtime_error naming the cause when not: the worker is started by a study, not by
// hand), keeps them from the processes a case may start, and makes stdout fully buffered, as it is
// for a process whose stdout is a file.
void prepareWorker();
// Serves the study's requests (the protocol above) until the requests' pipe closes: each case's run is
// `runCase(command)` with `command` from caseRunCommand(program, ...). Returns the worker's exit code.
int serveCases(const std::string& program, const std::filesystem::path& casesDir,
               const std::vector<std::string>& plugins, bool overwrite,
               const std::function<int(const std::vector<std::string>& command)>& runCase);

}  // namespace bc::drivers::study
