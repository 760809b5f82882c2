// beamcontact: command-line driver. Parses arguments, reads and validates the deck, runs it.
//   beamcontact run DECK.xml [--output DIR] [--quiet]
//   beamcontact --print-valid-parameters
//   beamcontact --help
// Exit codes: 0 run complete; 1 usage or input error; 2 run incomplete (a step failed to converge);
// 3 unexpected error. Errors are one line on stderr naming the cause.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>

#include <Teuchos_DefaultComm.hpp>
#include <Tpetra_Core.hpp>

#include "constraints/EnforcerRegistry.hpp"

#include "core/Simulation.hpp"
#include "input/Deck.hpp"

namespace {

const char* kUsage =
    "usage: beamcontact run DECK.xml [--output DIR] [--quiet]\n"
    "       beamcontact --print-valid-parameters\n"
    "       beamcontact --help\n"
    "\n"
    "Runs a BeamContact XML deck: geometrically nonlinear 3D beams, load factor T from 0 to 1.\n"
    "Results (CSV, VTK, status, effective parameters) go to the deck's Output/Directory, by\n"
    "default results/<deck name>, or to DIR.\n"
    "Exit codes: 0 complete, 1 usage or input error, 2 run incomplete, 3 unexpected error.\n";

int runDeck(const std::string& deck, const std::string& output, bool quiet) {
  auto comm = Tpetra::getDefaultComm();
  const bool root = comm->getRank() == 0;
  const std::string stem = std::filesystem::path(deck).stem().string();
  bc::input::Problem problem = bc::input::buildProblem(bc::input::readDeckFile(deck), stem);
  if (!output.empty()) problem.outputDirectory = output;
  bc::core::RunOptions options;
  options.outputDirectory = problem.outputDirectory;
  options.writeVtk = problem.writeVtk;
  options.progress = !quiet;
  options.effective = &problem.effective;
  if (root)
    std::printf("BeamContact: %s, %d nodes, %zu elements, %d ranks\n", deck.c_str(),
                problem.model.initial.numNodes(), problem.beams->elements().size(), comm->getSize());
  const auto result = bc::core::simulate(problem.model, problem.solver, problem.linearSolver, options, comm);
  if (root) {
    if (result.report.completed)
      std::printf("complete: %d steps, %d Newton iterations, solve %.3f s; results in %s\n", result.report.steps,
                  result.report.newtonIterations, result.solveSeconds, problem.outputDirectory.c_str());
    else
      std::fprintf(stderr, "beamcontact: run incomplete: stopped at T = %g: %s (converged steps are in %s)\n",
                   result.report.lastT, result.report.failure.c_str(), problem.outputDirectory.c_str());
  }
  return result.report.completed ? 0 : 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    std::fputs(kUsage, args.empty() ? stderr : stdout);
    return args.empty() ? 1 : 0;
  }
  Tpetra::ScopeGuard scope(&argc, &argv);
  bc::constraints::registerBuiltinEnforcers();
  const bool root = Tpetra::getDefaultComm()->getRank() == 0;
  try {
    if (args[0] == "--print-valid-parameters") {
      if (root) {
        std::cout << "BeamContact deck reference (ParameterList \"BeamContact\"):\n";
        bc::input::referenceParameters().print(
            std::cout, Teuchos::ParameterList::PrintOptions().showDoc(true).indent(2).showTypes(true));
      }
      return 0;
    }
    if (args[0] != "run" || args.size() < 2) {
      if (root) std::fprintf(stderr, "beamcontact: unknown command \"%s\"\n%s", args[0].c_str(), kUsage);
      return 1;
    }
    std::string output;
    bool quiet = false;
    for (std::size_t i = 2; i < args.size(); ++i) {
      if (args[i] == "--output" && i + 1 < args.size()) output = args[++i];
      else if (args[i] == "--quiet") quiet = true;
      else {
        if (root) std::fprintf(stderr, "beamcontact: unknown option \"%s\"\n%s", args[i].c_str(), kUsage);
        return 1;
      }
    }
    return runDeck(args[1], output, quiet);
  } catch (const bc::core::InputError& e) {
    if (root) std::fprintf(stderr, "beamcontact: input error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    if (root) std::fprintf(stderr, "beamcontact: error: %s\n", e.what());
    return 3;
  }
}
