#include "Simulation.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <Teuchos_XMLParameterListHelpers.hpp>

#include "ResultsWriter.hpp"

namespace bc::core {

RunResult simulate(Model& model, const SolverSettings& settings, const Teuchos::ParameterList& linearSolver,
                   const RunOptions& options, Teuchos::RCP<const Comm> comm) {
  auto timer = Teuchos::rcp(new Teuchos::StackedTimer("BeamContact"));
  const bool root = comm->getRank() == 0;
  auto linear = makeLinearSolver(linearSolver);

  ResultsWriter writer(options.outputDirectory, model, comm, options.writeVtk);
  if (root && options.effective)
    Teuchos::writeParameterListToXmlFile(*options.effective,
                                         (std::filesystem::path(options.outputDirectory) / "effective_parameters.xml").string());
  writer.writeInitial(model.initial);

  StaticSolver solver(comm, model, settings, *linear, timer);
  RunResult result;
  const auto t0 = std::chrono::steady_clock::now();
  const RunReport run = solver.run([&](const StepReport& step, const State& state, const Assembler& assembler) {
    writer.writeStep(step, state, assembler.fullResidual());
    result.steps.push_back(step);
    if (root && options.progress) {
      std::printf("step %4d  T = %.6f  Newton %2d  |r| %.3e", step.step, step.T, step.iterations,
                  step.history.back().residualNorm);
      for (const auto& c : model.contributions) {
        const std::string summary = c->progressSummary();
        if (!summary.empty()) std::printf("  %s", summary.c_str());
      }
      if (step.cutLevel) std::printf("  (cut level %d)", step.cutLevel);
      std::printf("\n");
      std::fflush(stdout);
    }
  });
  const auto t1 = std::chrono::steady_clock::now();
  timer->stopBaseTimer();
  std::ostringstream report;
  Teuchos::StackedTimer::OutputOptions opts;
  opts.output_fraction = true;
  opts.output_minmax = comm->getSize() > 1;
  timer->report(report, comm, opts);
  RunSummary summary;
  summary.run = run;
  summary.solveSeconds = std::chrono::duration<double>(t1 - t0).count();
  for (const auto& st : result.steps) {
    summary.maxIterationsPerStep = std::max(summary.maxIterationsPerStep, st.iterations);
    summary.passes += st.passes;
  }
  writer.writeSummary(summary);
  writer.finish(run, report.str());
  if (root && options.progress) std::printf("%s", report.str().c_str());

  result.report = run;
  result.solveSeconds = std::chrono::duration<double>(t1 - t0).count();
  result.finalState = solver.state();
  return result;
}

}  // namespace bc::core
