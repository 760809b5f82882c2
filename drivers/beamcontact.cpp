// beamcontact: command-line driver. Parses arguments, reads and validates the deck, runs it.
//   beamcontact run DECK.xml [-o DIR] [-q] [--overwrite] [--timers] [--restart DIR] [--plugin LIB]...
//   beamcontact check DECK.xml [--plugin LIB]...
//   beamcontact study STUDY.xml [-o DIR] [-q] [--parallel N] [--timing [N]] [--no-report] [--process-per-case]
//                     [--plugin LIB]...
//   (beamcontact study-worker CASES_DIR ...: a study's worker, started by the study; drivers/StudyPool.hpp)
//   beamcontact render RESULTS_DIR OUT.png [--stages T1,T2,...] [--view ELEV,AZIM] [--title TEXT]
//   beamcontact generate KIND [--OPTION VALUE]... [-o FILE]
//   beamcontact --print-valid-parameters [--format text|xml|yaml] [--plugin LIB]...
//   beamcontact --version (or version)
//   beamcontact --help, beamcontact COMMAND --help
// Each command's options are a table (CommandLine.hpp) that drives its parsing and its --help; the
// options are read before MPI and Kokkos start, so --help and usage errors come first and alone.
// Exit codes: 0 run complete; 1 usage or input error; 2 run incomplete (a step failed to converge, or
// a results file could not be written); 3 unexpected error; 4 a Python module render needs is missing,
// or a study's cases all completed but its report was not written (a missing module is named with its
// Debian package); 128 + N stopped by signal N (SIGTERM: 143, SIGINT: 130) after writing a checkpoint.
// Errors are one line on stderr naming the cause.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <malloc.h>
#include <string>
#include <utility>

#include <Teuchos_DefaultComm.hpp>
#include <Tpetra_Core.hpp>
#include <mpi.h>

#include "Study.hpp"
#include "StudyPool.hpp"
#include "constraints/ContactManager.hpp"
#include "constraints/EnforcerRegistry.hpp"
#include "input/Plugins.hpp"
#include "Generate.hpp"
#include "CommandLine.hpp"

#include "core/Faults.hpp"
#include "BuildInfo.hpp"
#include "core/OutputDirectory.hpp"
#include "core/Provenance.hpp"
#include "core/Simulation.hpp"
#include "input/Deck.hpp"
#include "input/Reference.hpp"

namespace {

const char* kUsage =
    "usage: beamcontact run DECK.xml [-o DIR] [-q] [--overwrite] [--timers] [--restart DIR] [--plugin LIB]...\n"
    "       beamcontact check DECK.xml [--plugin LIB]...\n"
    "       beamcontact study STUDY.xml [-o DIR] [-q] [--overwrite] [--parallel N] [--timing [N]] [--no-report] "
    "[--process-per-case] [--plugin LIB]...\n"
    "       beamcontact render RESULTS_DIR OUT.png [--stages T1,T2,...] [--view ELEV,AZIM] [--title TEXT]\n"
    "       beamcontact generate grid|weave|network|strand [--OPTION VALUE]... [-o FILE]\n"
    "       beamcontact --print-valid-parameters [--format text|xml|yaml] [--plugin LIB]...\n"
    "       beamcontact version (or --version)\n"
    "       beamcontact COMMAND --help (or -h): every option of COMMAND with its default and meaning\n"
    "\n"
    "Runs a BeamContact XML deck: geometrically nonlinear 3D beams, load factor T from 0 to 1.\n"
    "Options may come before or after the deck, as --option VALUE or --option=VALUE; -o is --output,\n"
    "-q is --quiet. A usage error is one line naming the problem and exit code 1.\n"
    "run: results (CSV, VTK, status, effective parameters, timers.txt) go to the deck's Output/Directory,\n"
    "by default results/<deck name>, or to DIR.\n"
    "check reads and validates a deck and checks the model (supports, duplicates) without running it.\n"
    "study runs every case of a study deck (a base deck and the parameters to vary) and writes cases.csv,\n"
    "report.md and plots (docs/studies.md).\n"
    "render draws a run's beams and contact forces at stages of loading into a PNG.\n"
    "generate writes a many-beam deck (grid, weave, network, strand; docs/input.md).\n"
    "--plugin LIB loads a shared library with strategies of its own (docs/contact.md); a deck's Plugins\n"
    "list only names what it needs: each must be given with --plugin too, since a plug-in runs code.\n"
    "study reports and render need Python 3 with matplotlib (Debian: python3-matplotlib), render also\n"
    "numpy and vtk (python3-numpy, python3-vtk9); a missing one is named (a study without it: --no-report).\n"
    "--version prints the version, git commit, build type, Trilinos, MPI library and compiler; every\n"
    "results directory records them with the date, host, ranks and command line (status.txt,\n"
    "summary.csv, effective_parameters.xml; a study's cases.csv, study.json and report.md).\n"
    "Exit codes: 0 complete, 1 usage or input error, 2 run incomplete or a results file could not be\n"
    "written (a study: some case did not complete; every case is recorded), 3 unexpected error,\n"
    "4 a Python module render needs is missing, or every case of a study is complete but its report\n"
    "was not written (a missing module is named with its Debian package), 128 + N stopped by signal N\n"
    "(status.txt says so).\n";

// The subcommands' options: each table drives both the parsing and the command's --help.
using bc::drivers::cli::Command;
using bc::drivers::cli::UsageError;

const bc::drivers::cli::Option kPlugin{
    "plugin", 0, "LIB", "none", "load a shared library of strategies (a deck's Plugins must be named here too)", true};

const Command& runSpec() {
  static const Command c{
      "run",
      "Runs a BeamContact XML deck: geometrically nonlinear 3D beams, load factor T from 0 to 1. Results\n"
      "(steps.csv, tracked_points.csv, VTK, status.txt, summary.csv, effective_parameters.xml, timers.txt)\n"
      "go to the results directory. One line per converged step shows T, Newton iterations, the step's\n"
      "time and the estimated time left; a complete run ends with its tracked points at T = 1.",
      {{"DECK.xml", "the deck (docs/input.md; beamcontact --print-valid-parameters lists every parameter)"}},
      {{"output", 'o', "DIR", "the deck's Output/Directory, else results/<deck name>",
        "results directory (any directory; a deck's own paths are relative, without \"..\" and links)"},
       {"overwrite", 0, "", "",
        "write into a directory that holds files beamcontact did not write (beside them; only its own "
        "files are replaced)"},
       {"quiet", 'q', "", "",
        "print nothing but errors and warnings (no header, no step, cut or Newton iteration lines, no results)"},
       {"timers", 0, "", "", "print the timer table at the end (it is always written to timers.txt)"},
       {"restart", 0, "DIR", "none: start at T = 0",
        "continue the run whose results are in DIR from its checkpoint.txt (written every Output/Checkpoint "
        "Every steps and when SIGTERM or SIGINT stops a run); the deck must be the same outside Output"},
       kPlugin},
      "Exit codes: 0 complete, 1 usage or input error, 2 incomplete (a step did not converge, or a results\n"
      "file could not be written), 3 unexpected error, 128 + N stopped by signal N after a checkpoint."};
  return c;
}

const Command& checkSpec() {
  static const Command c{"check",
                         "Reads and validates a deck and builds its model (supports, duplicates, contact points at "
                         "the\n"
                         "start) without running it; prints one line of counts. Exit code 0 when the deck is valid, 1 "
                         "if not.",
                         {{"DECK.xml", "the deck"}},
                         {kPlugin}};
  return c;
}

const Command& studySpec() {
  static const Command c{
      "study",
      "Runs every case of a study deck (a base deck and the parameters to vary, docs/studies.md), N at a\n"
      "time, and writes cases.csv, study.json, report.md and plots. The cases run in N worker processes,\n"
      "each started once and running case after case as beamcontact run would (no start-up per case); a\n"
      "case whose worker dies (a crash, an abort, a signal) is recorded with its cause, a new worker takes\n"
      "over and the others go on. Run it without mpirun. Exit codes: 0 every case complete, 1 usage or\n"
      "input error, 2 some case did not complete, 4 every case complete but the report not written.",
      {{"STUDY.xml", "the study deck"}},
      {{"output", 'o', "DIR", "results/<study name>", "study directory"},
       {"overwrite", 0, "", "", "write beside files beamcontact did not write (passed on to every case)"},
       {"parallel", 0, "N", "the deck's Parallel Cases, else one per core", "cases run at once (1 to 1024)"},
       {"timing", 0, "N", "off; N = 5 when given without N",
        "fair timing: one case at a time without VTK output, each run N times (1 to 100); solve_seconds "
        "is the median, with its spread",
        false, true, "5"},
       {"no-report", 0, "", "", "write cases.csv and study.json only (no report.md, no plots: no matplotlib needed)"},
       {"process-per-case", 0, "", "off: a pool of N worker processes",
        "run each case as a beamcontact run process of its own (each pays the program's start-up; nothing "
        "that one case or a plug-in leaves in a process reaches the next)"},
       {"quiet", 'q', "", "",
        "print nothing but errors and warnings (no start line, no line per case, no closing lines) when every "
        "case completes"},
       kPlugin}};
  return c;
}

const Command& renderSpec() {
  static const Command c{"render",
                         "Draws a run's beams and contact forces at stages of loading into a PNG, from the run's VTK "
                         "files\n"
                         "(needs python3-matplotlib, python3-numpy, python3-vtk9 or python3-paraview). Exit code 4 "
                         "when a module is missing.",
                         {{"RESULTS_DIR", "a run's results directory"}, {"OUT.png", "the picture to write"}},
                         {{"stages", 0, "T1,T2,...", "0.25,0.5,0.75,1",
                           "load factors to draw, one panel each (1 x N up to 3, then about square), 200 dpi"},
                          {"view", 0, "ELEV,AZIM", "22,-60", "camera elevation and azimuth [degrees]"},
                          {"title", 0, "TEXT", "the deck's file name", "title above the panels"}}};
  return c;
}

const Command& versionSpec() {
  static const Command c{
      "version", "Prints the version, git commit, build type, Trilinos, MPI library and compiler.", {}, {}};
  return c;
}

const Command& parametersSpec() {
  static const Command c{"--print-valid-parameters",
                         "Prints every deck parameter with its type, its default (or, for a required or optional "
                         "value, a valid\n"
                         "example) and its meaning, with the plug-ins' strategies; values as a deck writes them.",
                         {},
                         {{"format", 0, "FORMAT", "text",
                           "text (for people); xml (the deck format, with use=\"default|required|optional\" and "
                           "docString) or "
                           "yaml (lists of name, type, use, value, doc), for editors and scripts"},
                          kPlugin}};
  return c;
}

// Reads `args` (from the command's name on) by `spec`; an empty optional when --help was printed.
bool parseOrHelp(const Command& spec, const std::vector<std::string>& args, bc::drivers::cli::Parsed& parsed) {
  parsed = bc::drivers::cli::parse(spec, std::vector<std::string>(args.begin() + 1, args.end()));
  if (parsed.help) std::fputs(bc::drivers::cli::help(spec).c_str(), stdout);
  return !parsed.help;
}

// Before MPI starts, whether this process is rank 0 (or not under mpirun): it prints the usage errors.
bool firstRankByEnvironment() {
  for (const char* var : {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"}) {
    const char* rank = std::getenv(var);
    if (rank && std::atoi(rank) != 0) return false;
  }
  return true;
}

// A process that no launcher started (no mpirun: none of its variables) is an MPI singleton. Open MPI
// then forks its daemon (orted) before MPI_Init returns, to be ready for MPI_Comm_spawn, which a run never
// calls: that fork and the daemon's start took 0.3 s of Example 1's 0.45 s. ess_singleton_isolated
// starts the singleton without it (docs/scale.md, "Start-up"). A value the user set is left alone, and
// under a launcher nothing is set.
void singletonWithoutDaemon() {
#ifdef OPEN_MPI
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK", "PMI_FD"})
    if (std::getenv(var)) return;
  ::setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);  // (0: a value the user set stays)
#endif
}

// The command line as typed (before MPI and Kokkos take their own arguments out), for the provenance.
std::string g_commandLine;
// The program as it was started (argv[0]): a study's worker records its cases' command lines with it.
std::string g_program;

// beamcontact --version: the version and how this program was built.
int versionCommand() {
  const auto fields = bc::drivers::buildProvenance();
  std::printf("beamcontact %s\n", bc::core::field(fields, "version").c_str());
  for (const auto& [key, value] : fields)
    if (key != "version") std::printf("%s: %s\n", key.c_str(), value.c_str());
  return 0;
}

// Runs `body` and maps its errors to the exit codes above, each as one line on stderr (printed when
// `print`: on rank 0 under MPI).
int withExitCodes(bool print, const std::function<int()>& body) {
  try {
    return body();
  } catch (const UsageError& e) {
    if (print)
      std::fprintf(stderr, "beamcontact: %s: %s (see beamcontact %s --help)\n", e.command.c_str(), e.what(),
                   e.command.c_str());
    return 1;
  } catch (const bc::core::InputError& e) {
    if (print) std::fprintf(stderr, "beamcontact: input error: %s\n", e.what());
    return 1;
  } catch (const bc::core::OutputError& e) {
    if (print) std::fprintf(stderr, "beamcontact: output error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    // A failed allocation (std::bad_alloc, or Kokkos' report of one over several lines) in one line.
    if (print)
      std::fprintf(stderr, "beamcontact: error: %s\n",
                   bc::core::isOutOfMemory(e) ? bc::core::outOfMemoryText(e).c_str() : e.what());
    return 3;
  } catch (...) {
    if (print) std::fprintf(stderr, "beamcontact: error: %s\n", bc::core::nonStandardExceptionMessage().c_str());
    return 3;
  }
}

// Code besides ours (a plug-in) that calls exit() in the middle of a run would end it with that code and
// nothing recorded: while `g_working` is set, such an exit becomes exit code 3 with one line.
volatile bool g_working = false;
extern "C" void onExitDuringWork() {
  if (!g_working) return;
  const std::string note = bc::core::foreignCodeNote();
  bc::core::recordFailureInStatus("failed: the process was ended by a call to exit() in the middle of the run" +
                                  (note.empty() ? std::string() : " (" + note + ")"));
  std::fprintf(stderr, "beamcontact: error: the process was ended by a call to exit() in the middle of the work%s\n",
               note.empty() ? "" : (" (" + note + ")").c_str());
  std::fflush(stderr);
  std::_Exit(3);
}
// Registered after MPI and Kokkos are initialized too, so it runs before their own exit handlers.
void guardExit() { std::atexit(onExitDuringWork); }
struct Working {
  Working() { g_working = true; }
  ~Working() { g_working = false; }
};

// beamcontact study STUDY.xml [options]: the options, then the study.
int studyCommand(const std::vector<std::string>& args) {
  bc::drivers::cli::Parsed p;
  if (!parseOrHelp(studySpec(), args, p)) return 0;
  bc::drivers::StudyOptions options;
  options.plugins = p.all("plugin");
  options.command = g_commandLine;
  options.output = p.get("output");
  options.report = !p.has("no-report");
  options.overwrite = p.has("overwrite");
  options.quiet = p.has("quiet");
  options.processPerCase = p.has("process-per-case");
  if (p.has("parallel")) {
    const std::string v = p.get("parallel");
    options.parallel = -1;
    if (!v.empty() && v.size() <= 4 && v.find_first_not_of("0123456789") == std::string::npos)
      options.parallel = std::stoi(v);
    if (options.parallel < 1 || options.parallel > 1024)
      throw UsageError("study", "--parallel takes a whole number from 1 to 1024, got \"" + v + "\"");
  }
  if (p.has("timing")) {
    const std::string v = p.get("timing");
    const bool whole = !v.empty() && v.size() <= 3 && v.find_first_not_of("0123456789") == std::string::npos;
    options.timing = whole ? std::stoi(v) : 0;
    if (options.timing < 1 || options.timing > 100)
      throw UsageError("study", "--timing takes a whole number of runs from 1 to 100, got \"" + v + "\"");
  }
  return withExitCodes(true, [&] { return bc::drivers::runStudy(p.positionals[0], options); });
}

// A tracked point's published values (Output/Tracked Points/NAME/Reference ux, uy, uz) beside the
// run's `u` at T = 1: "SOURCE: ux X (diff +Y %), ...", Y = 100 (run - X) / X (+: the run's value is
// larger in magnitude); empty when the deck gives none.
template <class U> std::string referenceLine(const bc::input::Problem& problem, const std::string& point, const U& u) {
  const Teuchos::ParameterList& all = problem.effective.sublist("Output").sublist("Tracked Points");
  if (!all.isSublist(point)) return "";
  const Teuchos::ParameterList& p = all.sublist(point);
  std::string line;
  const char* names[] = {"ux", "uy", "uz"};
  for (int k = 0; k < 3; ++k) {
    const std::string key = std::string("Reference ") + names[k];
    if (!p.isParameter(key)) continue;
    const double reference = p.get<double>(key);
    char text[128];
    if (reference != 0.0)
      std::snprintf(text, sizeof text, "%s %.6g (diff %+.2f %%)", names[k], reference,
                    100.0 * (u[k] - reference) / reference);
    else std::snprintf(text, sizeof text, "%s 0 (diff %+.3g)", names[k], u[k]);
    line += (line.empty() ? "" : ", ") + std::string(text);
  }
  if (line.empty()) return "";
  return (p.isParameter("Reference Source") ? p.get<std::string>("Reference Source") : std::string("reference")) +
         ": " + line;
}

// The closing lines of a run (on rank 0): complete (unless `quiet`) with the tracked points at T = 1,
// interrupted (how to continue), or incomplete, and the run's warnings.
void printRunResult(const bc::core::RunResult& result, const bc::input::Problem& problem, const std::string& deck,
                    bool quiet) {
  const std::string& directory = problem.outputDirectory;
  if (result.restartedAtStep >= 0 && !quiet)
    std::printf("restarted after step %d from %s/checkpoint.txt\n", result.restartedAtStep, directory.c_str());
  if (result.report.completed && !quiet) {
    // At most kShown points, one line each (the rest are in tracked_points.csv).
    constexpr std::size_t kShown = 8;
    const auto& tracked = problem.model.tracked;
    for (std::size_t i = 0; i < tracked.size() && i < kShown; ++i) {
      const auto u = result.finalState.displacement(tracked[i].node);
      std::printf("at T = 1: %s: u = (%.6g, %.6g, %.6g)\n", tracked[i].name.c_str(), u[0], u[1], u[2]);
      const std::string published = referenceLine(problem, tracked[i].name, u);
      if (!published.empty()) std::printf("at T = 1: %s: %s\n", tracked[i].name.c_str(), published.c_str());
    }
    if (tracked.size() > kShown)
      std::printf("at T = 1: %zu more tracked points in tracked_points.csv\n", tracked.size() - kShown);
    std::printf("complete: %d steps, %d Newton iterations, solve %.3f s; results in %s\n", result.report.steps,
                result.report.newtonIterations, result.solveSeconds, directory.c_str());
  } else if (result.report.interrupted) {
    std::fprintf(stderr, "beamcontact: interrupted by %s at T = %g; continue with: beamcontact run %s --restart %s\n",
                 bc::core::signalName(result.report.interrupted).c_str(), result.report.lastT, deck.c_str(),
                 directory.c_str());
  } else if (!result.report.completed) {
    std::fprintf(stderr, "beamcontact: run incomplete: stopped at T = %g: %s (converged steps are in %s)\n",
                 result.report.lastT, result.report.failure.c_str(), directory.c_str());
  }
  for (const auto& w : result.report.warnings) std::fprintf(stderr, "beamcontact: warning: %s\n", w.c_str());
}

// What `beamcontact run` was asked (its options read before MPI starts).
struct RunRequest {
  std::string deck, output, restart;
  bool quiet = false, overwrite = false, timers = false;
  std::vector<std::string> plugins;
  std::string commandLine;  // for the run's provenance: as typed, or a study's command for the case
};

int runDeck(const RunRequest& request) {
  const std::string& deck = request.deck;
  auto comm = Tpetra::getDefaultComm();
  const bool root = comm->getRank() == 0;
  const std::string stem = std::filesystem::path(deck).stem().string();
  // Every rank reads the deck and builds the model (the strategy's constructor included); an error on
  // any rank ends every rank with the first failing rank's message.
  Teuchos::ParameterList list;
  bc::input::Problem problem;
  std::string deckDigest;
  bc::core::collectively(*comm, [&] {
    bc::core::injectFault("deck");
    list = bc::input::readDeckFile(deck, &deckDigest);
    // The deck's Plugins (and digests) against --plugin before any library is loaded.
    bc::input::checkDeckPlugins(list, deck, request.plugins);
  });
  // Loaded on every rank; a library that fails on one rank only ends every rank with its message.
  bc::core::collectively(*comm, [&] {
    bc::core::injectFault("plugin");
    for (const auto& plugin : request.plugins) bc::input::loadPlugin(plugin);
  });
  bc::core::collectively(*comm, [&] {
    bc::core::injectFault("strategy");
    // (The list handed over, not copied: a deck's lists take about 4 bytes per deck byte.)
    problem = bc::input::buildProblem(std::exchange(list, Teuchos::ParameterList()), stem);
  });
  if (!request.restart.empty()) problem.outputDirectory = request.restart;
  else if (!request.output.empty()) problem.outputDirectory = request.output;
  bc::core::RunOptions options;
  options.outputDirectory = problem.outputDirectory;
  options.outputFromDeck = request.restart.empty() && request.output.empty();
  options.overwrite = request.overwrite;
  for (const auto& p : bc::input::loadedPlugins())
    options.statusNotes.push_back("plug-in: " + p.path + " sha256 " + p.sha256);
  options.provenance = bc::core::runProvenance(bc::drivers::buildProvenance(), comm->getSize(), request.commandLine);
  options.provenance.emplace_back("deck_sha256", deckDigest);  // a study keeps a case only if it ran the case's deck
  options.writeVtk = problem.writeVtk;
  options.progress = !request.quiet;
  options.printTimers = request.timers;
  options.vtkEvery = problem.vtkEvery;
  options.vtkAt = problem.vtkAt;
  options.vtkCompression = problem.vtkCompression;
  options.effective = &problem.effective;
  options.contactPoints = problem.contact ? static_cast<long long>(problem.contact->points().size()) : 0;
  if (problem.contact)
    options.contactPointsNow = [contact = problem.contact] { return static_cast<long long>(contact->points().size()); };
  options.checkpointEvery = problem.checkpointEvery;
  options.restart = !request.restart.empty();
  options.fingerprint = bc::input::deckFingerprint(problem);
  if (request.quiet) {
    // Neither the Newton iterations (the deck's Print Iterations) nor the step cuts.
    problem.solver.printIterations = false;
    problem.solver.printCuts = false;
  }
  if (root && !request.quiet)
    std::printf("BeamContact: %s, %d nodes, %zu elements, %d ranks\n", deck.c_str(), problem.model.initial.numNodes(),
                problem.beams->elements().size(), comm->getSize());
  const auto result = bc::core::simulate(problem.model, problem.solver, problem.linearSolver, options, comm);
  if (root) printRunResult(result, problem, deck, request.quiet);
  if (result.report.interrupted) return 128 + result.report.interrupted;
  return result.report.completed ? 0 : 2;
}

// beamcontact render RESULTS_DIR OUT.png [options]: the render script draws it.
int renderCommand(const std::vector<std::string>& args) {
  bc::drivers::cli::Parsed p;
  if (!parseOrHelp(renderSpec(), args, p)) return 0;
  if (!std::filesystem::is_directory(p.positionals[0])) {
    std::fprintf(stderr, "beamcontact: render: \"%s\" is not a results directory\n", p.positionals[0].c_str());
    return 1;
  }
  std::vector<std::string> command = {"/usr/bin/python3", bc::drivers::scriptPath("render_stages.py"), "--",
                                      p.positionals[0], p.positionals[1]};
  // Options as --name=value, so that a value starting with "-" (a view's azimuth) stays a value.
  for (const char* name : {"stages", "view", "title"})
    if (p.has(name)) command.insert(command.begin() + 2, std::string("--") + name + "=" + p.get(name));
  // The script exits 1 (2 from its argument parser) on a usage error, 4 when a Python module is missing
  // (one line naming its Debian package), 3 otherwise.
  const int code = bc::drivers::runProgram(command);
  return code == 0 ? 0 : (code == 1 || code == 2) ? 1 : code == 4 ? 4 : 3;
}

// beamcontact check DECK.xml: reads the deck and builds the model without running it.
int checkCommand(const std::vector<std::string>& args) {
  bc::drivers::cli::Parsed p;
  if (!parseOrHelp(checkSpec(), args, p)) return 0;
  const std::string deck = p.positionals[0];
  const auto plugins = p.all("plugin");
  return withExitCodes(true, [&] {
    const Working working;
    bc::constraints::registerBuiltinEnforcers();
    Teuchos::ParameterList list = bc::input::readDeckFile(deck);
    bc::input::checkDeckPlugins(list, deck, plugins);  // before any library is loaded
    for (const auto& plugin : plugins) bc::input::loadPlugin(plugin);
    const auto problem = bc::input::buildProblem(std::exchange(list, Teuchos::ParameterList()),
                                                 std::filesystem::path(deck).stem().string());
    // The deck's own output path as run takes it (relative, no "..", no links); --output replaces it.
    bc::core::checkDeckOutputPath(problem.outputDirectory, "Output/Directory");
    std::printf("ok: %s: %d nodes, %zu elements, %d joints, %zu supports, %zu loads, %zu contact points at the start\n",
                deck.c_str(), problem.model.initial.numNodes(), problem.beams->elements().size(), problem.joints,
                problem.model.supports.size(), problem.model.loads.size(),
                problem.contact ? problem.contact->points().size() : std::size_t(0));
    return 0;
  });
}

// beamcontact --print-valid-parameters: the deck reference, with the plug-ins' strategies (printed on rank 0).
int printValidParameters(const bc::core::Comm& comm, const std::vector<std::string>& plugins,
                         bc::input::ReferenceFormat format, bool root) {
  bc::core::collectively(comm, [&] {
    for (const auto& plugin : plugins) bc::input::loadPlugin(plugin);
  });
  if (root) bc::input::writeReference(bc::input::referenceParameters(), format, std::cout);
  return 0;
}

// --format of --print-valid-parameters; throws UsageError.
bc::input::ReferenceFormat referenceFormat(const std::string& name) {
  if (name == "text") return bc::input::ReferenceFormat::Text;
  if (name == "xml") return bc::input::ReferenceFormat::Xml;
  if (name == "yaml") return bc::input::ReferenceFormat::Yaml;
  throw UsageError("--print-valid-parameters", "--format takes text, xml or yaml, got \"" + name + "\"");
}

// beamcontact run DECK.xml [options]: the options, checked before MPI starts (false: --help printed).
bool readRunRequest(const std::vector<std::string>& args, RunRequest& request) {
  bc::drivers::cli::Parsed p;
  if (!parseOrHelp(runSpec(), args, p)) return false;
  request.deck = p.positionals[0];
  request.output = p.get("output");
  request.restart = p.get("restart");
  request.quiet = p.has("quiet");
  request.overwrite = p.has("overwrite");
  request.timers = p.has("timers");
  request.plugins = p.all("plugin");
  request.commandLine = g_commandLine;
  if (p.has("output") && request.output.find_first_not_of(' ') == std::string::npos)
    throw UsageError("run", "--output names no directory");
  if (p.has("restart") && request.restart.find_first_not_of(' ') == std::string::npos)
    throw UsageError("run", "--restart names no directory");
  if (!request.restart.empty() && !request.output.empty() &&
      std::filesystem::path(request.restart).lexically_normal() !=
          std::filesystem::path(request.output).lexically_normal())
    throw UsageError("run", "--restart continues in its own directory; leave out --output");
  return true;
}

// One run of a deck, its errors mapped to the exit codes (MPI and Kokkos initialized): what
// `beamcontact run` does, and what a study's worker does for each case.
int runWithExitCodes(const RunRequest& request) {
  const bool root = Tpetra::getDefaultComm()->getRank() == 0;
  return withExitCodes(root, [&] {
    const Working working;
    return runDeck(request);
  });
}

// Starts MPI (a singleton without the daemon when no launcher started this process) and Kokkos, then
// the signal handlers and the built-in strategies, and runs `body`; MPI and Kokkos end with it.
int underMpi(int& argc, char**& argv, const std::function<int()>& body) {
  singletonWithoutDaemon();
  Tpetra::ScopeGuard scope(&argc, &argv);
  guardExit();
  bc::core::installSignalHandlers();
  bc::constraints::registerBuiltinEnforcers();
  return body();
}

// The commands that run under MPI (run, --print-valid-parameters), their options read before.
int mpiCommand(int& argc, char**& argv, const RunRequest* run, const std::vector<std::string>& plugins,
               bc::input::ReferenceFormat format = bc::input::ReferenceFormat::Text) {
  return underMpi(argc, argv, [&] {
    if (run) return runWithExitCodes(*run);
    const auto comm = Tpetra::getDefaultComm();
    const bool root = comm->getRank() == 0;
    return withExitCodes(root, [&] { return printValidParameters(*comm, plugins, format, root); });
  });
}

// beamcontact study-worker CASES_DIR [--overwrite] [--plugin LIB]...: a study's worker (not for use by
// hand; drivers/StudyPool.hpp has its protocol). Its cases' command lines are parsed as `run`'s, and
// each case runs as `beamcontact run` would run it.
const Command& studyWorkerSpec() {
  static const Command c{"study-worker",
                         "Runs the cases a study sends it (beamcontact study starts it, with its pipes on file "
                         "descriptors 3 and 4).",
                         {{"CASES_DIR", "the study's cases folder"}},
                         {{"overwrite", 0, "", "", "passed on to every case"}, kPlugin}};
  return c;
}

int studyWorkerCommand(int& argc, char**& argv, const std::vector<std::string>& args) {
  bc::drivers::cli::Parsed p;
  if (!parseOrHelp(studyWorkerSpec(), args, p)) return 0;
  try {
    bc::drivers::study::prepareWorker();  // before MPI starts
  } catch (const std::exception& e) {
    std::fprintf(stderr, "beamcontact: %s\n", e.what());
    return 1;
  }
  return underMpi(argc, argv, [&] {
    return bc::drivers::study::serveCases(
        g_program, p.positionals[0], p.all("plugin"), p.has("overwrite"), [](const std::vector<std::string>& command) {
          // The same reading of the command line as `beamcontact run`'s, and its command line recorded.
          RunRequest request;
          try {
            readRunRequest(std::vector<std::string>(command.begin() + 1, command.end()), request);
          } catch (const UsageError& e) {
            std::fprintf(stderr, "beamcontact: run: %s (see beamcontact run --help)\n", e.what());
            return 1;
          }
          std::vector<const char*> argv;
          for (const auto& a : command) argv.push_back(a.c_str());
          request.commandLine = bc::core::commandLine(static_cast<int>(argv.size()), argv.data());
          return runWithExitCodes(request);
        });
  });
}

// The command `args[0]` with its arguments; throws UsageError.
int command(int& argc, char**& argv, const std::vector<std::string>& args) {
  const std::string& name = args[0];
  bc::drivers::cli::Parsed p;
  if (name == "version" || name == "--version") return parseOrHelp(versionSpec(), args, p) ? versionCommand() : 0;
  if (name == "render") return renderCommand(args);
  // A study only starts and watches case processes (workers): no MPI in this process.
  if (name == "study") return studyCommand(args);
  if (name == "study-worker") return studyWorkerCommand(argc, argv, args);
  // generate writes a deck from a few parameters: no MPI in this process.
  if (name == "generate") return withExitCodes(true, [&] { return bc::drivers::generateDeck(args); });
  // check builds the model only: no MPI in this process (so it is quick to call many times).
  if (name == "check") return checkCommand(args);
  if (name == "--print-valid-parameters") {
    if (!parseOrHelp(parametersSpec(), args, p)) return 0;
    const auto format = referenceFormat(p.get("format", "text"));
    return mpiCommand(argc, argv, nullptr, p.all("plugin"), format);
  }
  if (name == "run") {
    RunRequest request;
    // --help is printed here, before MPI and Kokkos start (Kokkos would print its own).
    if (!readRunRequest(args, request)) return 0;
    return mpiCommand(argc, argv, &request, {});
  }
  throw UsageError("",
                   "unknown command \"" + name + "\"; the commands are run, check, study, render, generate, version");
}

}  // namespace

int main(int argc, char** argv) {
  // Freed memory stays with the process instead of going back to the kernel: UMFPACK allocates its
  // factors anew at every factorization (hundreds of MB at 10^4 contact points), and pages fresh from
  // the kernel are zeroed one fault at a time. At 10^4 points this takes a factorization from 1.8 to
  // 1.1 s (docs/scale.md); the peak memory grows by 2 %.
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, -1);
  std::vector<std::string> args(argv + 1, argv + argc);
  g_commandLine = bc::core::commandLine(argc, argv);
  g_program = argv[0];
  bc::core::setDocumentationDirectory(bc::drivers::findDocumentation());
  guardExit();
  if (args.empty()) {
    std::fputs("beamcontact: a command is needed (run, check, study, render, generate); see beamcontact --help\n",
               stderr);
    return 1;
  }
  if (args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    std::fputs(kUsage, stdout);
    std::fputs(bc::drivers::cli::documentationNote().c_str(), stdout);
    return 0;
  }
  try {
    return command(argc, argv, args);
  } catch (const UsageError& e) {
    // Under mpirun every rank reads the command line: rank 0 says what is wrong.
    if (firstRankByEnvironment())
      std::fprintf(stderr, "beamcontact: %s%s%s (see beamcontact %s--help)\n", e.command.c_str(),
                   e.command.empty() ? "" : ": ", e.what(), e.command.empty() ? "" : (e.command + " ").c_str());
    return 1;
  }
}
