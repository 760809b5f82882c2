#include "Study.hpp"

#include <fcntl.h>

#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <map>
#include <thread>

#include "BuildInfo.hpp"
#include "StudyDeck.hpp"
#include "StudyPool.hpp"
#include "StudyReport.hpp"
#include "core/Faults.hpp"
#include "core/OutputDirectory.hpp"
#include "core/Provenance.hpp"
#include "core/Sha256.hpp"
#include "core/Parameters.hpp"

namespace bc::drivers {

namespace fs = std::filesystem;
using core::InputError;
using study::Case;
using study::StudyDeck;
using study::StudyResults;

namespace {

std::string selfExecutable() {
  std::error_code ec;
  const auto p = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error("cannot locate the beamcontact executable (/proc/self/exe): " + ec.message());
  return p.string();
}

// A case in a progress line: its group and values (up to about 70 characters).
std::string describe(const Case& c, const std::vector<std::string>& columns) {
  std::string s = c.group;
  for (const auto& name : columns) {
    const auto it = c.values.find(name);
    if (it != c.values.end() && s.size() < 70) s += " " + name + "=" + it->second;
  }
  return s;
}

}  // namespace

std::string scriptPath(const std::string& name) {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error("cannot locate the beamcontact executable (/proc/self/exe): " + ec.message());
  const fs::path script = exe.parent_path().parent_path() / "share" / "beamcontact" / name;
  if (!fs::is_regular_file(script, ec))
    throw std::runtime_error("the helper script " + script.string() +
                             " is missing (install or build BeamContact again)");
  return script.string();
}

std::string findDocumentation() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  std::vector<fs::path> candidates;
  if (!ec) candidates.push_back(exe.parent_path().parent_path() / "share" / "beamcontact" / "docs");
  candidates.push_back(BC_SOURCE_DOCS);
  candidates.push_back(BC_INSTALLED_DOCS);
  for (const auto& dir : candidates)
    if (fs::is_regular_file(dir / "input.md", ec)) return fs::canonical(dir, ec).string();
  return "docs";
}

int runProgram(const std::vector<std::string>& command) {
  const pid_t pid = study::spawnProgram(command);
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) throw std::runtime_error("waiting for " + command[0] + " failed");
  return study::exitCodeOf(status);
}

namespace {

// Plug-ins as absolute paths: the cases run in their own folders.
std::vector<std::string> absolutePlugins(const std::vector<std::string>& given) {
  std::vector<std::string> plugins;
  for (const auto& p : given) {
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) throw InputError("plug-in \"" + p + "\" does not exist (or is not a file)");
    plugins.push_back(fs::canonical(p).string());
  }
  return plugins;
}

// Each case is its own process; under mpirun every rank would run the whole study.
void refuseUnderMpirun() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    const char* size = std::getenv(var);
    if (size && std::atoi(size) > 1)
      throw InputError("run the study without mpirun: it starts each case as a process of its own");
  }
}

// The study directory (--output, else the deck's Output Directory), opened with its manifest and locked:
// one study at a time in a directory (flock on the manifest while this study runs; the lock goes with
// the process, however it ends). Its cases/ folder is made, and the temporary files an interrupted
// write left are removed.
core::OutputDirectory openStudyDirectory(const fs::path& dir, const StudyDeck& deck, const StudyOptions& options) {
  if (std::error_code ec; fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw InputError("the study directory \"" + dir.string() + "\" is a file, not a directory; give " +
                     (options.output.empty() ? "\"" + deck.root + "/Output Directory\"" : std::string("--output")) +
                     " a directory");
  core::OutputDirectory::Options where;
  where.overwrite = options.overwrite;
  where.pathFromDeck = options.output.empty();
  where.parameter = deck.root + "/Output Directory";
  where.what = "study directory";
  core::OutputDirectory out(dir, where);
  // A run's results (its status.txt would stay beside the study's, saying "complete").
  if (out.lists("status.txt") || out.lists("steps.csv"))
    throw InputError(
        "study directory \"" + dir.string() +
        "\" holds a run's results (status.txt, steps.csv): give the study a directory of its own " +
        (options.output.empty() ? "(\"" + deck.root + "/Output Directory\" or --output)" : std::string("(--output)")));
  {
    const int lock = ::open((dir / core::kManifestName).c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
    if (lock < 0 || flock(lock, LOCK_EX | LOCK_NB) != 0)
      throw InputError("study directory \"" + dir.string() +
                       "\" is in use by another beamcontact study; wait for it "
                       "or choose another --output");
  }
  out.folder("cases/");
  out.removeLeftovers();
  return out;
}

// Case directories beyond this study's `cases`, and the last report, are from an earlier study: only
// what the study's manifest names goes (a case folder with its own manifest: its listed files).
void removeEarlierStudy(core::OutputDirectory& out, const fs::path& dir, std::size_t cases) {
  for (const auto& entry : fs::directory_iterator(dir / "cases")) {
    const std::string n = entry.path().filename().string();
    const bool number = n.size() == 3 && n.find_first_not_of("0123456789") == std::string::npos;
    const std::string rel = "cases/" + n + "/";
    if ((!number || std::stoi(n) < 1 || std::stoi(n) > static_cast<int>(cases)) && out.lists(rel))
      out.removeOwnFolder(rel);
  }
  out.removeOwn([](const std::string& name) {
    const fs::path p(name);
    return name.find('/') == std::string::npos &&
           (p.extension() == ".png" || p.extension() == ".pdf" || name == "report.md");
  });
}

// Gives case `c` its folder in `dir`/cases and writes its deck there. A case whose folder holds the
// same deck (same parameters, same base deck) and a complete run of that deck (its status.txt names
// the deck's SHA-256: not a run of another deck into the folder) is kept from an earlier run of the
// study (returns true); any other case folder is cleared and prepared anew.
bool prepareCase(core::OutputDirectory& out, const fs::path& dir, const StudyDeck& deck, Case& c,
                 const StudyOptions& options) {
  char name[16];
  std::snprintf(name, sizeof name, "%03d", c.index);
  c.dir = dir / "cases" / name;
  const std::string xml = study::caseDeckXml(deck, c, options.timing != 0);
  if (!options.timing && study::readText(c.dir / "deck.xml") == xml &&
      study::runStatusLine(c.dir).rfind("complete", 0) == 0 &&
      core::field(core::readFieldLines(study::readText(c.dir / "status.txt")), "deck_sha256") == core::sha256Hex(xml)) {
    c.status = "complete";
    c.kept = true;
    c.exitCode = 0;
    return true;
  }
  const std::string rel = "cases/" + std::string(name) + "/";
  if (out.lists(rel)) out.removeOwnFolder(rel);
  out.folder(rel);  // a case folder that is a link is refused: nothing is written through it
  core::OutputDirectory::Options caseWhere;
  caseWhere.overwrite = options.overwrite;
  caseWhere.what = "case directory";
  core::OutputDirectory caseDir(c.dir, caseWhere);
  caseDir.removeLeftovers();
  caseDir.add("deck.xml");
  caseDir.add("log.txt");
  core::writeFileAtomically(c.dir / "deck.xml", xml);
  return false;
}

// Cases run at once: --parallel, else the deck's "Parallel Cases", else one per core; one with --timing,
// so that no case competes with another for the cores.
int parallelCases(const StudyDeck& deck, const StudyOptions& options) {
  int parallel = options.parallel > 0 ? options.parallel : deck.study->get<int>("Parallel Cases");
  if (parallel <= 0) parallel = std::max(1u, std::thread::hardware_concurrency());
  if (options.timing) parallel = 1;
  return parallel;
}

// The status of a case whose process `c.exitCode` ended, from the status.txt its run wrote: complete,
// interrupted (with the signal that stopped the study, `stopSignal`, or before it), or not (its cause).
void recordCaseStatus(Case& c, int stopSignal) {
  const std::string runStatus = study::runStatusLine(c.dir);
  // A run that recorded itself complete is complete, whatever ended its process afterwards (its
  // status is written last, after every other file).
  if (c.exitCode == 0 || runStatus.rfind("complete: ", 0) == 0) {
    c.status = "complete";
  } else if (runStatus.rfind("interrupted: ", 0) == 0 || (stopSignal && c.exitCode > 128)) {
    c.status = "interrupted";
    c.cause = runStatus.rfind("interrupted: ", 0) == 0 ? runStatus.substr(13)
                                                       : "stopped by " + core::signalName(c.exitCode - 128);
  } else {
    c.status = c.exitCode == 2 ? "incomplete" : c.exitCode == 1 ? "input error" : "failed";
    // The run's own record first (status.txt: "incomplete: <cause>"), else its one-line error.
    c.cause = runStatus.rfind("incomplete: ", 0) == 0 ? runStatus.substr(12)
                                                      : study::lastLine(c.dir / "log.txt", "beamcontact: ");
    if (c.cause.empty()) c.cause = "exit code " + std::to_string(c.exitCode);
  }
}

// Runs a study's cases, several at once (through `launcher`: a pool of workers or a process per case),
// recording each as it ends (the table is rewritten, atomically, after every finished case, so an
// interrupted study keeps it).
class CaseRunner {
 public:
  CaseRunner(std::vector<Case>& all, const StudyResults& results, const StudyOptions& options, int parallel,
             study::CaseLauncher& launcher)
      : all_(all), results_(results), options_(options), parallel_(parallel), launcher_(launcher) {}

  // Runs every case not kept (`kept` of them are); returns the signal that stopped the study, 0 when
  // none did. SIGTERM / SIGINT: the running cases get SIGTERM (each stops at its next Newton
  // iteration and records itself interrupted), are waited for and recorded; no new case starts.
  int run(int kept) {
    done_ = static_cast<std::size_t>(kept);
    t0_ = std::chrono::steady_clock::now();
    study::writeCaseTable(results_);
    while (done_ < all_.size() && !(stopSignal_ && launcher_.running() == 0)) {
      while (!stopSignal_ && next_ < all_.size() && static_cast<int>(launcher_.running()) < parallel_) {
        if (!all_[next_].kept) launcher_.start(all_[next_]);
        ++next_;
      }
      if (launcher_.running() == 0) break;
      const auto ended = launcher_.wait();
      if (!stopSignal_ && core::receivedSignal()) stopRunning();
      if (!ended.c) continue;
      Case& c = *ended.c;
      c.exitCode = ended.exitCode;
      if (options_.timing && c.exitCode == 0 && runAgainForTiming(c)) continue;
      ++done_;
      recordCaseStatus(c, stopSignal_);
      study::writeCaseTable(results_);
      printProgress(c);
    }
    launcher_.finish();
    return stopSignal_;
  }

 private:
  void stopRunning() {
    stopSignal_ = core::receivedSignal();
    std::printf("study %s: %s received; stopping the %zu running cases\n", results_.deck.stem.c_str(),
                core::signalName(stopSignal_).c_str(), launcher_.running());
    std::fflush(stdout);
    launcher_.stopRunning();
  }

  // Timing: a complete run adds its solve time; the case runs again until it has them all (true).
  bool runAgainForTiming(Case& c) {
    const auto summary = study::readSummary(c.dir);
    const auto seconds = summary.find("solve_seconds");
    if (seconds != summary.end()) c.timings.push_back(std::stod(seconds->second));
    if (static_cast<int>(c.timings.size()) < options_.timing && !stopSignal_ && !core::receivedSignal()) {
      launcher_.start(c);
      return true;
    }
    return false;
  }

  void printProgress(const Case& c) const {
    const int width = 30, filled = static_cast<int>(width * done_ / all_.size());
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    if (options_.quiet) return;
    std::printf("[%s%s] %3zu/%zu  %6.1f s  case %03d %-10s %s\n", std::string(filled, '#').c_str(),
                std::string(width - filled, '.').c_str(), done_, all_.size(), elapsed, c.index, c.status.c_str(),
                describe(c, results_.deck.columns).c_str());
    std::fflush(stdout);
  }

  std::vector<Case>& all_;
  const StudyResults& results_;
  const StudyOptions& options_;
  const int parallel_;
  study::CaseLauncher& launcher_;
  std::size_t next_ = 0, done_ = 0;
  int stopSignal_ = 0;
  std::chrono::steady_clock::time_point t0_;
};

void printStart(const StudyDeck& deck, std::size_t cases, const fs::path& dir, int parallel, int timing, int kept,
                const std::string& how) {
  std::printf("study %s: %zu cases from %s, %d at a time (%s), in %s", deck.stem.c_str(), cases,
              deck.base.string().c_str(), parallel, how.c_str(), dir.string().c_str());
  if (timing) std::printf(" (timing: each case %d times, VTK off)", timing);
  if (kept) std::printf(" (%d complete from an earlier run, kept)", kept);
  std::printf("\n");
  std::fflush(stdout);
}

// A study that `stopSignal` stopped: its table as it stands, and how to go on.
int reportStopped(const StudyResults& results, int stopSignal) {
  study::writeCaseTable(results);
  const auto& all = results.all;
  std::printf("study %s: stopped by %s; %zu of %zu cases complete; run the study again to run the others\n",
              results.deck.stem.c_str(), core::signalName(stopSignal).c_str(),
              static_cast<std::size_t>(
                  std::count_if(all.begin(), all.end(), [](const Case& c) { return c.status == "complete"; })),
              all.size());
  std::fprintf(stderr, "beamcontact: study interrupted by %s; run it again to run the cases not complete\n",
               core::signalName(stopSignal).c_str());
  return 128 + stopSignal;
}

// A study whose cases all ran: the table, study.json and (unless --no-report) the report. Exit code 2
// when a case did not complete; else 4 when the report could not be written (the cases and their
// table are complete: one line says so, or the report script's own line names a missing module).
// `report` is false with --no-report, `modules` false when the report's Python modules were found
// missing before the cases ran (the report is then not attempted: that line was the message).
// `launcher` ran the cases (how, and the processes it started, go to study.json and the closing line).
int reportFinished(const StudyResults& results, int parallel, const study::CaseLauncher& launcher, bool report,
                   bool modules, bool quiet) {
  study::writeCaseTable(results);
  study::writeStudyJson(results, parallel, launcher.how(), launcher.processesStarted());
  const auto& all = results.all;
  const auto failed = std::count_if(all.begin(), all.end(), [](const Case& c) { return c.status != "complete"; });
  const std::string table = (results.dir / "cases.csv").string();
  if (!quiet)
    std::printf("study %s: %zu cases, %td complete, %td not; %d processes started (%s); table %s\n",
                results.deck.stem.c_str(), all.size(), static_cast<std::ptrdiff_t>(all.size()) - failed, failed,
                launcher.processesStarted(), launcher.how().c_str(), table.c_str());
  std::fflush(stdout);
  const int reportCode = !report ? 0 : !modules ? 4 : study::writeReport(results, quiet);
  if (reportCode != 0 && reportCode != 4)
    std::fprintf(stderr, "beamcontact: study report not written: the report script %s failed (exit code %d)%s\n",
                 bc::drivers::scriptPath("study_report.py").c_str(), reportCode,
                 failed ? "" : "; every case is complete and in cases.csv");
  if (reportCode != 0 && !failed)
    std::printf("study %s: every case complete, the report not written; table %s\n", results.deck.stem.c_str(),
                table.c_str());
  if (failed)
    std::fprintf(stderr, "beamcontact: study incomplete: %td of %zu cases did not complete (their causes are in %s)\n",
                 static_cast<std::ptrdiff_t>(failed), all.size(), table.c_str());
  return failed ? 2 : reportCode != 0 ? 4 : 0;
}

}  // namespace

int runStudy(const std::string& studyFile, const StudyOptions& options) {
  const std::vector<std::string> plugins = absolutePlugins(options.plugins);
  refuseUnderMpirun();
  const StudyDeck deck = study::readStudyDeck(studyFile, options.plugins);
  // The cases the groups expand to (each with a step at At T), the study directory, and each case's
  // deck in its folder.
  std::vector<Case> all = study::expandCases(deck.groups);
  for (const Case& c : all) study::checkAtTIsAStep(deck, c);
  const fs::path dir =
      options.output.empty() ? fs::path(deck.study->get<std::string>("Output Directory")) : fs::path(options.output);
  core::OutputDirectory out = openStudyDirectory(dir, deck, options);
  const Case* reference = study::referenceCase(deck, all);
  removeEarlierStudy(out, dir, all.size());
  int kept = 0;
  for (Case& c : all) kept += prepareCase(out, dir, deck, c, options) ? 1 : 0;

  const StudyResults results{
      deck, all, reference, options.timing, dir, out, core::runProvenance(buildProvenance(), 1, options.command)};
  const int parallel = parallelCases(deck, options);
  // The cases run in a pool of `parallel` workers (each starts MPI and Kokkos once), or with
  // --process-per-case each as a process of its own.
  const std::string program = selfExecutable();
  const auto launcher = options.processPerCase
                            ? study::processPerCase(program, plugins, options.overwrite)
                            : study::workerPool(program, dir / "cases", plugins, options.overwrite, parallel);
  CaseRunner runner(all, results, options, parallel, *launcher);
  // A report that cannot be written is known before the cases run: the report script's one line (the
  // missing Python module, its Debian package and --no-report) comes first, not after the last case.
  const bool modules = !options.report || study::reportModulesPresent();
  if (!options.quiet)
    printStart(deck, all.size(), dir, parallel, options.timing, kept,
               options.processPerCase ? "a process per case" : "worker processes");
  core::installSignalHandlers(false);
  const int stopSignal = runner.run(kept);
  if (stopSignal) return reportStopped(results, stopSignal);
  return reportFinished(results, parallel, *launcher, options.report, modules, options.quiet);
}

}  // namespace bc::drivers
