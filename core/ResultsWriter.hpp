// The results directory of a run, written by rank 0 as steps converge, so nothing of a converged step
// is lost when a later step fails:
//   status.txt               "running", then "complete" or "incomplete: <cause>"
//   steps.csv                step, T, cut level, Newton iterations, final residual, linear iterations
//   tracked_points.csv       displacements and unwrapped rotation vectors of the named points
//   reactions.csv            force and moment sums (f_int - f_ext) over each support's nodes
//   <table>.csv              per-step tables of contributions (contact_points.csv: every contact point)
//   vtk/step_NNNNN.vtu       the beams with their real cross-sections (point data: displacement, and
//                            "contact force" at the active contact points, drawn as vertex cells)
//   results.pvd              ParaView collection of the .vtu files with their T (rewritten each step)
//   timers.txt               StackedTimer summary
//   summary.csv              one row: completed, last T, steps, Newton iterations (total and largest per
//                            step), passes, solve wall time [s], peak memory [MB]; for studies and scripts
#pragma once
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "Model.hpp"
#include "StaticSolver.hpp"
#include "TpetraTypes.hpp"

namespace bc::core {

struct RunSummary {
  RunReport run;
  int maxIterationsPerStep = 0;
  int passes = 0;
  double solveSeconds = 0.0;
};

class ResultsWriter {
 public:
  ResultsWriter(const std::string& directory, const Model& model, Teuchos::RCP<const Comm> comm,
                bool writeVtk = true);
  void writeInitial(const State& state);
  void writeStep(const StepReport& step, const State& state, const std::vector<double>& fullResidual);
  void writeSummary(const RunSummary& summary);
  void finish(const RunReport& run, const std::string& timerReport);
  const std::string& directory() const { return dir_; }

 private:
  void writeVtk(int step, double T, const State& state);
  void writePvd();
  void writeStatus(const std::string& text);
  bool root() const { return rank_ == 0; }

  std::string dir_;
  const Model& model_;
  int rank_ = 0;
  bool vtk_ = true;
  std::ofstream steps_, tracked_, reactions_;
  std::vector<std::unique_ptr<std::ofstream>> tables_;  // one per contribution with a table
  std::vector<std::pair<double, std::string>> vtkFiles_;
};

}  // namespace bc::core
