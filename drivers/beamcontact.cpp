// beamcontact: command-line driver. Parses arguments, reads and validates the deck, runs it.
//   beamcontact run DECK.xml [--output DIR] [--quiet] [--restart DIR]
//   beamcontact check DECK.xml
//   beamcontact study STUDY.xml [--output DIR] [--parallel N] [--timing [N]] [--no-report]
//   beamcontact render RESULTS_DIR OUT.png [--stages T1,T2,...] [--view ELEV,AZIM] [--title TEXT]
//   beamcontact --print-valid-parameters
//   beamcontact --version (or version)
//   beamcontact --help
// Exit codes: 0 run complete; 1 usage or input error; 2 run incomplete (a step failed to converge, or
// a results file could not be written); 3 unexpected error; 4 a Python module render needs is missing,
// or a study's cases all completed but its report was not written (a missing module is named with its
// Debian package); 128 + N stopped by signal N (SIGTERM: 143, SIGINT: 130) after writing a checkpoint.
// Errors are one line on stderr naming the cause.
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

#include "Study.hpp"
#include "constraints/ContactManager.hpp"
#include "constraints/EnforcerRegistry.hpp"
#include "input/Plugins.hpp"
#include "Generate.hpp"

#include "core/Faults.hpp"
#include "BuildInfo.hpp"
#include "core/Provenance.hpp"
#include "core/Simulation.hpp"
#include "input/Deck.hpp"

namespace {

const char* kUsage =
    "usage: beamcontact run DECK.xml [--output DIR] [--overwrite] [--quiet] [--restart DIR] [--plugin LIB]...\n"
    "       beamcontact check DECK.xml [--plugin LIB]...\n"
    "       beamcontact study STUDY.xml [--output DIR] [--overwrite] [--parallel N] [--timing [N]] [--no-report] "
    "[--plugin LIB]...\n"
    "       beamcontact render RESULTS_DIR OUT.png [--stages T1,T2,...] [--view ELEV,AZIM] [--title TEXT]\n"
    "       beamcontact generate grid|weave [--n N] [--m M] [--spacing S] [--radius R] [--gap G]\n"
    "                [--press P (grid) | --pull P (weave)] [--elements E] [--youngs-modulus Y] [--friction MU]\n"
    "                [--penalty EPS] [--increments K] [--output FILE]\n"
    "       beamcontact generate network [--fibres N] [--box B] [--height H] [--length L] [--tilt DEG]\n"
    "                [--min-angle DEG] [--compress C] [--seed S] [--radius R] [--gap G] [--elements E] ...\n"
    "       beamcontact generate strand [--wires W] [--core 0|1] [--lay-length L] [--turns T] [--stretch S] ...\n"
    "       beamcontact --print-valid-parameters [--plugin LIB]...\n"
    "       beamcontact --version\n"
    "       beamcontact --help\n"
    "\n"
    "Runs a BeamContact XML deck: geometrically nonlinear 3D beams, load factor T from 0 to 1.\n"
    "Results (CSV, VTK, status, effective parameters) go to the deck's Output/Directory, by\n"
    "default results/<deck name>, or to DIR.\n"
    "--plugin LIB loads a shared library with strategies of its own (a study passes it to every case);\n"
    "a deck's Plugins list only names what it needs: each must be given with --plugin too, since a\n"
    "plug-in runs code. docs/contact.md shows how to write one.\n"
    "A results or study directory holds beamcontact-manifest.txt, the files beamcontact wrote there; a\n"
    "directory holding anything else is refused, unless --overwrite, which writes beside the other\n"
    "files and replaces only beamcontact's own. A deck's output paths are relative, without \"..\" and\n"
    "links; --output may name any directory.\n"
    "generate writes a many-beam deck (grid: two layers of crossing beams pressed together; weave: a\n"
    "plain-weave mat of undulating yarns whose warps are pulled; network: random fibres in a box,\n"
    "compressed; strand: helical wires, pulled); docs/input.md lists the options.\n"
    "check reads and validates a deck and checks the model (supports, duplicates) without running it.\n"
    "A study runs every case of a study deck (a base deck and the parameters to vary), N at a time\n"
    "(default: one per core), and writes cases.csv, report.md and plots (docs/studies.md); its timings\n"
    "are indicative. --timing [N] runs the cases one at a time without VTK output, each N times\n"
    "(default 5), and reports the median solve time with its spread.\n"
    "render draws a run's beams and contact forces at four stages of loading (default T = 0.25, 0.5,\n"
    "0.75, 1) into a PNG, from the run's VTK files.\n"
    "study reports and render need Python 3 with matplotlib (Debian: python3-matplotlib), render also\n"
    "numpy and vtk (python3-numpy, python3-vtk9); a missing one is named (a study without it: --no-report).\n"
    "--version prints the version, git commit, build type, Trilinos, MPI library and compiler; every\n"
    "results directory records them with the date, host, ranks and command line (status.txt,\n"
    "summary.csv, effective_parameters.xml; a study's cases.csv, study.json and report.md).\n"
    "--restart DIR continues the run whose results are in DIR from its checkpoint.txt (written every\n"
    "Output/Checkpoint Every steps and when SIGTERM or SIGINT stops a run); the deck must be the same\n"
    "outside its Output sublist, and the checkpoint as written (its last line is its SHA-256) and\n"
    "consistent with the deck's model; a checkpoint that is not is refused and nothing in DIR changes.\n"
    "Exit codes: 0 complete, 1 usage or input error, 2 run incomplete or a results file could not be\n"
    "written (a study: some case did not complete; every case is recorded), 3 unexpected error,\n"
    "4 a Python module render needs is missing, or every case of a study is complete but its report\n"
    "was not written (a missing module is named with its Debian package), 128 + N stopped by signal N\n"
    "(status.txt says so).\n";

// The command line as typed (before MPI and Kokkos take their own arguments out), for the provenance.
std::string g_commandLine;

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
int studyCommand(const std::vector<std::string>& args, const std::vector<std::string>& plugins) {
  if (args.size() < 2) {
    std::fprintf(stderr, "beamcontact: study needs a study deck; see beamcontact --help\n");
    return 1;
  }
  bc::drivers::StudyOptions options;
  options.plugins = plugins;
  options.command = g_commandLine;
  for (std::size_t i = 2; i < args.size(); ++i) {
    if (args[i] == "--output" && i + 1 < args.size()) {
      options.output = args[++i];
    } else if (args[i] == "--parallel" && i + 1 < args.size()) {
      const std::string& v = args[++i];
      options.parallel = -1;
      if (!v.empty() && v.size() <= 4 && v.find_first_not_of("0123456789") == std::string::npos)
        options.parallel = std::stoi(v);
      if (options.parallel < 1 || options.parallel > 1024) {
        std::fprintf(stderr, "beamcontact: --parallel takes a whole number from 1 to 1024, got \"%s\"\n",
                     args[i].c_str());
        return 1;
      }
    } else if (args[i] == "--timing") {
      // Optional count: the next argument when it is a whole number.
      options.timing = 5;
      const bool count = i + 1 < args.size() && !args[i + 1].empty() &&
                         args[i + 1].find_first_not_of("0123456789") == std::string::npos;
      if (count) {
        const std::string& v = args[++i];
        options.timing = v.size() <= 3 ? std::stoi(v) : 0;
        if (options.timing < 1 || options.timing > 100) {
          std::fprintf(stderr, "beamcontact: --timing takes a whole number of runs from 1 to 100, got \"%s\"\n",
                       v.c_str());
          return 1;
        }
      }
    } else if (args[i] == "--no-report") {
      options.report = false;
    } else if (args[i] == "--overwrite") {
      options.overwrite = true;
    } else {
      std::fprintf(stderr, "beamcontact: unknown option \"%s\"; see beamcontact --help\n", args[i].c_str());
      return 1;
    }
  }
  return withExitCodes(true, [&] { return bc::drivers::runStudy(args[1], options); });
}

// The closing lines of a run (on rank 0): complete, interrupted (how to continue), or incomplete, and
// the run's warnings.
void printRunResult(const bc::core::RunResult& result, const std::string& deck, const std::string& directory) {
  if (result.restartedAtStep >= 0)
    std::printf("restarted after step %d from %s/checkpoint.txt\n", result.restartedAtStep, directory.c_str());
  if (result.report.completed)
    std::printf("complete: %d steps, %d Newton iterations, solve %.3f s; results in %s\n", result.report.steps,
                result.report.newtonIterations, result.solveSeconds, directory.c_str());
  else if (result.report.interrupted)
    std::fprintf(stderr, "beamcontact: interrupted by %s at T = %g; continue with: beamcontact run %s --restart %s\n",
                 bc::core::signalName(result.report.interrupted).c_str(), result.report.lastT, deck.c_str(),
                 directory.c_str());
  else
    std::fprintf(stderr, "beamcontact: run incomplete: stopped at T = %g: %s (converged steps are in %s)\n",
                 result.report.lastT, result.report.failure.c_str(), directory.c_str());
  for (const auto& w : result.report.warnings) std::fprintf(stderr, "beamcontact: warning: %s\n", w.c_str());
}

int runDeck(const std::string& deck, const std::string& output, bool quiet, const std::string& restart, bool overwrite,
            const std::vector<std::string>& plugins) {
  auto comm = Tpetra::getDefaultComm();
  const bool root = comm->getRank() == 0;
  const std::string stem = std::filesystem::path(deck).stem().string();
  // Every rank reads the deck and builds the model (the strategy's constructor included); an error on
  // any rank ends every rank with the first failing rank's message.
  Teuchos::ParameterList list;
  bc::input::Problem problem;
  bc::core::collectively(*comm, [&] {
    bc::core::injectFault("deck");
    list = bc::input::readDeckFile(deck);
    // The deck's Plugins (and digests) against --plugin before any library is loaded.
    bc::input::checkDeckPlugins(list, deck, plugins);
  });
  // Loaded on every rank; a library that fails on one rank only ends every rank with its message.
  bc::core::collectively(*comm, [&] {
    bc::core::injectFault("plugin");
    for (const auto& plugin : plugins) bc::input::loadPlugin(plugin);
  });
  bc::core::collectively(*comm, [&] {
    bc::core::injectFault("strategy");
    // (The list handed over, not copied: a deck's lists take about 4 bytes per deck byte.)
    problem = bc::input::buildProblem(std::exchange(list, Teuchos::ParameterList()), stem);
  });
  if (!restart.empty()) problem.outputDirectory = restart;
  else if (!output.empty()) problem.outputDirectory = output;
  bc::core::RunOptions options;
  options.outputDirectory = problem.outputDirectory;
  options.outputFromDeck = restart.empty() && output.empty();
  options.overwrite = overwrite;
  for (const auto& p : bc::input::loadedPlugins())
    options.statusNotes.push_back("plug-in: " + p.path + " sha256 " + p.sha256);
  options.provenance = bc::core::runProvenance(bc::drivers::buildProvenance(), comm->getSize(), g_commandLine);
  options.writeVtk = problem.writeVtk;
  options.vtkEvery = problem.vtkEvery;
  options.vtkAt = problem.vtkAt;
  options.vtkCompression = problem.vtkCompression;
  options.progress = !quiet;
  options.effective = &problem.effective;
  options.checkpointEvery = problem.checkpointEvery;
  options.restart = !restart.empty();
  options.fingerprint = bc::input::deckFingerprint(problem);
  if (root)
    std::printf("BeamContact: %s, %d nodes, %zu elements, %d ranks\n", deck.c_str(), problem.model.initial.numNodes(),
                problem.beams->elements().size(), comm->getSize());
  const auto result = bc::core::simulate(problem.model, problem.solver, problem.linearSolver, options, comm);
  if (root) printRunResult(result, deck, problem.outputDirectory);
  if (result.report.interrupted) return 128 + result.report.interrupted;
  return result.report.completed ? 0 : 2;
}

// The --plugin LIB pairs (any number, after the command), taken out of `args` into `plugins`; false
// (with the message) when one lacks its library.
bool takePlugins(std::vector<std::string>& args, std::vector<std::string>& plugins) {
  for (std::size_t i = 1; i < args.size();) {
    if (args[i] != "--plugin") {
      ++i;
      continue;
    }
    if (i + 1 >= args.size()) {
      std::fprintf(stderr, "beamcontact: missing library after \"--plugin\"; see beamcontact --help\n");
      return false;
    }
    plugins.push_back(args[i + 1]);
    args.erase(args.begin() + i, args.begin() + i + 2);
  }
  return true;
}

// No command (an error) or --help.
int helpCommand(const std::vector<std::string>& args) {
  if (args.empty())
    std::fputs("beamcontact: a command is needed (run, check, study, render, generate); see beamcontact --help\n",
               stderr);
  else std::fputs(kUsage, stdout);
  return args.empty() ? 1 : 0;
}

// beamcontact render RESULTS_DIR OUT.png [options]: the render script draws it.
int renderCommand(const std::vector<std::string>& args) {
  if (args.size() < 3) {
    std::fprintf(stderr, "beamcontact: render needs a results directory and an output file; see beamcontact --help\n");
    return 1;
  }
  if (!std::filesystem::is_directory(args[1])) {
    std::fprintf(stderr, "beamcontact: render: \"%s\" is not a results directory\n", args[1].c_str());
    return 1;
  }
  std::vector<std::string> command = {"/usr/bin/python3", bc::drivers::scriptPath("render_stages.py")};
  command.insert(command.end(), args.begin() + 1, args.end());
  // The script exits 1 (2 from its argument parser) on a usage error, 4 when a Python module is missing
  // (one line naming its Debian package), 3 otherwise.
  const int code = bc::drivers::runProgram(command);
  return code == 0 ? 0 : (code == 1 || code == 2) ? 1 : code == 4 ? 4 : 3;
}

// beamcontact check DECK.xml: reads the deck and builds the model without running it.
int checkCommand(const std::vector<std::string>& args, const std::vector<std::string>& plugins) {
  if (args.size() != 2) {
    std::fprintf(stderr, "beamcontact: check takes one deck; see beamcontact --help\n");
    return 1;
  }
  return withExitCodes(true, [&] {
    const Working working;
    bc::constraints::registerBuiltinEnforcers();
    Teuchos::ParameterList list = bc::input::readDeckFile(args[1]);
    bc::input::checkDeckPlugins(list, args[1], plugins);  // before any library is loaded
    for (const auto& plugin : plugins) bc::input::loadPlugin(plugin);
    const auto problem = bc::input::buildProblem(std::exchange(list, Teuchos::ParameterList()),
                                                 std::filesystem::path(args[1]).stem().string());
    std::printf("ok: %s: %d nodes, %zu elements, %d joints, %zu supports, %zu loads, %zu contact points at the start\n",
                args[1].c_str(), problem.model.initial.numNodes(), problem.beams->elements().size(), problem.joints,
                problem.model.supports.size(), problem.model.loads.size(),
                problem.contact ? problem.contact->points().size() : std::size_t(0));
    return 0;
  });
}

// beamcontact --print-valid-parameters: the deck reference, with the plug-ins' strategies (printed on rank 0).
int printValidParameters(const bc::core::Comm& comm, const std::vector<std::string>& plugins, bool root) {
  bc::core::collectively(comm, [&] {
    for (const auto& plugin : plugins) bc::input::loadPlugin(plugin);
  });
  if (root) {
    std::cout << "BeamContact deck reference (ParameterList \"BeamContact\"):\n";
    bc::input::referenceParameters().print(
        std::cout, Teuchos::ParameterList::PrintOptions().showDoc(true).indent(2).showTypes(true));
  }
  return 0;
}

// beamcontact run DECK.xml [options]: the options (messages on rank 0), then the run.
int runCommand(const std::vector<std::string>& args, const std::vector<std::string>& plugins, bool root) {
  std::string output, restart;
  bool quiet = false, overwrite = false, outputGiven = false;
  for (std::size_t i = 2; i < args.size(); ++i) {
    if (args[i] == "--output" && i + 1 < args.size()) {
      output = args[++i];
      outputGiven = true;
    } else if (args[i] == "--restart" && i + 1 < args.size()) restart = args[++i];
    else if (args[i] == "--quiet") quiet = true;
    else if (args[i] == "--overwrite") overwrite = true;
    else {
      if (root)
        std::fprintf(stderr, "beamcontact: %s \"%s\"; see beamcontact --help\n",
                     args[i] == "--output" || args[i] == "--restart" ? "missing directory after" : "unknown option",
                     args[i].c_str());
      return 1;
    }
  }
  if (!restart.empty() && !output.empty() &&
      std::filesystem::path(restart).lexically_normal() != std::filesystem::path(output).lexically_normal()) {
    if (root) std::fprintf(stderr, "beamcontact: --restart continues in its own directory; leave out --output\n");
    return 1;
  }
  if (outputGiven && output.find_first_not_of(' ') == std::string::npos) {
    if (root) std::fprintf(stderr, "beamcontact: --output names no directory\n");
    return 1;
  }
  return runDeck(args[1], output, quiet, restart, overwrite, plugins);
}

// The commands that run under MPI (run, --print-valid-parameters; any other is unknown), with MPI and
// Kokkos initialized, the signal handlers and the built-in strategies.
int mpiCommand(int& argc, char**& argv, const std::vector<std::string>& args, const std::vector<std::string>& plugins) {
  Tpetra::ScopeGuard scope(&argc, &argv);
  guardExit();
  bc::core::installSignalHandlers();
  bc::constraints::registerBuiltinEnforcers();
  const auto comm = Tpetra::getDefaultComm();
  const bool root = comm->getRank() == 0;
  return withExitCodes(root, [&] {
    const Working working;
    if (args[0] == "--print-valid-parameters") return printValidParameters(*comm, plugins, root);
    if (args[0] == "run" && args.size() < 2) {
      if (root) std::fprintf(stderr, "beamcontact: run needs a deck; see beamcontact --help\n");
      return 1;
    }
    if (args[0] != "run") {
      if (root) std::fprintf(stderr, "beamcontact: unknown command \"%s\"; see beamcontact --help\n", args[0].c_str());
      return 1;
    }
    return runCommand(args, plugins, root);
  });
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
  guardExit();
  std::vector<std::string> plugins;
  if (!takePlugins(args, plugins)) return 1;
  if (args.empty() || args[0] == "--help" || args[0] == "-h") return helpCommand(args);
  if ((args[0] == "--version" || args[0] == "version") && args.size() == 1) return versionCommand();
  if (args[0] == "render") return renderCommand(args);
  // A study only starts and watches case processes: no MPI in this process.
  if (args[0] == "study") return studyCommand(args, plugins);
  // generate writes a deck from a few parameters: no MPI in this process.
  if (args[0] == "generate") return withExitCodes(true, [&] { return bc::drivers::generateDeck(args); });
  // check builds the model only: no MPI in this process (so it is quick to call many times).
  if (args[0] == "check") return checkCommand(args, plugins);
  return mpiCommand(argc, argv, args, plugins);
}
