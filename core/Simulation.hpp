// One run, as the algorithm reads: set up the solver and the results directory, step the load,
// write every converged step, close the run with its status and the timer summary.
#pragma once
#include <iosfwd>
#include <string>
#include <vector>

#include <Teuchos_ParameterList.hpp>

#include "Model.hpp"
#include "StaticSolver.hpp"

namespace bc::core {

struct RunOptions {
  std::string outputDirectory;
  bool writeVtk = true;
  bool progress = true;                       // one line per step on rank 0
  const Teuchos::ParameterList* effective = nullptr;  // written as effective_parameters.xml
};

struct RunResult {
  RunReport report;
  double solveSeconds = 0.0;  // wall time of the load stepping (excludes start-up and set-up)
  State finalState;
  std::vector<StepReport> steps;  // every converged step with its Newton history
};

RunResult simulate(Model& model, const SolverSettings& settings, const Teuchos::ParameterList& linearSolver,
                   const RunOptions& options, Teuchos::RCP<const Comm> comm);

}  // namespace bc::core
