// Quasi-static solution: load factor T from 0 to 1 over the configured increments, Newton-Raphson
// in every increment, and bisection of an increment that fails (up to a configured depth).
//
// Per increment T_a -> T_b: the prescribed motions are advanced by their change over the increment
// (rotations as spins about the global axes), then Newton iterates on the free dofs with the
// consistent tangent. Convergence needs both
//   ||r_k|| <= "Residual Tolerance" * max(||r_0||, ||T f_ext||, ||reactions||)  and
//   ||du_k|| <= "Increment Tolerance" * ||accumulated increment of the step||,
// where each test also passes at its round-off floor when the other one holds: a residual that
// stagnates while the increment test holds (then ||r|| <= ||K|| ||du|| is negligible), and an
// increment that stopped falling (not below half the one before) within sqrt(Increment Tolerance)
// of the step's motion while the residual test holds (in a short step the floor of ||du||, K^-1
// times the residual's, can lie above the increment test). A failure on Maximum Iterations names
// the test that failed, with both norms and their thresholds.
// Step bound: a contribution may shorten a Newton step (a contact spring open at the iterate that the
// full step would close: the step ends just past its first touch, so the next tangent holds its
// stiffness); the full step's norm still decides convergence. This is what lets stiff penalties
// (eps_N 1e6..1e8) pass first contact.
// Line search (optional, "Line Search" Backtracking): when an iterate's residual is not below
// (1 - 1e-4 alpha) times the last one's, Newton returns to the last iterate and tries half the step,
// up to "Maximum Backtracks" times (then it goes on from the shortest step tried).
// An increment fails on the iteration limit, a non-finite or exploding residual, or a failed linear
// solve; it is then halved, up to "Maximum Step Cuts" levels, and after two converged pieces the step
// is doubled again (never beyond the configured increment); steps.csv gives each step's cut level.
// If a piece fails at the deepest level the run stops: every converged step's output stays, and the
// run is reported incomplete.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Teuchos_StackedTimer.hpp>

#include "Assembler.hpp"
#include "Checkpoint.hpp"
#include "LinearSolver.hpp"
#include "Model.hpp"
#include "Parameters.hpp"
#include "linalg/SerialLu.hpp"

namespace bc::core {

struct NewtonIterate {
  double residualNorm = 0.0;
  double incrementNorm = 0.0;  // of the increment solved at this iterate (0 on the last one)
  int linearIterations = 0;
  double linearResidual = 0.0;
};

struct StepReport {
  int step = 0;  // counter of converged (sub)steps, from 1
  double T = 0.0;  // load factor reached
  int cutLevel = 0;  // 0 for a configured increment, k for a piece of a k-times halved one
  int iterations = 0;  // Newton iterations (linear solves), over all passes
  int backtracks = 0;  // line-search step halvings, over all iterations
  int stalls = 0;  // Newton solves that stalled and went on with backtracking (When Stalled)
  int boundedSteps = 0;  // Newton steps shortened because a contact would close within them
  int coupledSteps = 0;  // Newton steps that moved a contribution's estimates too (Physics::coupleStep)
  int passes = 1;  // Newton solves of the increment (augmentation / active-set passes)
  std::vector<NewtonIterate> history;
};

struct RunReport {
  bool completed = false;
  int steps = 0;
  int newtonIterations = 0;
  double lastT = 0.0;
  std::string failure;  // cause, when not completed
  std::vector<std::string> warnings;  // what the contributions could not model (Contribution::warnings)
  int interrupted = 0;  // the signal that stopped the run (0: none)
};

enum class LineSearch { None, Backtracking, WhenStalled };

struct SolverSettings {
  std::vector<double> loadFactors;  // increasing, ending at 1
  int maxStepCuts = 5;
  int maxIterations = 25;
  double residualTolerance = 1e-9;
  double incrementTolerance = 1e-8;
  double divergenceFactor = 1e10;  // ||r|| above this times the reference is divergence
  bool printIterations = false;  // one line per Newton iteration on rank 0
  bool printCuts = true;  // one line per step cut on rank 0
  bool extrapolate = true;  // predictor: the free dofs continue the last step's increment
  LineSearch lineSearch = LineSearch::WhenStalled;  // backtracking on ||r||
  int maxBacktracks = 8;
};

const ParameterSpec& loadSteppingSpec();
const ParameterSpec& newtonSpec();
// Reads validated "Load Stepping" and "Nonlinear Solver" sublists.
SolverSettings readSolverSettings(const Teuchos::ParameterList& stepping, const Teuchos::ParameterList& newton);

class StaticSolver {
 public:
  using StepCallback = std::function<void(const StepReport&, const State&, const Assembler&)>;

  StaticSolver(Teuchos::RCP<const Comm> comm, Model& model, SolverSettings settings, LinearSolver& linear,
               Teuchos::RCP<Teuchos::StackedTimer> timer = Teuchos::null);

  // Runs the increments (from the start, or from where loadCheckpoint left); `onStep` is called on
  // every rank after each converged (sub)step. A signal (Faults.hpp) stops it between Newton
  // iterations with the last converged step committed (RunReport::interrupted).
  RunReport run(const StepCallback& onStep);
  // The complete solver state after the last converged step, and its restoration (with every
  // contribution's history); the next run() continues from there.
  void saveCheckpoint(CheckpointOut& out) const;
  void loadCheckpoint(CheckpointIn& in);
  const State& state() const { return committed_; }
  const RunReport& runReport() const { return run_; }
  // Newton iterations from `start` (converged at load factor Ta) to Tb, prescribed motions advanced
  // by their change; for convergence studies. Returns the history and the final state.
  StepReport iterateFrom(const State& start, double Ta, double Tb, State& result);
  Assembler& assembler() { return assembler_; }

 private:
  bool attempt(double Ta, double Tb, int cutLevel, StepReport& report, std::string& failure);
  bool increment(const StepCallback& onStep);
  bool newton(double Ta, double Tb, StepReport& report, std::string& failure, bool predict = false);
  // loadCheckpoint's parts: the counters and load-stepping position (and the load factors, which
  // must be the deck's); the reference geometry; the states and contributions; the checks that the
  // position is one the load stepping reaches, and that the states hold the prescribed motions.
  void readProgress(CheckpointIn& in);
  void readReference(CheckpointIn& in) const;
  void readStates(CheckpointIn& in);
  void checkProgress(CheckpointIn& in) const;
  void checkPrescribed(CheckpointIn& in) const;
  // One Newton solve's state and steps (StaticSolver.cpp).
  struct Newton;

  Teuchos::RCP<const Comm> comm_;
  Model& model_;
  SolverSettings settings_;
  LinearSolver& linear_;
  Teuchos::RCP<Teuchos::StackedTimer> timer_;
  Assembler assembler_;
  double modelSize_ = 0.0;  // largest distance of a reference node from the origin [length]
  State committed_, trial_;
  State previous_;  // the converged state before committed_ (for the predictor)
  double previousT_ = -1.0, committedT_ = 0.0;  // their load factors; previousT_ < 0: none yet
  bool graphStale_ = false;
  // The model's response to loads (Physics::useResponse): on one rank from Newton's own tangent at
  // trial_, factored here once more (refactored while the graph's generation is the same); else
  // assembled and factored anew on each rank (modelResponse).
  ModelResponse response(const State& state, const std::vector<SparseLoad>& rows,
                         const std::vector<SparseLoad>& columns);
  std::unique_ptr<SerialLu> responseLu_;
  int responseGeneration_ = -1;
  // Where the load stepping stands: the configured increment, the load factor reached within it, its
  // cut level and the converged pieces at that level.
  struct Progress {
    int increment = 0;
    double T = 0.0;
    int level = 0;
    int converged = 0;
  } progress_;
  RunReport run_;
};

}  // namespace bc::core
