#include "LinearSolver.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include <Teuchos_CommHelpers.hpp>

namespace bc::core {

namespace {

constexpr const char* kAutomatic = "Automatic";

bool haveMethod(const std::string& name) {
  for (const auto& m : directMethodNames())
    if (m == name) return true;
  return false;
}

}  // namespace

std::string automaticRule() {
  return "UMFPACK with Reuse Factorization from " + std::to_string(kAutomaticLuUnknowns) +
         " unknowns (6 per node and the extra unknowns) with a contact point for every " +
         std::to_string(kAutomaticUnknownsPerPoint) + " unknowns or fewer, on several ranks MUMPS with it from " +
         std::to_string(kAutomaticMumpsUnknowns) +
         " unknowns; KLU2 otherwise (small or nearly banded matrices); taken when the run starts and, while it "
         "gives KLU2, again before every solve with the unknowns and contact points of that moment (contact that "
         "appears during the run), changing once to the other LU";
}

DirectChoice chooseDirectSolver(const SystemSize& size) {
  DirectChoice c;
  c.reason = std::to_string(size.unknowns) + " unknowns, " + std::to_string(size.contactPoints) +
             " contact points on " + std::to_string(size.ranks) + (size.ranks == 1 ? " rank" : " ranks");
  const bool large = size.unknowns >= kAutomaticLuUnknowns;
  const bool coupled = size.contactPoints * kAutomaticUnknownsPerPoint >= size.unknowns;
  if (!large || !coupled) {
    c.method = "KLU2";
    c.reuse = false;
    c.reason += !large
                    ? " (fewer than " + std::to_string(kAutomaticLuUnknowns) + " unknowns)"
                    : " (fewer than one contact point per " + std::to_string(kAutomaticUnknownsPerPoint) + " unknowns)";
    return c;
  }
  c.method = size.ranks > 1 && size.unknowns >= kAutomaticMumpsUnknowns && haveMethod("MUMPS") ? "MUMPS" : "UMFPACK";
  c.reuse = true;
  return c;
}

std::string resolveLinearSolver(Teuchos::ParameterList& p, const SystemSize& size) {
  if (p.get<std::string>("Type") != "Direct") return "";
  if (p.get<std::string>("Direct Solver") != kAutomatic) {
    // A Direct Solver named: no reuse unless given (the effective parameters say so).
    if (!p.isParameter("Reuse Factorization"))
      p.set("Reuse Factorization", false, "not given, with a Direct Solver named: false");
    return "";
  }
  const DirectChoice c = chooseDirectSolver(size);
  const bool reuseGiven = p.isParameter("Reuse Factorization");
  const bool reuse = reuseGiven ? p.get<bool>("Reuse Factorization") : c.reuse;
  const std::string why = "chosen by Direct Solver = Automatic (" + automaticRule() + "): " + c.reason;
  p.set("Direct Solver", c.method, why);
  if (!reuseGiven) p.set("Reuse Factorization", reuse, why);
  return c.method + (reuse ? " with Reuse Factorization" : "") + " (Automatic: " + c.reason +
         (reuseGiven ? "; Reuse Factorization as given" : "") + ")";
}

const ParameterSpec& linearSolverSpec() {
  static const ParameterSpec spec = [] {
    ParameterSpec s;
    s.addChoice("Type", "Direct", {"Direct", "GMRES"},
                "Direct: sparse LU (Direct Solver); GMRES: Belos GMRES with an Ifpack2 or MueLu preconditioner");
    std::vector<std::string> methods = directMethodNames();
    methods.insert(methods.begin(), kAutomatic);
    s.addChoice("Direct Solver", kAutomatic, methods,
                "Direct only: the sparse LU factorization. Automatic: chosen when the run starts by the model's "
                "size, its contact points and the rank count (" +
                    automaticRule() +
                    "); a Reuse Factorization the deck gives is kept; the run's header and "
                    "effective_parameters.xml say which. " +
                    directMethodsDoc());
    s.add("Residual Check Tolerance", 1e-10,
          "largest accepted backward error ||b - A x|| / (||A||_F ||x|| + ||b||) of a solve; above it the solve "
          "is an error",
          positive(), "> 0");
    s.add("Condition Limit", 1e14,
          "largest accepted ||A||_F ||x|| / ||b|| of a solve (a lower bound of the matrix's condition number); "
          "above it the matrix is taken as singular and the solve is an error",
          positive(), "> 0");
    s.addChoice("Preconditioner", "ILUT", {"ILUT", "RILUK", "MueLu"},
                "GMRES only: ILUT or RILUK: additive Schwarz with incomplete factorizations of the subdomains; "
                "MueLu: smoothed-aggregation multigrid with the nodes' rigid-body modes as near-null space "
                "(Penalty and Augmented Lagrange only: no multiplier rows)");
    s.add("Fill Level", 2.0,
          "GMRES only: ILUT level of fill, RILUK level k, or MueLu's Gauss-Seidel sweeps per level (at least 1)",
          nonNegative(), ">= 0");
    s.add("Overlap", 1, "GMRES only: overlap of the additive Schwarz subdomains", atLeast(0), ">= 0");
    s.addOptional("Reuse Factorization", true,
                  "Direct only: solve by GMRES preconditioned with the last LU factorization (of an earlier Newton "
                  "matrix of the same size), and factor the matrix again only when the GMRES iterations since the "
                  "last factorization reach Reuse Iteration Limit; a saddle point (Lagrange multipliers' zero "
                  "diagonal) is factored with that diagonal regularized (a millionth of its Schur complement "
                  "estimate), which keeps the fill-reducing order's pivots; the solution is held to the same "
                  "residual check; absent: false with a Direct Solver named, the automatic choice's with Automatic",
                  {}, "");
    s.addOptional("Reuse Iteration Limit", 25,
                  "Direct with Reuse Factorization: GMRES iterations, summed over the solves since the last "
                  "factorization, after which the matrix is factored again (one solve takes at most 100); "
                  "absent or \"Automatic\": half the iterations whose floating-point operations equal the "
                  "last full factorization's (the Direct Solver's count), at least 10",
                  atLeast(1), ">= 1");
    s.allowWord("Reuse Iteration Limit", "Automatic");
    s.add(
        "Tolerance", 1e-12, "GMRES only: relative residual at which GMRES stops",
        [](const Teuchos::ParameterEntry& e) {
          const double v = e.getAny().type() == typeid(int) ? Teuchos::any_cast<int>(e.getAny())
                                                            : Teuchos::any_cast<double>(e.getAny());
          std::ostringstream got;
          got << v;
          return v > 0.0 && v < 1.0
                     ? std::string()
                     : "must be in (0, 1) (a relative residual of 1 is the start: no solve), got " + got.str();
        },
        "in (0, 1)");
    s.add("Maximum Iterations", 1000, "GMRES only: iteration limit", atLeast(1), ">= 1");
    s.add("Restart", 200, "GMRES only: Krylov vectors kept before a restart", atLeast(1), ">= 1");
    return s;
  }();
  return spec;
}

void applyLinearSolverParameters(Teuchos::ParameterList& user, const std::string& path) {
  static const std::vector<std::string> directOnly = {"Direct Solver", "Reuse Iteration Limit"};
  static const std::vector<std::string> gmresOnly = {"Preconditioner", "Fill Level",         "Overlap",
                                                     "Tolerance",      "Maximum Iterations", "Restart"};
  std::vector<std::string> given;
  for (const auto& names : {directOnly, gmresOnly})
    for (const auto& name : names)
      if (user.isParameter(name)) given.push_back(name);
  const bool typeGiven = user.isParameter("Type");
  linearSolverSpec().apply(user, path);
  const std::string type = user.get<std::string>("Type");
  const auto& foreign = type == "Direct" ? gmresOnly : directOnly;
  // (A foreign parameter at its default value changes nothing: effective_parameters.xml, which a run
  // writes with every default, is a deck again.)
  static const Teuchos::ParameterList defaults = linearSolverSpec().example();
  const auto atDefault = [&](const std::string& name) {
    return defaults.isParameter(name) && user.getEntry(name).getAny(false) == defaults.getEntry(name).getAny(false);
  };
  for (const auto& name : given)
    if (std::find(foreign.begin(), foreign.end(), name) != foreign.end() && !atDefault(name))
      throw InputError(
          "parameter \"" + path + "/" + name + "\" applies to Type \"" + (type == "Direct" ? "GMRES" : "Direct") +
          "\" only, and \"" + path + "/Type\" is \"" + type + "\"" + (typeGiven ? "" : " (the default)") +
          ": it would be ignored; remove it, or set Type to \"" + (type == "Direct" ? "GMRES" : "Direct") + "\"");
}

namespace {

SolveChecks readChecks(const Teuchos::ParameterList& p) {
  SolveChecks c;
  c.residualTolerance = p.get<double>("Residual Check Tolerance");
  c.conditionLimit = p.get<double>("Condition Limit");
  return c;
}

DirectSettings readDirect(const Teuchos::ParameterList& p) {
  DirectSettings s;
  s.method = p.get<std::string>("Direct Solver");
  s.checks = readChecks(p);
  if (s.method == kAutomatic)
    throw std::logic_error(
        "Linear Solver/Direct Solver = Automatic is resolved (resolveLinearSolver) before the "
        "solver is made");
  s.reuse.on = p.isParameter("Reuse Factorization") && p.get<bool>("Reuse Factorization");
  s.reuse.iterationLimit = p.isType<int>("Reuse Iteration Limit") ? p.get<int>("Reuse Iteration Limit") : 0;
  // The GMRES target leaves the backward error well below the check (LinearSolver::solve redoes a
  // shortcut's solve that is not).
  s.reuse.target = 0.5e-3 * s.checks.residualTolerance;
  return s;
}

GmresSettings readGmres(const Teuchos::ParameterList& p) {
  GmresSettings s;
  s.preconditioner = p.get<std::string>("Preconditioner");
  s.overlap = p.get<int>("Overlap");
  s.fill = p.get<double>("Fill Level");
  s.tolerance = p.get<double>("Tolerance");
  s.maxIterations = p.get<int>("Maximum Iterations");
  s.restart = p.get<int>("Restart");
  s.checks = readChecks(p);
  return s;
}

}  // namespace

std::unique_ptr<LinearSolver> makeLinearSolver(const Teuchos::ParameterList& p) {
  const std::string type = p.get<std::string>("Type");
  if (type != "Direct" && p.isParameter("Reuse Factorization") && p.get<bool>("Reuse Factorization"))
    throw InputError(
        "parameter \"Linear Solver/Reuse Factorization\" reuses the Direct solver's LU factorization; "
        "with Type \"" +
        type + "\" give Preconditioner instead");
  if (type == "Direct") return makeDirectSolver(readDirect(p));
  return makeGmresSolver(readGmres(p));
}

std::unique_ptr<LinearSolver> makeLinearSolver(const Teuchos::ParameterList& params, const SystemSize& size) {
  Teuchos::ParameterList resolved = params;
  resolveLinearSolver(resolved, size);
  return makeLinearSolver(resolved);
}

namespace {

// Direct Solver = Automatic that started on KLU2: the rule before every solve until it picks another LU.
class AutomaticDirect : public LinearSolver {
 public:
  AutomaticDirect(const Teuchos::ParameterList& params, const SystemSize& start, std::unique_ptr<LinearSolver> first,
                  std::function<long long()> contactPoints, std::function<void(const AutomaticChange&)> onChange)
      : LinearSolver(readChecks(params)),
        params_(params),
        ranks_(start.ranks),
        inner_(std::move(first)),
        contactPoints_(std::move(contactPoints)),
        onChange_(std::move(onChange)) {}
  std::string name() const override { return inner_->name(); }

 protected:
  int doSolve(const Teuchos::RCP<const Matrix>& A, const Vector& b, Vector& x) override {
    if (!changed_) reconsider(*A);
    inner_->setTimer(timer_);
    return forwardSolve(*inner_, A, b, x);
  }
  bool redoWithoutShortcut() override { return forwardRedo(*inner_); }

 private:
  void reconsider(const Matrix& A) {
    long long here = contactPoints_(), points = 0;
    Teuchos::reduceAll(*A.getComm(), Teuchos::REDUCE_MAX, here, Teuchos::outArg(points));
    const SystemSize size{static_cast<long long>(A.getGlobalNumRows()), points, ranks_};
    if (chooseDirectSolver(size).method == "KLU2") return;
    AutomaticChange change;
    change.resolved = params_;
    change.line = resolveLinearSolver(change.resolved, size);
    inner_ = makeLinearSolver(change.resolved);
    changed_ = true;
    if (onChange_) onChange_(change);
  }

  Teuchos::ParameterList params_;
  int ranks_;
  std::unique_ptr<LinearSolver> inner_;
  std::function<long long()> contactPoints_;
  std::function<void(const AutomaticChange&)> onChange_;
  bool changed_ = false;
};

}  // namespace

std::unique_ptr<LinearSolver> makeLinearSolver(const Teuchos::ParameterList& params, const SystemSize& start,
                                               std::function<long long()> contactPoints,
                                               std::function<void(const AutomaticChange&)> onChange) {
  const bool automatic =
      params.get<std::string>("Type") == "Direct" && params.get<std::string>("Direct Solver") == kAutomatic;
  if (!automatic || !contactPoints || chooseDirectSolver(start).method != "KLU2")
    return makeLinearSolver(params, start);
  return std::make_unique<AutomaticDirect>(params, start, makeLinearSolver(params, start), std::move(contactPoints),
                                           std::move(onChange));
}

}  // namespace bc::core
