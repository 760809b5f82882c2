#include "Simulation.hpp"

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_TimeMonitor.hpp>

#include "Checkpoint.hpp"
#include "Faults.hpp"
#include "ResultsWriter.hpp"
#include "Version.hpp"

namespace bc::core {

namespace {

// The checkpoint's text, read on rank 0 and sent to all ranks.
std::string readCheckpointText(const std::string& dir, const Comm& comm) {
  std::string text;
  collectively(comm, [&] {
    if (comm.getRank() != 0) return;
    const auto path = std::filesystem::path(dir) / "checkpoint.txt";
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
      throw InputError("cannot restart: " + path.string() + " is a directory, not a checkpoint file");
    std::ifstream f(path);
    if (!f) throw InputError("cannot restart: " + path.string() + " does not exist or cannot be read");
    std::ostringstream s;
    s << f.rdbuf();
    text = s.str();
  });
  long long size = static_cast<long long>(text.size());
  Teuchos::broadcast(comm, 0, &size);
  text.resize(static_cast<std::size_t>(size));
  if (size > 0) Teuchos::broadcast(comm, 0, static_cast<int>(size), text.data());
  return text;
}

// The Trilinos solvers' own timers (Belos, MueLu: Teuchos::TimeMonitor) land in this run's timer,
// nested where they run; the global one is put back when the run ends.
struct TimeMonitorTarget {
  Teuchos::RCP<Teuchos::StackedTimer> previous = Teuchos::TimeMonitor::getStackedTimer();
  explicit TimeMonitorTarget(const Teuchos::RCP<Teuchos::StackedTimer>& t) { Teuchos::TimeMonitor::setStackedTimer(t); }
  ~TimeMonitorTarget() { Teuchos::TimeMonitor::setStackedTimer(previous); }
};

// A restart: the solver and the contributions take the checkpoint's state (before the results
// directory is touched, so a checkpoint that does not fit the deck changes nothing), and the run
// summary its counts; returns the earlier run's solve time.
double resume(StaticSolver& solver, RunSummary& summary, const RunOptions& options, const Comm& comm) {
  const std::string source = (std::filesystem::path(options.outputDirectory) / "checkpoint.txt").string();
  CheckpointIn in(readCheckpointText(options.outputDirectory, comm), source);
  in.label("beamcontact-checkpoint");
  const long long format = in.integer();
  if (format != kCheckpointFormat)
    in.fail("it has format version " + std::to_string(format) + ", this BeamContact reads version " +
            std::to_string(kCheckpointFormat));
  in.verifyChecksum();
  in.label("version");
  const std::string version = in.word();
  if (version != kVersion)
    in.fail("it was written by BeamContact " + version + ", this is BeamContact " + kVersion +
            " (a run continues only with the version that started it)");
  in.label("deck");
  if (in.word() != options.fingerprint)
    in.fail(
        "it was written for another deck (the deck changed outside its Output sublist, or its Output/Tracked "
        "Points changed)");
  in.label("summary");
  const long long passes = in.integer(), maxIterations = in.integer();
  const double earlierSeconds = in.real();
  if (passes < 0 || passes > INT_MAX || maxIterations < 0 || maxIterations > INT_MAX || earlierSeconds < 0.0)
    in.fail("its run summary has a negative or too large count (passes " + std::to_string(passes) +
            ", most iterations in a step " + std::to_string(maxIterations) + ", seconds " + shortest(earlierSeconds) +
            ")");
  summary.passes = static_cast<int>(passes);
  summary.maxIterationsPerStep = static_cast<int>(maxIterations);
  solver.loadCheckpoint(in);
  in.finish();
  // Every converged step took at least one pass, and no step more iterations than all of them.
  const RunReport& loaded = solver.runReport();
  if (summary.passes < loaded.steps || summary.maxIterationsPerStep > loaded.newtonIterations)
    in.fail("its run summary (" + std::to_string(summary.passes) + " passes, at most " +
            std::to_string(summary.maxIterationsPerStep) + " iterations in a step) does not fit its " +
            std::to_string(loaded.steps) + " steps of " + std::to_string(loaded.newtonIterations) +
            " Newton iterations");
  return earlierSeconds;
}

// A duration for the progress line: "85 ms", "4.2 s", "3 min 05 s", "2 h 07 min".
std::string shortDuration(double seconds) {
  char text[32];
  if (seconds < 1.0) std::snprintf(text, sizeof text, "%.0f ms", 1e3 * seconds);
  else if (seconds < 60.0) std::snprintf(text, sizeof text, "%.1f s", seconds);
  else if (seconds < 3600.0) std::snprintf(text, sizeof text, "%d min %02d s", int(seconds / 60), int(seconds) % 60);
  else std::snprintf(text, sizeof text, "%d h %02d min", int(seconds / 3600), int(seconds / 60) % 60);
  return text;
}

// One line per converged step on rank 0: T, Newton iterations, the residual, the contributions' counts,
// the step's wall time and the time left, estimated from the pace so far: elapsed (1 - T) / (T - T0),
// T0 the load factor this process started from.
struct Progress {
  using Clock = std::chrono::steady_clock;
  double T0 = 0.0;
  Clock::time_point start = Clock::now(), last = start;

  void print(const StepReport& step, const Model& model) {
    const auto now = Clock::now();
    const double stepSeconds = std::chrono::duration<double>(now - last).count();
    const double elapsed = std::chrono::duration<double>(now - start).count();
    last = now;
    std::printf("step %4d  T = %.6f  Newton %2d  |r| %.3e", step.step, step.T, step.iterations,
                step.history.back().residualNorm);
    for (const auto& c : model.contributions) {
      const std::string text = c->progressSummary();
      if (!text.empty()) std::printf("  %s", text.c_str());
    }
    if (step.cutLevel) std::printf("  (cut level %d)", step.cutLevel);
    std::printf("  %s/step", shortDuration(stepSeconds).c_str());
    if (step.T > T0 && step.T < 1.0)
      std::printf(", %s left", shortDuration(elapsed * (1.0 - step.T) / (step.T - T0)).c_str());
    std::printf("\n");
    std::fflush(stdout);
  }
};
// Where the results go, and what status.txt says beside its first line.
ResultsWriter::Where where(const RunOptions& options) {
  ResultsWriter::Where w;
  w.directory = options.outputDirectory;
  w.fromDeck = options.outputFromDeck;
  w.overwrite = options.overwrite;
  w.notes = options.statusNotes;
  w.provenance = options.provenance;
  w.vtkEvery = options.vtkEvery;
  w.vtkAt = options.vtkAt;
  w.vtkCompression = options.vtkCompression;
  return w;
}

// The run closed: the run's timer stopped, its summary (timers.txt, printed when `print`: --timers), what the
// contributions could not model among the run's warnings, the main stages' times in summary.csv
// (this process's times; a restart counts its own part only), the status.
void finish(ResultsWriter& writer, RunSummary& summary, const Model& model, Teuchos::StackedTimer& timer,
            const Teuchos::RCP<const Comm>& comm, bool print) {
  timer.stopBaseTimer();
  std::ostringstream report;
  Teuchos::StackedTimer::OutputOptions opts;
  opts.output_fraction = true;
  opts.output_minmax = comm->getSize() > 1;
  // Teuchos' three-line note on timers missing on some ranks means nothing on one rank.
  opts.print_warnings = comm->getSize() > 1;
  timer.report(report, comm, opts);
  for (const auto& c : model.contributions)
    for (const auto& w : c->warnings()) summary.run.warnings.push_back(w);
  for (const auto& [column, path] :
       std::vector<std::pair<std::string, std::string>>{{"search_seconds", "Contact Search"},
                                                        {"assembly_seconds", "Assembly"},
                                                        {"contact_evaluation_seconds", "Assembly@Evaluate contact"},
                                                        {"linear_solve_seconds", "Linear Solve"},
                                                        {"active_set_seconds", "Active Set"},
                                                        {"output_seconds", "Output"}})
    summary.stages.emplace_back(column, timer.accumulatedTime(path));
  writer.writeSummary(summary);
  writer.finish(summary.run, report.str());
  if (print) std::printf("%s", report.str().c_str());
}

}  // namespace

RunResult simulate(Model& model, const SolverSettings& settings, const Teuchos::ParameterList& linearSolver,
                   const RunOptions& options, Teuchos::RCP<const Comm> comm) {
  auto timer = Teuchos::rcp(new Teuchos::StackedTimer("BeamContact"));
  TimeMonitorTarget timeMonitorTarget(timer);
  const bool root = comm->getRank() == 0;
  // Direct Solver = Automatic chosen by the system's size and the rank count: the choice in the run's
  // header and in effective_parameters.xml.
  const SystemSize size{model.initial.numDofs(), options.contactPoints, comm->getSize()};
  Teuchos::ParameterList linearList = linearSolver;
  const std::string choice = resolveLinearSolver(linearList, size);
  if (root && options.progress && !choice.empty()) std::printf("Direct Solver: %s\n", choice.c_str());
  Teuchos::ParameterList effective;
  if (options.effective) {
    effective = *options.effective;
    if (effective.isSublist("Linear Solver")) resolveLinearSolver(effective.sublist("Linear Solver"), size);
  }
  // A run on KLU2 by Automatic changes its LU when contact points appear during it (beams that start
  // apart): said before the step's line and in effective_parameters.xml, with the step.
  std::unique_ptr<AutomaticChange> change;
  bool changeWritten = false;
  auto linear = makeLinearSolver(linearSolver, size, options.contactPointsNow,
                                 [&](const AutomaticChange& c) { change = std::make_unique<AutomaticChange>(c); });
  StaticSolver solver(comm, model, settings, *linear, timer);
  RunResult result;
  RunSummary summary;
  double earlierSeconds = 0.0;  // solve time of the run before the restart
  int resumeStep = -1;
  if (options.restart) {
    earlierSeconds = resume(solver, summary, options, *comm);
    resumeStep = result.restartedAtStep = solver.runReport().steps;
  }

  ResultsWriter writer(where(options), model, comm, options.writeVtk, resumeStep,
                       options.restart ? solver.runReport().lastT : 0.0);
  try {
    if (options.effective) writer.writeEffective(effective);
    if (!options.restart) writer.writeInitial(model.initial);

    auto checkpoint = [&] {
      CheckpointOut out;
      out.label("beamcontact-checkpoint").integer(kCheckpointFormat);
      out.label("version").word(kVersion);
      out.label("deck").word(options.fingerprint);
      out.label("summary").integer(summary.passes).integer(summary.maxIterationsPerStep).real(earlierSeconds);
      solver.saveCheckpoint(out);
      writer.writeCheckpoint(out.text());
    };

    const auto t0 = std::chrono::steady_clock::now();
    Progress progress;
    progress.T0 = options.restart ? solver.runReport().lastT : 0.0;
    // The change of LU (at most one) from the step that made it (`step`; 0: the run stopped in it).
    const auto recordChange = [&](int step, double T) {
      if (!change || changeWritten) return;
      changeWritten = true;
      const std::string when = step > 0 ? "from step " + std::to_string(step) + " (T = " + std::to_string(T) + ")"
                                        : "from the step after the last converged one";
      if (root && options.progress) std::printf("Direct Solver: %s %s\n", change->line.c_str(), when.c_str());
      if (!options.effective || !effective.isSublist("Linear Solver")) return;
      Teuchos::ParameterList& lin = effective.sublist("Linear Solver");
      const std::string before = "; " + when + ", before it " + lin.get<std::string>("Direct Solver") +
                                 (lin.get<bool>("Reuse Factorization") ? " with" : " without") +
                                 " Reuse Factorization (" + chooseDirectSolver(size).reason + ")";
      for (const char* name : {"Direct Solver", "Reuse Factorization"}) {
        const Teuchos::ParameterEntry& now = change->resolved.getEntry(name);
        lin.setEntry(name, now);
        lin.getEntryRCP(name)->setDocString(now.docString() + before);
      }
      writer.writeEffective(effective);
    };
    RunReport run = solver.run([&](const StepReport& step, const State& state, const Assembler& assembler) {
      recordChange(step.step, step.T);
      writer.writeStep(step, state, assembler.fullResidual());
      result.steps.push_back(step);
      summary.maxIterationsPerStep = std::max(summary.maxIterationsPerStep, step.iterations);
      summary.passes += step.passes;
      if (options.checkpointEvery > 0 && step.step % options.checkpointEvery == 0) checkpoint();
      if (root && options.progress) progress.print(step, model);
    });
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // A run stopped by a signal keeps its last converged step for --restart.
    if (run.interrupted) {
      earlierSeconds += seconds;
      checkpoint();
    }
    recordChange(0, 0.0);
    summary.run = run;
    summary.solveSeconds = earlierSeconds + (run.interrupted ? 0.0 : seconds);
    finish(writer, summary, model, *timer, comm, root && options.printTimers);
    result.report = summary.run;
    result.solveSeconds = summary.solveSeconds;
    result.finalState = solver.state();
  } catch (const std::exception& e) {
    writer.fail(isOutOfMemory(e) ? outOfMemoryText(e) : e.what());
    throw;
  }
  return result;
}

}  // namespace bc::core
