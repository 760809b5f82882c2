#include "StaticSolver.hpp"

#include "Compliance.hpp"

#include <climits>
#include <cmath>
#include <map>
#include <iomanip>
#include <iterator>
#include <sstream>

#include "Checkpoint.hpp"
#include "Faults.hpp"
#include "ScopedTimer.hpp"
#include "linalg/SerialKlu.hpp"

#include <iterator>

#include <Teuchos_Array.hpp>

namespace bc::core {

const ParameterSpec& loadSteppingSpec() {
  static const ParameterSpec spec = [] {
    ParameterSpec s;
    s.add("Number of Increments", 10, "equal increments of the load factor T from 0 to 1", wholeBetween(1, 10000000),
          "1 to 1e7");
    const double factors[] = {0.25, 0.5, 1.0};  // the reference's example
    s.addOptional("Load Factors", Teuchos::Array<double>(std::begin(factors), std::end(factors)),
                  "explicit increasing list of T values ending at 1 (non-uniform stepping); replaces "
                  "Number of Increments");
    s.add("Maximum Step Cuts", 5, "how many times a failing increment may be halved", wholeBetween(0, 30), "0 to 30");
    return s;
  }();
  return spec;
}

const ParameterSpec& newtonSpec() {
  static const ParameterSpec spec = [] {
    ParameterSpec s;
    s.add("Maximum Iterations", 25, "Newton iterations allowed per increment", wholeBetween(1, 100000), "1 to 1e5");
    s.add("Residual Tolerance", 1e-9,
          "converged when ||r|| <= this * max(first residual of the step, ||T f_ext||, ||reactions||)",
          inRange(0.0, 1.0), "in (0, 1]");
    s.add("Increment Tolerance", 1e-8, "and when ||du|| <= this * ||accumulated increment of the step|| (nodal dofs)",
          inRange(0.0, 1.0), "in (0, 1]");
    s.add("Print Iterations", false, "print ||r|| and ||du|| of every Newton iteration on rank 0");
    s.addChoice("Predictor", "Extrapolate", {"Extrapolate", "None"},
                "start of each increment's Newton iterations: \"Extrapolate\" continues the last converged "
                "increment (scaled to this one) on the free dofs; \"None\" starts from the last converged state");
    s.addChoice("Line Search", "When Stalled", {"When Stalled", "None", "Backtracking"},
                "\"None\": full Newton steps (but a contact that would close within a step shortens it); "
                "\"Backtracking\": an iterate whose residual did not fall is replaced by one with half the step, up "
                "to Maximum Backtracks times (large-rotation beam paths are not monotone in ||r||: there it costs "
                "iterations); \"When Stalled\": full steps while ||r|| keeps falling, backtracking for the rest of "
                "the Newton solve once its lowest ||r|| has not halved in 4 iterations (e.g. a slip direction that "
                "flips from one iterate to the next makes full-step Newton cycle)");
    s.add("Maximum Backtracks", 8, "step halvings allowed per Newton iteration (Line Search)", wholeBetween(1, 50),
          "1 to 50");
    s.add("Divergence Factor", 1e10, "an iterate whose residual exceeds this times the reference diverged", positive(),
          "> 0");
    return s;
  }();
  return spec;
}

SolverSettings readSolverSettings(const Teuchos::ParameterList& stepping, const Teuchos::ParameterList& newton) {
  SolverSettings s;
  if (stepping.isParameter("Load Factors")) {
    const auto& a = stepping.get<Teuchos::Array<double>>("Load Factors");
    double prev = 0.0;
    for (double t : a) {
      if (!(t > prev) || t > 1.0)
        throw InputError(
            "parameter \"Load Stepping/Load Factors\": values must increase strictly from 0 and not "
            "exceed 1");
      s.loadFactors.push_back(t);
      prev = t;
    }
    if (s.loadFactors.empty() || std::abs(s.loadFactors.back() - 1.0) > 1e-14)
      throw InputError("parameter \"Load Stepping/Load Factors\": the last value must be 1");
    s.loadFactors.back() = 1.0;
  } else {
    const int n = stepping.get<int>("Number of Increments");
    for (int k = 1; k <= n; ++k) s.loadFactors.push_back(double(k) / n);
  }
  s.maxStepCuts = stepping.get<int>("Maximum Step Cuts");
  s.maxIterations = newton.get<int>("Maximum Iterations");
  s.residualTolerance = newton.get<double>("Residual Tolerance");
  s.incrementTolerance = newton.get<double>("Increment Tolerance");
  s.divergenceFactor = newton.get<double>("Divergence Factor");
  s.printIterations = newton.get<bool>("Print Iterations");
  s.extrapolate = newton.get<std::string>("Predictor") == "Extrapolate";
  const std::string search = newton.get<std::string>("Line Search");
  s.lineSearch = search == "Backtracking" ? LineSearch::Backtracking
                 : search == "None"       ? LineSearch::None
                                          : LineSearch::WhenStalled;
  s.maxBacktracks = newton.get<int>("Maximum Backtracks");
  return s;
}

StaticSolver::StaticSolver(Teuchos::RCP<const Comm> comm, Model& model, SolverSettings settings, LinearSolver& linear,
                           Teuchos::RCP<Teuchos::StackedTimer> timer)
    : comm_(comm),
      model_(model),
      settings_(std::move(settings)),
      linear_(linear),
      timer_(timer),
      assembler_(comm, model) {
  committed_ = model_.initial;
  trial_ = committed_;
  for (const auto& x : model_.initial.reference) modelSize_ = std::max(modelSize_, std::sqrt(dot(x, x)));
  graphStale_ = true;  // built at the first iteration, from the state being solved
  assembler_.setTimer(timer_);
  linear_.setTimer(timer_);
  for (const auto& c : model_.contributions) {
    const Physics* self = c.get();
    c->useCompliance([this, self](const State& state, const std::vector<SparseLoad>& loads) {
      return structureCompliance(model_, *self, state, loads);
    });
    c->useResponse([this](const State& state, const std::vector<SparseLoad>& rows,
                          const std::vector<SparseLoad>& columns) { return response(state, rows, columns); });
    c->useCommunicator(comm_);
  }
}

ModelResponse StaticSolver::response(const State& state, const std::vector<SparseLoad>& rows,
                                     const std::vector<SparseLoad>& columns) {
  // (Contributions ask from within Newton's step, after its solve: the matrix is the tangent at trial_.)
  if (comm_->getSize() > 1 || &state != &trial_ || assembler_.matrix().is_null())
    return modelResponse(model_, state, rows, columns);
  const Matrix& K = *assembler_.matrix();
  if (!responseLu_) responseLu_ = std::make_unique<SerialKlu>();
  // Refactored with the last pivot order while the graph is the same; a solve that fails its checks
  // with those pivots is done again with a fresh factorization (as LinearSolver does).
  for (bool refactor : {responseGeneration_ == assembler_.generation(), false}) {
    try {
      responseLu_->factor(K, refactor);
      responseGeneration_ = assembler_.generation();
      return factoredResponse(K, assembler_.constrainedDofs(), *responseLu_, rows, columns);
    } catch (const std::runtime_error& e) {
      responseGeneration_ = -1;
      if (!refactor) throw std::runtime_error(std::string("the model's tangent is singular: ") + e.what());
    }
  }
  throw std::logic_error("unreachable");
}

namespace {
// The 2-norm of a few numbers (reactions, loads) without underflow or overflow (scaledNorm2).
double safeNorm2(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  if (!(m > 0.0) || !std::isfinite(m)) return m;
  double s = 0.0;
  for (double x : v) s += (x / m) * (x / m);
  return m * std::sqrt(s);
}

// The six rigid-body modes of the nodes at the state's positions (translations along x, y, z and
// rotations about axes through the nodes' centroid), on the owned dofs of `map`; zero on any dof
// beyond the nodal ones.
Teuchos::RCP<MultiVector> rigidBodyModes(const State& s, const Teuchos::RCP<const Map>& map) {
  auto modes = Teuchos::rcp(new MultiVector(map, 6));
  Vec3d centre{};
  for (const Vec3d& x : s.position) centre = centre + x;
  if (s.numNodes() > 0) centre = (1.0 / s.numNodes()) * centre;
  const GlobalDof nodal = GlobalDof(kDofsPerNode) * s.numNodes();
  for (std::size_t i = 0; i < map->getNodeNumElements(); ++i) {
    const GlobalDof g = map->getGlobalElement(static_cast<LO>(i));
    if (g >= nodal) continue;
    const int node = static_cast<int>(g / kDofsPerNode), c = static_cast<int>(g % kDofsPerNode);
    // Translation c (c < 3) or rotation c - 3 (its spin): 1 at dof c.
    modes->replaceLocalValue(static_cast<LO>(i), c, 1.0);
    if (c >= 3) continue;
    // A rotation about axis a moves the node by e_a x r.
    const Vec3d r = s.position[node] - centre;
    for (int a = 0; a < 3; ++a) {
      Vec3d e{};
      e[a] = 1.0;
      modes->replaceLocalValue(static_cast<LO>(i), 3 + a, math::cross(e, r)[c]);
    }
  }
  return modes;
}
}  // namespace

RunReport StaticSolver::run(const StepCallback& onStep) {
  const int n = static_cast<int>(settings_.loadFactors.size());
  try {
    while (progress_.increment < n) {
      if (!increment(onStep)) return run_;
    }
  } catch (const Interrupted& e) {
    // Stopped between Newton iterations: the last converged step stays the committed one.
    for (auto& c : model_.contributions) c->restoreStep();
    graphStale_ = true;
    run_.interrupted = e.signal();
    run_.failure = e.what();
    return run_;
  }
  run_.completed = true;
  return run_;
}

bool StaticSolver::increment(const StepCallback& onStep) {
  // Pieces of (Tb - Ta) / 2^level: a failed piece is halved (level + 1), two converged pieces in a
  // row double the next one (level - 1), so a hard moment costs small steps only while it lasts.
  // Where the increment stands (T, level, converged pieces) is kept in progress_, so a checkpoint
  // written after any piece resumes the same sequence.
  const int i = progress_.increment;
  const double Ta = i == 0 ? 0.0 : settings_.loadFactors[i - 1], Tb = settings_.loadFactors[i];
  Progress& at = progress_;
  while (at.T < Tb) {
    const double piece = (Tb - Ta) / double(1 << at.level);
    const double Tn = (Tb - at.T) <= 1.000001 * piece ? Tb : at.T + piece;
    std::string failure;
    StepReport report;
    if (attempt(at.T, Tn, at.level, report, failure)) {
      at.T = Tn;
      if (++at.converged >= 2 && at.level > 0) {
        --at.level;
        at.converged = 0;
      }
      if (Tn == Tb) at = Progress{i + 1, Tb, 0, 0};
      {
        ScopedTimer output(timer_, "Output");
        onStep(report, committed_, assembler_);
      }
      if (Tn == Tb) return true;
      continue;
    }
    at.converged = 0;
    if (at.level >= settings_.maxStepCuts) {
      std::ostringstream s;
      s << "increment T = " << at.T << " -> " << Tn << " did not converge after " << at.level
        << " step cuts (Maximum Step Cuts): " << failure;
      run_.failure = s.str();
      return false;
    }
    if (settings_.printCuts && comm_->getRank() == 0)
      std::printf("  cutting increment T = %.6g -> %.6g (%s)\n", at.T, Tn, failure.c_str());
    ++at.level;
  }
  progress_ = Progress{i + 1, Tb, 0, 0};
  return true;
}

bool StaticSolver::attempt(double Ta, double Tb, int cutLevel, StepReport& report, std::string& failure) {
  trial_ = committed_;
  if (newton(Ta, Tb, report, failure, true)) {
    previous_ = committed_;
    previousT_ = committedT_;
    committedT_ = Tb;
    committed_ = trial_;
    committed_.updateRotationVectors();
    for (auto& c : model_.contributions) c->commitStep(committed_);
    for (auto& c : model_.contributions) c->stepConverged(committed_, Tb);
    report.step = ++run_.steps;
    report.T = Tb;
    report.cutLevel = cutLevel;
    run_.newtonIterations += report.iterations;
    run_.lastT = Tb;
    return true;
  }
  for (auto& c : model_.contributions) c->restoreStep();
  graphStale_ = true;  // the restored contributions may couple other dofs than the last graph
  return false;
}

void StaticSolver::saveCheckpoint(CheckpointOut& out) const {
  out.label("run").integer(run_.steps).integer(run_.newtonIterations).real(run_.lastT);
  out.label("progress")
      .integer(progress_.increment)
      .real(progress_.T)
      .integer(progress_.level)
      .integer(progress_.converged);
  out.label("load-factors").integer(static_cast<long long>(settings_.loadFactors.size()));
  for (double t : settings_.loadFactors) out.real(t);
  // The model's reference geometry: a restart on a model whose nodes are elsewhere is refused.
  out.label("reference").integer(model_.initial.numNodes());
  for (int n = 0; n < model_.initial.numNodes(); ++n) {
    out.label("at").integer(n);
    for (double v : model_.initial.reference[n].v) out.real(v);
  }
  out.label("committed").real(committedT_);
  out.state(committed_);
  out.label("previous").real(previousT_);
  out.state(previousT_ >= 0.0 ? previous_ : committed_);
  for (const auto& c : model_.contributions) {
    out.label("contribution").word(c->name());
    c->saveCommitted(out);
  }
  out.label("end");
}

namespace {
// A counter of a checkpoint: a whole number from 0 up.
int readCount(CheckpointIn& in, const std::string& what) {
  const long long v = in.integer();
  if (v < 0 || v > INT_MAX) in.fail("its " + what + " is " + std::to_string(v) + " (it must be 0 or more)");
  return static_cast<int>(v);
}
}  // namespace

void StaticSolver::loadCheckpoint(CheckpointIn& in) {
  readProgress(in);
  readReference(in);
  readStates(in);
  checkProgress(in);
  checkPrescribed(in);
  trial_ = committed_;
  graphStale_ = true;
  if (run_.steps > 0)
    for (auto& c : model_.contributions) c->stepConverged(committed_, committedT_);
}

void StaticSolver::readProgress(CheckpointIn& in) {
  in.label("run");
  run_ = RunReport{};
  run_.steps = readCount(in, "step counter");
  run_.newtonIterations = readCount(in, "Newton iteration counter");
  run_.lastT = in.real();
  in.label("progress");
  progress_.increment = readCount(in, "configured increment");
  progress_.T = in.real();
  progress_.level = readCount(in, "cut level");
  progress_.converged = readCount(in, "count of converged pieces");
  in.label("load-factors");
  const int n = static_cast<int>(settings_.loadFactors.size());
  if (in.integer() != n) in.fail("the load stepping differs");
  for (double t : settings_.loadFactors)
    if (in.real() != t) in.fail("the load stepping differs");
}

// The model's reference geometry: a restart on a model whose nodes are elsewhere is refused.
void StaticSolver::readReference(CheckpointIn& in) const {
  in.label("reference");
  const long long nodes = in.integer();
  if (nodes != model_.initial.numNodes())
    in.fail("it is for a model of " + std::to_string(nodes) + " nodes, the deck's has " +
            std::to_string(model_.initial.numNodes()));
  for (int k = 0; k < model_.initial.numNodes(); ++k) {
    in.label("at");
    if (in.integer() != k) in.fail("its reference nodes are out of order (it is damaged)");
    Vec3d X;
    for (double& v : X.v) v = in.real();
    const Vec3d& model = model_.initial.reference[k];
    if (X[0] != model[0] || X[1] != model[1] || X[2] != model[2])
      in.fail("node " + std::to_string(k) + " is at (" + shortest(X[0]) + ", " + shortest(X[1]) + ", " +
              shortest(X[2]) + ") in its reference geometry, at (" + shortest(model[0]) + ", " + shortest(model[1]) +
              ", " + shortest(model[2]) + ") in the model's");
  }
}

// The committed and previous states, and every contribution's history.
void StaticSolver::readStates(CheckpointIn& in) {
  in.label("committed");
  committedT_ = in.real();
  committed_ = model_.initial;
  in.state(committed_);
  in.label("previous");
  previousT_ = in.real();
  previous_ = model_.initial;
  in.state(previous_);
  for (auto& c : model_.contributions) {
    in.label("contribution");
    if (in.word() != CheckpointOut::token(c->name())) in.fail("its contributions differ from the deck's");
    c->loadCommitted(in, committed_);
  }
  in.label("end");
}

void StaticSolver::checkProgress(CheckpointIn& in) const {
  // The load-stepping position is one that increment() reaches. In configured increment i (T_a -> T_b)
  // at cut level L the pieces are (T_b - T_a) / 2^L; a piece that converges adds one (or ends the
  // increment when T_b is within it), one that fails is halved. So T = T_a + k (T_b - T_a) / 2^C with
  // 0 <= k < 2^C, C = Maximum Step Cuts (to the round-off of adding the pieces up: 1e-6 of 2^-C of the
  // increment, or 1e-12 T_b, about 4500 additions' rounding, when that is larger), and at level 0
  // T = T_a (its one piece ends the increment); after the last increment T = 1. Converged pieces count
  // to 2 at most and are reset then, and at level 0 the first ends the increment.
  const int n = static_cast<int>(settings_.loadFactors.size());
  const Progress& at = progress_;
  const std::string position = "in configured increment " + std::to_string(at.increment + 1) + " of " +
                               std::to_string(n) + " at cut level " + std::to_string(at.level);
  if (at.increment > n)
    in.fail("its configured increment " + std::to_string(at.increment + 1) + " is beyond the " + std::to_string(n) +
            " of the load stepping");
  if (at.level > settings_.maxStepCuts)
    in.fail("its cut level " + std::to_string(at.level) + " is beyond Maximum Step Cuts (" +
            std::to_string(settings_.maxStepCuts) + ")");
  if (at.converged > (at.level > 0 ? 1 : 0))
    in.fail("its count of converged pieces (" + std::to_string(at.converged) +
            ") is not one the load stepping reaches " + position);
  if (at.increment == n) {
    if (at.T != 1.0 || at.level != 0)
      in.fail("its load stepping is finished but T = " + shortest(at.T) + " (it must be 1)");
  } else {
    const double Ta = at.increment == 0 ? 0.0 : settings_.loadFactors[at.increment - 1];
    const double Tb = settings_.loadFactors[at.increment];
    const double finest = (Tb - Ta) / double(1 << settings_.maxStepCuts);
    const double k = std::round((at.T - Ta) / finest);
    if (!(k >= 0.0 && k < double(1 << settings_.maxStepCuts) && (at.level > 0 || k == 0.0) &&
          std::abs(at.T - (Ta + k * finest)) <= std::max(1e-6 * finest, 1e-12 * Tb)))
      in.fail("its load factor T = " + shortest(at.T) + " is not one the load stepping reaches " + position + " (T " +
              shortest(Ta) + " -> " + shortest(Tb) + " in multiples of " + shortest(finest) + ")");
  }
  // The converged state is the position's, and the state before it the previous step's.
  if (committedT_ != at.T || run_.lastT != at.T)
    in.fail("its load factors disagree: the committed state's T = " + shortest(committedT_) + ", the last step's " +
            shortest(run_.lastT) + ", the load stepping's " + shortest(at.T));
  if (run_.steps == 0 ? (at.T != 0.0 || previousT_ != -1.0)
                      : !(previousT_ >= 0.0 && previousT_ < committedT_ && (run_.steps > 1 || previousT_ == 0.0)))
    in.fail("its " + std::to_string(run_.steps) + " steps do not fit its load factors (T = " + shortest(committedT_) +
            ", the step before at T = " + shortest(previousT_) + ")");
  // Every configured increment before the position took a step at least, and so did a piece of this one.
  const bool inside = at.increment < n && at.T > (at.increment == 0 ? 0.0 : settings_.loadFactors[at.increment - 1]);
  if (run_.steps < at.increment + (inside ? 1 : 0))
    in.fail("its step counter (" + std::to_string(run_.steps) + ") is below the steps needed to reach T = " +
            shortest(at.T) + " (" + std::to_string(at.increment + (inside ? 1 : 0)) + ")");
}

void StaticSolver::checkPrescribed(CheckpointIn& in) const {
  // Prescribed translations: every step moves a supported node's fixed translation by
  // value (curve(T_b) - curve(T_a)) and nothing else does, so a state at T has it at
  // x_0 + value (curve(T) - curve(0)) (to the round-off of the steps' sum; 1e-9 of the model's size).
  // (node, translation) -> its support (the last one wins, as in newton()).
  std::map<std::pair<int, int>, const Support*> prescribed;
  for (const Support& sup : model_.supports)
    for (int node : sup.nodes)
      for (int k = 0; k < 3; ++k)
        if (sup.fixed[k]) prescribed[{node, k}] = &sup;
  const auto check = [&](const State& state, double T, const std::string& which) {
    for (const auto& [dof, sup] : prescribed) {
      const auto [node, k] = dof;
      const double expected = model_.initial.position[node][k] + sup->value[k] * (sup->curve(T) - sup->curve(0.0));
      if (!(std::abs(state.position[node][k] - expected) <= 1e-9 * (modelSize_ + std::abs(sup->value[k]))))
        in.fail(which + " has supported node " + std::to_string(node) + " at " + "xyz"[k] + " = " +
                shortest(state.position[node][k]) + ", where its support \"" + sup->name + "\" puts it at " +
                shortest(expected) + " (T = " + shortest(T) + ")");
    }
  };
  check(committed_, committedT_, "its converged state");
  if (previousT_ >= 0.0) check(previous_, previousT_, "its previous state");
}

StepReport StaticSolver::iterateFrom(const State& start, double Ta, double Tb, State& result) {
  StepReport report;
  graphStale_ = true;
  std::string failure;
  trial_ = start;
  newton(Ta, Tb, report, failure);
  result = trial_;
  trial_ = committed_;
  return report;
}

// One Newton solve of the increment Ta -> Tb on trial_: the state the iterations carry and their named
// steps (StaticSolver::newton is the loop over them).
struct StaticSolver::Newton {
  enum class Verdict { Iterate, Converged, NextPass, Failed };

  Newton(StaticSolver& solver, double ta, double tb, StepReport& r, std::string& f)
      : s(solver),
        settings(solver.settings_),
        Ta(ta),
        Tb(tb),
        report(r),
        failure(f),
        ndof(GlobalDof(kDofsPerNode) * solver.trial_.numNodes()),
        searching(settings.lineSearch == LineSearch::Backtracking) {}

  StaticSolver& s;
  const SolverSettings& settings;
  const double Ta, Tb;
  StepReport& report;
  std::string& failure;
  // Increments are measured on the nodal dofs only: extra unknowns (multipliers) are forces, and their
  // number may change from one iteration to the next.
  const GlobalDof ndof;
  std::vector<double> accumulated;  // the step's motion so far (nodal dofs)
  double stepNorm2 = 0.0;  // its squared norm
  Teuchos::RCP<Vector> x;
  double firstResidual = 0.0;
  int pass = 0, passStart = 0;  // a pass is one Newton solve of the increment
  // Line search: the iterate the last step left, that step, the fraction of it taken, and the
  // residual there.
  State lastIterate;
  std::vector<double> lastStep;
  double alpha = 1.0, lastResidual = 0.0;
  int backtracks = 0;
  // Whether this Newton solve backtracks (always, never, or from when it stalls: its lowest residual
  // `best` last halved at iteration `progressAt`).
  bool searching;
  double best = 0.0;
  int progressAt = 0;
  static constexpr int kStallIterations = 4;
  static constexpr double kCoupleBelow = 1e-2;  // coupleStep below this fraction of the solve's first residual
  // The iterate at hand: its number (overall and within the pass), whether its graph was rebuilt,
  // and its measures.
  int k = 0, kp = 0;
  bool rebuilt = false, likelyConverged = false, finite = true;
  double incrementScale = 0.0, rn = 0.0, reactionNorm = 0.0, loadNorm = 0.0, reference = 0.0;

  // Predictor: the nodal dofs continue the last converged increment, scaled to this one (the
  // rotations as the spin that took the previous rotation to the current one).
  std::vector<double> predict(bool wanted) const {
    std::vector<double> du(s.trial_.numDofs(), 0.0);
    if (!(wanted && settings.extrapolate && s.previousT_ >= 0.0 && s.committedT_ > s.previousT_ &&
          Ta == s.committedT_ && s.previous_.numNodes() == s.trial_.numNodes()))
      return du;
    const double ratio = (Tb - Ta) / (s.committedT_ - s.previousT_);
    for (int n = 0; n < s.trial_.numNodes(); ++n) {
      const Vec3d du_n = s.committed_.position[n] - s.previous_.position[n];
      const Vec3d w = math::logSO3(s.committed_.rotation[n] * math::transpose(s.previous_.rotation[n]));
      for (int d = 0; d < 3; ++d) {
        du[std::size_t(kDofsPerNode) * n + d] = ratio * du_n[d];
        du[std::size_t(kDofsPerNode) * n + 3 + d] = ratio * w[d];
      }
    }
    return du;
  }

  // The supports overwrite their prescribed dofs with their motion over the increment; the first
  // iterate is the predicted one.
  void prescribe(std::vector<double> du) {
    for (const Support& sup : s.model_.supports)
      for (int n : sup.nodes)
        for (int c = 0; c < 6; ++c)
          if (sup.fixed[c]) du[std::size_t(kDofsPerNode) * n + c] = sup.value[c] * (sup.curve(Tb) - sup.curve(Ta));
    for (double v : du) stepNorm2 += v * v;
    accumulated.assign(du.begin(), du.begin() + ndof);
    s.trial_.applyIncrement(du);
  }

  // The contact search of the contributions, and the graph rebuilt when they or the dofs ask.
  void prepare() {
    bool rebuild =
        s.graphStale_ || s.assembler_.ownedMap().is_null() ||
        static_cast<Tpetra::global_size_t>(s.trial_.numDofs()) != s.assembler_.ownedMap()->getGlobalNumElements();
    s.graphStale_ = false;
    {
      ScopedTimer search(s.timer_, "Contact Search");
      for (auto& c : s.model_.contributions) rebuild = c->prepareIteration(s.trial_) || rebuild;
    }
    if (rebuild) {
      ScopedTimer graph(s.timer_, "Graph Rebuild");
      s.assembler_.rebuild(s.trial_);
    }
    rebuilt = rebuild;
    if (x.is_null() || !x->getMap()->isSameAs(*s.assembler_.ownedMap()))
      x = Teuchos::rcp(new Vector(s.assembler_.ownedMap()));
  }

  // The residual (and the tangent unless this iterate is likely the solution) and its measures.
  // When the last increment was already below its tolerance this iterate is probably the solution:
  // its residual alone decides, and the tangent is formed only if another solve follows. The
  // increment is judged against the step's accumulated motion, or, in a step that barely moves
  // anything (an unloaded step), against round-off of the model's size: there a rotated beam's
  // residual sits at its round-off floor (about 1e-14) from the start, and no relative test passes.
  void assembleAndMeasure() {
    incrementScale = std::max(std::sqrt(stepNorm2), 1e-6 * s.modelSize_);
    likelyConverged = kp > 0 && report.history[k - 1].incrementNorm <= settings.incrementTolerance * incrementScale;
    {
      ScopedTimer assembly(s.timer_, "Assembly");
      s.assembler_.assemble(s.trial_, Tb, !likelyConverged);
    }
    rn = scaledNorm2(*s.assembler_.residual());
    // Every entry of the residual, reactions included, and every node's place and rotation must be
    // numbers: overflowing loads or prescribed motions (1e300) leave a state of infinities whose
    // residual can still measure 0 on the free dofs.
    finite = true;
    for (double v : s.assembler_.fullResidual()) finite = finite && std::isfinite(v);
    for (int n = 0; finite && n < s.trial_.numNodes(); ++n)
      for (int i = 0; i < 3; ++i) {
        finite = finite && std::isfinite(s.trial_.position[n][i]);
        for (int j = 0; j < 3; ++j) finite = finite && std::isfinite(s.trial_.rotation[n](i, j));
      }
    std::vector<double> entries;
    for (GlobalDof g : s.assembler_.constrainedDofs()) entries.push_back(s.assembler_.fullResidual()[g]);
    reactionNorm = safeNorm2(entries);
    entries.clear();
    for (const NodalLoad& l : s.model_.loads)
      for (double v : l.value) entries.push_back(l.curve(Tb) * v);
    loadNorm = safeNorm2(entries);
    if (kp == 0) {
      firstResidual = rn;
      best = rn;
      progressAt = 0;
      searching = settings.lineSearch == LineSearch::Backtracking;
    } else if (rn < 0.5 * best) {
      best = rn;
      progressAt = kp;
    }
    reference = std::max({firstResidual, reactionNorm, loadNorm});
  }

  // Backtracking: the residual did not fall (by 1e-4 of the step fraction), so go back to the last
  // iterate and take half the step. Not once the Newton step was already below its tolerance (the
  // residual may then sit at its round-off floor). The recorded increment norm stays the full Newton
  // step's, so a short step never passes for convergence. Returns whether it backtracked.
  bool lineSearch() {
    if (!(searching && kp > 0 && !likelyConverged && !lastStep.empty() && backtracks < settings.maxBacktracks &&
          std::isfinite(lastResidual) && !(rn <= (1.0 - 1e-4 * alpha) * lastResidual) &&
          rn > settings.residualTolerance * reference))
      return false;
    const double shorter = 0.5 * alpha;
    s.trial_ = lastIterate;
    for (auto& c : s.model_.contributions) c->returnToIterate();
    s.graphStale_ = s.graphStale_ || rebuilt;  // the graph may belong to the rejected iterate
    std::vector<double> step(lastStep.size());
    for (std::size_t i = 0; i < step.size(); ++i) step[i] = shorter * lastStep[i];
    stepNorm2 = 0.0;
    for (GlobalDof g = 0; g < ndof; ++g) {
      accumulated[g] -= (alpha - shorter) * lastStep[g];
      stepNorm2 += accumulated[g] * accumulated[g];
    }
    s.trial_.applyIncrement(step);
    if (settings.printIterations && s.comm_->getRank() == 0)
      std::printf("    T %.6g  iteration %2d  ||r|| %.3e  rejected, step x %.4g\n", Tb, k, rn, shorter);
    alpha = shorter;
    ++backtracks;
    ++report.backtracks;
    return true;
  }

  // The iterate in the history (and printed).
  void record() {
    if (settings.printIterations && s.comm_->getRank() == 0) {
      std::printf("    T %.6g  iteration %2d  ||r|| %.3e", Tb, k, rn);
      if (k > 0) std::printf("  ||du|| %.3e", report.history[k - 1].incrementNorm);
      std::printf("\n");
    }
    NewtonIterate it;
    it.residualNorm = rn;
    report.history.push_back(it);
  }

  // Whether the iterate has converged. At k = 0 nothing has been solved yet: accept only a state
  // already in equilibrium with respect to the loads and reactions (e.g. an increment that changes
  // nothing). After that each test may meet the other's round-off floor:
  // - the residual cannot fall below its floor (about eps * EA per element): once the increments
  //   are negligible, a residual that stopped decreasing has reached that floor;
  // - the increment cannot fall below K^-1 times that floor either. The residual test is relative to
  //   the whole load (reactions, loads), the increment test to the step's motion, which is small in a
  //   cut step: there the floor of ||du|| can lie above its tolerance with the residual at its own
  //   floor, and cutting further only makes it worse. So with the residual test met, an increment
  //   that stopped falling (not below half the one before) while within sqrt(Increment Tolerance) of
  //   the step's motion is at its floor. A Newton iterate that still converges halves its increment
  //   at every iteration; one cycling between active sets moves by far more than that bound.
  struct Tests {
    bool residual = false, increment = false, residualFloor = false, incrementFloor = false;
    bool met() const { return (residual || residualFloor) && (increment || incrementFloor); }
  };
  Tests tests() const {
    Tests t;
    if (kp == 0) {
      // (A pass after the first follows a change the contributions made, an active set or estimates:
      // it solves at least once. Accepted unsolved, a new multiplier keeps its start value 0 while its
      // row, a gap, is far below a residual measured in forces, and the next pass sees the same state.)
      if (pass > 0) return t;
      t.residual = t.increment = rn == 0.0 || rn <= settings.residualTolerance * std::max(reactionNorm, loadNorm);
      return t;
    }
    const double duLast = report.history[k - 1].incrementNorm;
    t.residual = rn <= settings.residualTolerance * reference;
    t.increment = duLast <= settings.incrementTolerance * incrementScale;
    // (A floor is where the residual stopped falling, not where it rose: a residual that jumped up
    // at a negligible nodal increment, multipliers that moved at a fixed place, is no floor. Its
    // level is the internal forces' round-off, which can lie far above Residual Tolerance where a
    // light load makes the reference small: 0.17 of it early in Example 1 with 20 elements.)
    const double rnLast = report.history[k - 1].residualNorm;
    t.residualFloor = t.increment && kp >= 2 && rn > 0.5 * rnLast && rn <= 2.0 * rnLast;
    t.incrementFloor = t.residual && kp >= 2 && duLast > 0.5 * report.history[k - 2].incrementNorm &&
                       duLast <= std::sqrt(settings.incrementTolerance) * incrementScale;
    return t;
  }
  bool converged() const { return tests().met(); }

  // What the iterate means: a failure (a residual not finite, divergence, the iteration limit), the
  // increment converged, another pass (the contributions ask for another solve of the increment:
  // augmentation, active set), or another iteration.
  Verdict verdict() {
    if (!std::isfinite(rn)) return fail("the residual is not finite");
    if (!finite)
      return fail(
          "the state is not finite (a reaction, a node's place or rotation overflowed: loads or prescribed "
          "motions too large for double precision?)");
    if (kp > 0 && rn > settings.divergenceFactor * std::max(reference, 1e-300))
      return fail("Newton diverged (residual above Divergence Factor times its reference)");
    if (converged()) {
      bool accepted = true;
      try {
        ScopedTimer activeSet(s.timer_, "Active Set");
        for (auto& c : s.model_.contributions) accepted = c->acceptSolution(s.trial_) && accepted;
      } catch (const std::runtime_error& e) {
        return fail(e.what());
      }
      ++pass;
      if (accepted) return Verdict::Converged;
      passStart = k + 1;
      return Verdict::NextPass;
    }
    if (kp < settings.maxIterations) return Verdict::Iterate;
    std::ostringstream m;
    const Tests t = tests();
    const double duLast = kp > 0 ? report.history[k - 1].incrementNorm : 0.0;
    m << std::setprecision(3) << "no convergence in " << settings.maxIterations
      << " Newton iterations (Maximum Iterations): the residual test " << (t.residual ? "holds" : "fails")
      << " (||r|| = " << rn << " against Residual Tolerance x " << reference << " = "
      << settings.residualTolerance * reference << "), the increment test " << (t.increment ? "holds" : "fails")
      << " (||du|| = " << duLast << " against Increment Tolerance x " << incrementScale << " = "
      << settings.incrementTolerance * incrementScale << ")";
    for (auto& c : s.model_.contributions) {
      const std::string hint = c->failureHint(*s.comm_);
      if (!hint.empty()) m << "; " << hint;
    }
    return fail(m.str());
  }
  Verdict fail(const std::string& why) {
    failure = why;
    return Verdict::Failed;
  }

  // The Newton step: the tangent (when the iterate was taken as likely converged it was not formed),
  // the linear solve, and the step shortened to the contributions' bound; false (with `failure`)
  // when the solve fails. Returns the step in `inc` and the full step's norm in the history.
  bool solve(std::vector<double>& inc, double& bound) {
    if (likelyConverged) {
      ScopedTimer assembly(s.timer_, "Assembly");
      s.assembler_.assemble(s.trial_, Tb, true);
    }
    Vector rhs(s.assembler_.ownedMap());
    rhs.update(-1.0, *s.assembler_.residual(), 0.0);
    if (s.linear_.wantsNearNullSpace()) {
      if (!s.trial_.extra.empty()) {
        failure = s.linear_.name() + " preconditions matrices of nodal dofs only; this one has " +
                  std::to_string(s.trial_.extra.size()) +
                  " multiplier rows (Lagrange Multiplier at points; Lagrange Multiplier, Augmented Lagrange and "
                  "Penalty with Line Springs = Nodes on the lines of line contact): use Penalty with Line Springs = "
                  "Gauss Points with it, or Linear Solver/Type = Direct";
        return false;
      }
      s.linear_.setNearNullSpace(rigidBodyModes(s.trial_, s.assembler_.ownedMap()));
    }
    SolveReport lin;
    {
      ScopedTimer linearSolve(s.timer_, "Linear Solve");
      try {
        if (faultInjection()) collectively(*s.comm_, [] { injectFault("solve"); });
        lin = s.linear_.solve(s.assembler_.matrix(), rhs, *x);
      } catch (const LinearSolveError& e) {
        failure = e.what();
        return false;
      }
    }
    inc = s.assembler_.gatherToAll(*x);
    // The largest fraction of the step the contributions allow.
    const auto boundStep = [&] {
      ScopedTimer stepBound(s.timer_, "Step Bound");
      for (auto& c : s.model_.contributions) bound = std::min(bound, c->stepBound(s.trial_, inc));
    };
    bound = 1.0;
    boundStep();
    // Near the solution, contributions may move the estimates they keep with the step (coupleStep):
    // the step is then Newton's on the motion and the estimates together, and its norm counts both.
    {
      ScopedTimer coupledTimer(s.timer_, "Coupled Step");
      // (Not on the step after which When Stalled starts backtracking: the iterate it keeps would
      // carry the moved estimates with the unmoved motion.)
      const bool stalls = settings.lineSearch == LineSearch::WhenStalled && kp - progressAt >= kStallIterations;
      const bool near = bound >= 1.0 && !searching && !stalls && kp >= 1 && rn <= kCoupleBelow * firstResidual;
      bool coupled = false;
      for (auto& c : s.model_.contributions)
        if (c->coupleStep(s.trial_, inc, near)) {
          ++report.coupledSteps;
          coupled = true;
        }
      // The coupled step is bounded as Newton's is: a contact it would close ends it.
      if (coupled) boundStep();
    }
    if (faultAt("step") && !inc.empty()) inc[0] += 1e-3;
    if (!sameOnEveryRank(inc))
      throw std::runtime_error(
          "the ranks computed different Newton steps (a contribution's step depends on the rank: a "
          "strategy or plug-in that reads rank-local data where every rank must agree); stopped, as the "
          "ranks would otherwise go on from different states");
    double n2 = 0.0;
    for (GlobalDof g = 0; g < ndof; ++g) n2 += inc[g] * inc[g];  // the full Newton step decides convergence
    if (bound < 1.0) {
      for (double& v : inc) v *= bound;
      ++report.boundedSteps;
    }
    report.history[k].incrementNorm = std::sqrt(n2);
    report.history[k].linearIterations = lin.iterations;
    report.history[k].linearResidual = lin.relativeResidual;
    return true;
  }

  // Whether every rank holds the same step: a weighted sum of its entries, its least and largest
  // over the ranks equal to 1e-12 of its scale (each rank gathers the same solution, and the
  // contributions' changes to it must not depend on the rank).
  bool sameOnEveryRank(const std::vector<double>& inc) const {
    if (s.comm_->getSize() < 2) return true;
    double sum[2] = {0.0, 0.0};
    for (std::size_t g = 0; g < inc.size(); ++g) {
      sum[0] += inc[g] * double(1 + g % 7);
      sum[1] += std::abs(inc[g]);
    }
    const double local[2] = {sum[0], -sum[0]};
    double least[2] = {0.0, 0.0};
    Teuchos::reduceAll(*s.comm_, Teuchos::REDUCE_MIN, 2, local, least);
    return std::abs(-least[1] - least[0]) <= 1e-12 * 7.0 * sum[1];
  }

  // The step taken: added to the step's motion, line search switched on when Newton stalls (When
  // Stalled), the iterate kept for backtracking, and the state moved.
  void advance(const std::vector<double>& inc, double bound) {
    stepNorm2 = 0.0;
    for (GlobalDof g = 0; g < ndof; ++g) {
      accumulated[g] += inc[g];
      stepNorm2 += accumulated[g] * accumulated[g];
    }
    lastStep.clear();  // a step shortened to close a contact is taken as it is
    if (!searching && settings.lineSearch == LineSearch::WhenStalled && kp - progressAt >= kStallIterations) {
      searching = true;
      ++report.stalls;
      if (settings.printIterations && s.comm_->getRank() == 0)
        std::printf("    T %.6g  iteration %2d  stalled: backtracking from here\n", Tb, k);
    }
    if (searching && bound >= 1.0) {
      lastIterate = s.trial_;
      for (auto& c : s.model_.contributions) c->markIterate();
      lastStep = inc;
      alpha = 1.0;
      backtracks = 0;
      lastResidual = rn;
    }
    s.trial_.applyIncrement(inc);
  }
};

bool StaticSolver::newton(double Ta, double Tb, StepReport& report, std::string& failure, bool predict) {
  Newton n(*this, Ta, Tb, report, failure);
  n.prescribe(n.predict(predict));
  for (n.k = 0;; ++n.k) {
    if (const int sig = receivedSignalOnAnyRank(*comm_)) throw Interrupted(sig);
    n.kp = n.k - n.passStart;
    n.prepare();
    n.assembleAndMeasure();
    if (n.lineSearch()) {
      --n.k;
      continue;
    }
    n.record();
    switch (n.verdict()) {
      case Newton::Verdict::Failed: return false;
      case Newton::Verdict::Converged:
        report.iterations = n.k;
        report.passes = n.pass;
        return true;
      case Newton::Verdict::NextPass: continue;
      case Newton::Verdict::Iterate: break;
    }
    std::vector<double> inc;
    double bound = 1.0;
    if (!n.solve(inc, bound)) return false;
    n.advance(inc, bound);
  }
}

}  // namespace bc::core
