#include "AugmentedLagrangeEnforcer.hpp"

#include <algorithm>
#include <cmath>

#include "CoulombFriction.hpp"
#include "RegularizedContactLaw.hpp"

namespace bc::constraints {

const core::ParameterSpec& AugmentedLagrangeEnforcer::spec() {
  static const core::ParameterSpec s = [] {
    core::ParameterSpec p;
    PenaltyChoice::addTo(p, "stiffness (augmented law)");
    p.add("Gap Tolerance", 1e-6, "stop augmenting when |g_N| and sticking |g_T| are below this [length]",
          core::positive(), "> 0");
    p.add("Maximum Augmentations", 50, "Newton solves allowed per increment (passes)", core::atLeast(1), ">= 1");
    p.add("Maximum Coupled Constraints", 200,
          "up to this many constrained gaps (normal, sticking lines) the estimates move with Newton's steps near the "
          "solution, coupled over the points through the model's tangent (one solve with it per gap and coupled "
          "step); with more, or 0, each point updates its own between passes",
          core::atLeast(0), ">= 0");
    p.add("Regularization Gap", 0.0,
          "width g0 of a C1 onset of the normal force centred on the augmented law's kink (0: the kinked law) "
          "at point contacts (line contact uses Lagrange's field rows); the augmentations still close the gap "
          "where the force exceeds eps_N g0 / 2 [length]",
          core::nonNegative(), ">= 0");
    return p;
  }();
  return s;
}

namespace {
// The line nodes' Lagrange rows: this strategy's tolerance and passes, Lagrange's other defaults.
Teuchos::ParameterList fieldParameters(const Teuchos::ParameterList& v) {
  Teuchos::ParameterList l = LagrangeMultiplierEnforcer::spec().reference();
  l.set("Gap Tolerance", v.get<double>("Gap Tolerance"));
  l.set("Maximum Active Set Iterations", v.get<int>("Maximum Augmentations"));
  return l;
}
// The Uzawa update lambda_hat <- lambda = lambda_hat + eps g divides a point's gap by a factor
// 1 + eps c (c its compliance) per pass. Over-relaxed, lambda_hat <- lambda_hat + omega eps g, a gap
// that depends linearly on the estimate, g = a (lambda_hat - lambda*), falls by r = 1 + omega eps a
// per pass, and is closed in one pass by omega* = -1 / (eps a) = omega / (1 - r): omega is measured
// from r, the ratio of the gap to the last pass's gap in the same increment (a secant on g), and
// kept for the next increment, where the point's compliance is nearly the same. Bounded to
// [1, kMaxOverRelaxation] and set back to 1 when the gap did not fall (r >= 1: coupling with other
// points or a change of the law): plain Uzawa is the fallback. Returns the extra (omega - 1) eps g
// beyond the converged force.
constexpr double kMaxOverRelaxation = 1e3;
double overRelaxedUpdate(AugmentedLagrangeEnforcer::State& h, int line, double gap, double eps) {
  double& omega = h.omega[line];
  const double last = h.lastGap[line];
  if (last != 0.0) {
    const double ratio = gap / last;
    omega = ratio < 1.0 ? std::clamp(omega / (1.0 - ratio), 1.0, kMaxOverRelaxation) : 1.0;
  }
  h.lastGap[line] = gap;
  return (omega - 1.0) * eps * gap;
}
// Isotropic Coulomb slip: the friction force's direction is the trial's, lambda_hat_T + eps_T M g_T,
// so it lies along the slip s = g_T1 a - g_T2 b only once the estimate is the force itself (the fixed
// point; Lagrange multipliers slide along s). The part of s across the force F is that estimate's
// error, a length, signed by the side of the force the slip lies on: (F x s) . (a x b) / |F| / |a x b|,
// F = f_1 a - f_2 b with f = M^-1 lambda_T and |F|^2 = |lambda_T|_{M^-1}^2 (CoulombFriction.hpp).
double signedSlipAcrossForce(const ContactKinematics& k, const double lambdaT[2]) {
  const double c = k.cosine, g[2] = {k.tangent1.value, k.tangent2.value};
  const double f2 = cone::lengthSquared(c, lambdaT);
  if (!(f2 > 0.0)) return 0.0;
  // f = M^-1 lambda_T, the force's components along (a, -b); F x s = (f_2 g_1 - f_1 g_2) a x b.
  const double f[2] = {(lambdaT[0] + c * lambdaT[1]) / (1.0 - c * c), (c * lambdaT[0] + lambdaT[1]) / (1.0 - c * c)};
  return (f[1] * g[0] - f[0] * g[1]) * std::sqrt(std::max(0.0, 1.0 - c * c)) / std::sqrt(f2);
}
// Its size, the stopping test's measure; all of |s| (|s|^2 = g_T . M g_T) when the slip runs against the
// force (F . s = lambda_T . g_T < 0) or there is no force.
double slipAcrossForce(const ContactKinematics& k, const double lambdaT[2]) {
  const double g[2] = {k.tangent1.value, k.tangent2.value};
  if (cone::lengthSquared(k.cosine, lambdaT) > 0.0 && lambdaT[0] * g[0] + lambdaT[1] * g[1] >= 0.0)
    return std::abs(signedSlipAcrossForce(k, lambdaT));
  double Mg[2];
  cone::metric(k.cosine, g, Mg);
  return std::sqrt(std::max(0.0, g[0] * Mg[0] + g[1] * Mg[1]));
}
}  // namespace

AugmentedLagrangeEnforcer::AugmentedLagrangeEnforcer(const Teuchos::ParameterList& v)
    : field_(fieldParameters(v)),
      choice_(v),
      tolerance_(v.get<double>("Gap Tolerance")),
      regularization_(v.get<double>("Regularization Gap")),
      maxPasses_(v.get<int>("Maximum Augmentations")),
      maxCoupled_(v.get<int>("Maximum Coupled Constraints")) {}

std::unique_ptr<PointState> AugmentedLagrangeEnforcer::newPointState() const {
  auto s = std::make_unique<State>();
  s->penalties.start(choice_);
  return s;
}

std::unique_ptr<PointState> AugmentedLagrangeEnforcer::newLineNodeState() const {
  auto s = std::make_unique<State>();
  s->lineNode = true;
  return s;
}

int AugmentedLagrangeEnforcer::multipliers(const PointState& s) const {
  const State& h = stateOf<State>(s);
  return h.lineNode ? field_.multipliers(h.field) : 0;
}

double AugmentedLagrangeEnforcer::lineEpsN(const ContactPoint& node) const {
  const double e = choice_.target(0);
  const double modes = node.fieldCompliance > 0.0 ? (1.0 - e) / (e * node.fieldCompliance) : 0.0;
  return std::max(modes, choice_.automatic() ? 0.0 : choice_.given()[0]);
}

void AugmentedLagrangeEnforcer::evaluateLineNode(const ContactPoint& node, const PointState& s, double length,
                                                 double* f, double* K) const {
  const State& h = stateOf<State>(s);
  const double eps = lineEpsN(node);
  if (!h.lineNode || !h.field.active || !(eps > 0.0) || !node.lambda) return;
  f[0] -= length * (node.lambda[0] - h.lambdaN) / eps;
  if (K) K[0] -= length / eps;
}

bool AugmentedLagrangeEnforcer::wantsCompliance(const PointState& s) const {
  const State& h = stateOf<State>(s);
  return !h.lineNode && h.penalties.waiting();
}

void AugmentedLagrangeEnforcer::setCompliance(PointState& s, const double compliance[3]) const {
  choice_.choose(compliance, stateOf<State>(s).penalties.eps);
}

void AugmentedLagrangeEnforcer::relaxTangential(PointState& s, const double compliance[3], int relaxations) const {
  choice_.choose(compliance, stateOf<State>(s).penalties.eps, relaxations);
}

double AugmentedLagrangeEnforcer::activationGap(const PointState& s) const {
  const State& h = stateOf<State>(s);
  if (h.lineNode) return field_.activationGap(h.field);
  if (fixed_) return ConstraintEnforcer::activationGap(s);  // (no step bound while the set is fixed)
  h.penalties.require();
  return 0.5 * regularization_ - h.lambdaN / choice_.at(h.penalties)[0];
}

bool AugmentedLagrangeEnforcer::contributes(double gapN, const PointState& s) const {
  const State& h = stateOf<State>(s);
  if (h.lineNode) return field_.contributes(gapN, h.field);
  if (fixed_) return h.engaged;
  h.penalties.require();
  return h.lambdaN + choice_.at(h.penalties)[0] * (gapN - 0.5 * regularization_) <= 0.0;
}

NormalLaw AugmentedLagrangeEnforcer::normalLaw(const State& h, double epsN) const {
  return fixed_ ? linearNormalLaw(h.lambdaN, epsN) : smoothedAugmentedLaw(h.lambdaN, epsN, regularization_);
}

PointResult AugmentedLagrangeEnforcer::evaluate(const ContactPoint& p, const PointState& s, double* f,
                                                double* K) const {
  const State& h = stateOf<State>(s);
  // A Gauss point of a line, acting through its field nodes' multipliers: Lagrange's rows.
  if (h.lineNode) return field_.evaluate(p, h.field, f, K);
  h.penalties.require();
  const double* eps = choice_.at(h.penalties);
  const FrictionRegularization friction{{h.lambdaT[0], h.lambdaT[1]}, eps[1]};
  if (fixedOut(h)) return PointResult{};
  return regularizedEvaluate(p, normalLaw(h, eps[0]), friction, f, K, fixed_);
}

PointResult AugmentedLagrangeEnforcer::lawForces(const ContactPoint& p, const State& h) const {
  h.penalties.require();
  const double* eps = choice_.at(h.penalties);
  const FrictionRegularization friction{{h.lambdaT[0], h.lambdaT[1]}, eps[1]};
  if (fixedOut(h)) return PointResult{};
  return regularizedForces(p, normalLaw(h, eps[0]), friction, fixed_);
}

bool AugmentedLagrangeEnforcer::inOnset(const PointResult& r, const State& h) const {
  return regularization_ > 0.0 && r.active && -r.lambdaN < 0.5 * choice_.at(h.penalties)[0] * regularization_;
}

bool AugmentedLagrangeEnforcer::acceptNormal(const ContactPoint& p, PointState& s) const {
  State& h = stateOf<State>(s);
  if (!h.lineNode) {
    if (!fixed_) return true;
    // Fixed for the retry: joins where its law presses, leaves where it pulls.
    h.penalties.require();
    return settleEngaged(h.engaged, h.lambdaN + choice_.at(h.penalties)[0] * p.kinematics.normal.value);
  }
  const bool kept = field_.acceptNormal(p, h.field);
  if (!h.field.active) h.lambdaN = 0.0;  // released (or still open): no estimate
  return kept;
}

bool AugmentedLagrangeEnforcer::acceptPoint(const ContactPoint& p, PointState& s, double& worstViolation) const {
  State& h = stateOf<State>(s);
  if (h.lineNode) {
    // The field's stick/slip (Per Line), and its violation |g_a|; then the Uzawa update.
    double violation = 0.0;
    const bool settled = field_.acceptPoint(p, h.field, violation);
    worstViolation = std::max(worstViolation, violation);
    if (!h.field.active) return settled;
    h.lambdaN = p.lambda ? p.lambda[0] : 0.0;
    return settled && violation <= tolerance_;
  }
  const ContactKinematics& k = p.kinematics;
  const PointResult r = lawForces(p, h);
  const double* eps = choice_.at(h.penalties);
  const double epsN = eps[0];
  double violation = 0.0;
  // With a Regularization Gap, a point whose force is within the smooth onset (below eps_N g0 / 2)
  // is left regularized: its gap lies within g0 / 2 of zero by construction.
  const bool onset = inOnset(r, h);
  if (onset) {
    violation = std::max(0.0, std::min(-k.normal.value, std::abs(k.normal.value) - 0.5 * regularization_));
  } else if (r.active) {
    violation = std::abs(k.normal.value);
    const GapDerivatives* gt[2] = {&k.tangent1, &k.tangent2};
    for (int i = 0; i < 2; ++i)
      if (p.friction > 0.0 && !r.slip[i]) violation = std::max(violation, std::abs(gt[i]->value));
    if (p.friction > 0.0 && p.law == FrictionLaw::IsotropicCoulomb && r.slip[0])
      violation = std::max(violation, slipAcrossForce(k, r.lambdaT));
  } else {
    violation = std::max(0.0, -k.normal.value);
  }
  // A point blended with line contact carries only its share of the force: its gap counts as much.
  violation *= p.weight;
  worstViolation = std::max(worstViolation, violation);
  const bool met = violation <= tolerance_;
  // Uzawa update of the estimates, over-relaxed while the gaps are not met (overRelaxedUpdate).
  // Normal: on the linear branch of the law only (not open, not within the smooth onset); tangential:
  // on sticking lines of the Per Line law only (a slipping force is the cone's, an isotropic stick
  // couples the two lines through the cone).
  const bool normalLinear = r.active && !onset && !met;
  h.lambdaN = r.lambdaN + (normalLinear ? overRelaxedUpdate(h, 0, k.normal.value, epsN) : 0.0);
  if (!normalLinear) h.lastGap[0] = 0.0;
  const GapDerivatives* gt[2] = {&k.tangent1, &k.tangent2};
  const bool isotropicSlip =
      r.active && !onset && p.friction > 0.0 && p.law == FrictionLaw::IsotropicCoulomb && r.slip[0];
  for (int i = 0; i < 2; ++i) {
    const bool stick = normalLinear && p.friction > 0.0 && !r.slip[i] && p.law == FrictionLaw::PerLine;
    h.lambdaT[i] = r.lambdaT[i] + (stick ? overRelaxedUpdate(h, 1 + i, gt[i]->value, eps[1]) : 0.0);
    if (!stick && !(isotropicSlip && i == 0)) h.lastGap[1 + i] = 0.0;
  }
  // Isotropic Coulomb slip: the estimate turns towards the slip, over-relaxed by a secant on the signed
  // slip across the force, as the gaps are: lambda_hat_T = the cone's force along lambda_T + (omega - 1)
  // eps_T M g_T (omega 1: the converged force, the plain update).
  if (isotropicSlip) {
    const double across = signedSlipAcrossForce(k, r.lambdaT);
    if (!met && p.weight * std::abs(across) > tolerance_) {
      overRelaxedUpdate(h, 1, across, eps[1]);
      const double g[2] = {k.tangent1.value, k.tangent2.value};
      double Mg[2];
      cone::metric(k.cosine, g, Mg);
      const double t[2] = {r.lambdaT[0] + (h.omega[1] - 1.0) * eps[1] * Mg[0],
                           r.lambdaT[1] + (h.omega[1] - 1.0) * eps[1] * Mg[1]};
      const double length = std::sqrt(cone::lengthSquared(k.cosine, t));
      if (length > 0.0)
        for (int i = 0; i < 2; ++i) h.lambdaT[i] = -p.friction * r.lambdaN * t[i] / length;
    } else {
      h.lastGap[1] = 0.0;
    }
  }
  return met;
}

int AugmentedLagrangeEnforcer::coupledConstraints(const ContactPoint& p, const PointState& s,
                                                  CoupledConstraint out[3]) const {
  const State& h = stateOf<State>(s);
  if (h.lineNode) return 0;
  const PointResult r = lawForces(p, h);
  // On the linear branch of the law only (not open, not within the smooth onset).
  if (!r.active || inOnset(r, h)) return 0;
  int n = 0;
  out[n] = CoupledConstraint{};
  out[n].force[0] = 1.0;
  bool stick[2];
  for (int i = 0; i < 2; ++i) {
    stick[i] = p.friction > 0.0 && !r.slip[i] && p.measured[i];
    // A slipping line's force is the cone's: it follows the normal force.
    if (!stick[i] && r.lambdaN != 0.0) out[n].force[1 + i] = r.lambdaT[i] / r.lambdaN;
  }
  ++n;
  for (int i = 0; i < 2; ++i) {
    if (!stick[i]) continue;
    out[n] = CoupledConstraint{};
    out[n].gap = 1 + i;
    out[n].force[1 + i] = 1.0;
    ++n;
  }
  return n;
}

void AugmentedLagrangeEnforcer::coupledUpdate(PointState& s, const CoupledConstraint* c, int n,
                                              const double* delta) const {
  State& h = stateOf<State>(s);
  if (h.lineNode) return;
  // (The per-point secant's gap of the last pass belongs to an estimate that has moved since.)
  for (int j = 0; j < n; ++j) {
    (c[j].gap == 0 ? h.lambdaN : h.lambdaT[c[j].gap - 1]) += delta[j];
    h.lastGap[c[j].gap] = 0.0;
  }
  // A point the step would pull keeps no tensile estimate: it opens, and closes again as any other
  // (a tensile estimate would hold it open until it penetrated by lambda_hat_N / eps_N).
  h.lambdaN = std::min(0.0, h.lambdaN);
}

void AugmentedLagrangeEnforcer::commitPoint(const ContactPoint& p, PointState& s) const {
  State& h = stateOf<State>(s);
  if (h.lineNode) return;
  for (double& g : h.lastGap) g = 0.0;
  // The next increment's first estimates: the converged forces extrapolated linearly from this
  // increment and the last (as the predictor extrapolates the motion), while the point stays in
  // contact; the tangential ones (Per Line) bounded by the cone. The augmentations then start from
  // the gap the extrapolation misses (second order in the increment) instead of the increment's
  // whole change of the gap. Only the start of the iteration changes: its fixed point does not.
  const bool closed = h.lambdaN < 0.0 && h.committedN < 0.0;
  const double forces[3] = {h.lambdaN, h.lambdaT[0], h.lambdaT[1]};
  if (closed) {
    h.lambdaN = std::min(0.0, 2.0 * h.lambdaN - h.committedN);
    const double limit = p.friction * -h.lambdaN;
    for (int i = 0; i < 2; ++i)
      h.lambdaT[i] = p.law == FrictionLaw::PerLine ? std::clamp(2.0 * h.lambdaT[i] - h.committedT[i], -limit, limit)
                                                   : h.lambdaT[i];
  }
  h.committedN = forces[0];
  for (int i = 0; i < 2; ++i) h.committedT[i] = forces[1 + i];
}

std::vector<double> AugmentedLagrangeEnforcer::outputValues(const ContactPoint& p, const PointState& s) const {
  const State& h = stateOf<State>(s);
  if (!h.lineNode) return choice_.outputValues(h.penalties);
  return {lineEpsN(p), 0.0};
}

PointResult AugmentedLagrangeEnforcer::reportedForces(const ContactPoint& p, const PointState& s) const {
  const State& h = stateOf<State>(s);
  if (h.lineNode) return field_.reportedForces(p, h.field);
  PointResult r;
  r.active = h.lambdaN < 0.0;
  if (!r.active) return r;
  r.lambdaN = h.lambdaN;
  const double mu = p.friction;
  const double limit = -mu * h.lambdaN * (1.0 - 1e-12);
  const double length = std::sqrt(cone::lengthSquared(p.kinematics.cosine, h.lambdaT));
  for (int i = 0; i < 2; ++i) {
    r.lambdaT[i] = h.lambdaT[i];
    r.slip[i] = mu > 0.0 && (p.law == FrictionLaw::PerLine ? std::abs(h.lambdaT[i]) : length) >= limit;
  }
  return r;
}

}  // namespace bc::constraints
