// One run, as the algorithm reads: set up the solver and the results directory, step the load,
// write every converged step (and a checkpoint every few), close the run with its status and the
// timer summary. A restart reads the checkpoint first and continues the load stepping from it.
// Every error after the results directory exists leaves status.txt saying "failed: <cause>".
#pragma once
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include <Teuchos_ParameterList.hpp>

#include "Model.hpp"
#include "Provenance.hpp"
#include "StaticSolver.hpp"

namespace bc::core {

struct RunOptions {
  std::string outputDirectory;
  bool outputFromDeck = false;  // the directory is the deck's Output/Directory (relative, no "..", no links)
  bool overwrite = false;  // --overwrite: write beside files beamcontact did not write (OutputDirectory.hpp)
  std::vector<std::string> statusNotes;  // lines status.txt carries after its first (the loaded plug-ins)
  Fields provenance;  // what produced the run (Provenance.hpp): in status.txt, summary.csv, effective_parameters.xml
  bool writeVtk = true;
  int vtkEvery = 1;  // Output/VTK Every (0: only vtkAt; T = 0 and the last converged step always)
  std::vector<double> vtkAt;  // Output/VTK At
  bool vtkCompression = true;  // Output/VTK Compression
  bool progress = true;  // one line per step on rank 0 (T, iterations, time per step, time left)
  bool printTimers = false;  // the timer table on stdout (rank 0) as well as in timers.txt
  const Teuchos::ParameterList* effective = nullptr;  // written as effective_parameters.xml
  long long contactPoints = 0;  // at the start (with the model's unknowns, what Direct Solver = Automatic takes)
  std::function<long long()> contactPointsNow;  // during the run (Automatic takes it again while on KLU2)
  int checkpointEvery = 0;  // write checkpoint.txt after every this many converged steps (0: never)
  bool restart = false;  // continue from outputDirectory/checkpoint.txt
  std::string fingerprint;  // of the deck (without Output), kept in the checkpoint
};

struct RunResult {
  RunReport report;
  double solveSeconds = 0.0;  // wall time of the load stepping (excludes start-up and set-up)
  State finalState;
  std::vector<StepReport> steps;  // every converged step (of this process) with its Newton history
  int restartedAtStep = -1;  // the checkpoint's step when restarted
};

RunResult simulate(Model& model, const SolverSettings& settings, const Teuchos::ParameterList& linearSolver,
                   const RunOptions& options, Teuchos::RCP<const Comm> comm);

}  // namespace bc::core
