#include "LagrangeMultiplierEnforcer.hpp"

#include <algorithm>
#include <cmath>

#include "CoulombFriction.hpp"

namespace bc::constraints {

const core::ParameterSpec& LagrangeMultiplierEnforcer::spec() {
  static const core::ParameterSpec s = [] {
    core::ParameterSpec p;
    p.add("Gap Tolerance", 1e-9,
          "an inactive point is activated when g_N < -this; a slipping line sticks when its slip opposes its "
          "force by more than this [length]",
          core::positive(), "> 0");
    p.add("Maximum Active Set Iterations", 30, "Newton solves allowed per increment while the active set changes",
          core::atLeast(1), ">= 1");
    p.add("Friction Complementarity Parameter", 100.0,
          "Isotropic Coulomb: c_T of the friction rows lambda_T = P(lambda_T + c_T M g_T) (projection on the "
          "cone); any c_T > 0 has the same solution, it only steers Newton's stick/slip guesses: too large and "
          "Newton's slip direction follows the slip increments' noise and cycles (a pure press at first "
          "contact did with 1000); too small and it follows the force only [force/length]",
          core::positive(), "> 0");
    return p;
  }();
  return s;
}

LagrangeMultiplierEnforcer::LagrangeMultiplierEnforcer(const Teuchos::ParameterList& v)
    : tolerance_(v.get<double>("Gap Tolerance")),
      maxPasses_(v.get<int>("Maximum Active Set Iterations")),
      complementarity_(v.get<double>("Friction Complementarity Parameter")) {}

bool LagrangeMultiplierEnforcer::isotropicFrictionRows(const ContactPoint& p, double* f, double* K,
                                                       const Compliance& compliance) const {
  const ContactKinematics& k = p.kinematics;
  const double mu = p.friction;
  const double* lambda = p.lambda;
  // C(lambda_T, lambda_N, g_T, c) = lambda_T - P(lambda_T + c_T M g_T) = 0, P the projection on the
  // cone of radius mu max(0, -lambda_N): inside (stick) it reads -c_T M g_T = 0, outside (slip)
  // lambda_T = mu |lambda_N| (lambda_T + c_T M g_T) / |..|, the force at the limit along the slip.
  // Semismooth Newton: the branch is taken anew at every iterate; derivatives by forward AD over
  // (lambda_T1, lambda_T2, lambda_N, g_T1, g_T2, c).
  using F = Sacado::Fad::SFad<double, 6>;
  constexpr int n = kPairDofs + 3, iN = kPairDofs;
  const F lT[2] = {F(6, 0, lambda[1]), F(6, 1, lambda[2])};
  const F lN(6, 2, lambda[0]), c(6, 5, k.cosine);
  const F g[2] = {F(6, 3, k.tangent1.value), F(6, 4, k.tangent2.value)};
  F Mg[2], P[2];
  cone::metric(c, g, Mg);
  // (A direction without a measured slip is frictionless: v = 0 there gives the row lambda_T = 0.)
  // (c_T lowered tenfold per retry after slip directions cycled: the same solution, steadier guesses.)
  const double cT = complementarity_ / p.frictionRelaxation;
  // (Springs: the trial's slip less the spring's stretch, (lambda_T - committedT) times the compliance.)
  const double ct = compliance.tangential;
  const F stretch[2] = {ct * (lT[0] - compliance.committedT[0]), ct * (lT[1] - compliance.committedT[1])};
  const F v[2] = {p.measured[0] ? F(lT[0] + cT * (Mg[0] - stretch[0])) : F(0.0),
                  p.measured[1] ? F(lT[1] + cT * (Mg[1] - stretch[1])) : F(0.0)};
  const F radius = lN.val() < 0.0 ? F(-mu * lN) : F(0.0);
  const bool slip = cone::project(c, radius, v, P);
  const Vector24* Rs[3] = {&k.tangent1.gradient, &k.tangent2.gradient, &k.cosineR};
  for (int t = 0; t < 2; ++t) {
    const F C = lT[t] - P[t];
    const int row = iN + 1 + t;
    f[row] += C.val();
    if (!K) continue;
    K[n * row + iN + 1] += C.dx(0);
    K[n * row + iN + 2] += C.dx(1);
    K[n * row + iN] += C.dx(2);
    for (int b = 0; b < 3; ++b) {
      const double db = C.dx(3 + b);
      if (db != 0.0)
        for (int j = 0; j < kPairDofs; ++j) K[n * row + j] += db * (*Rs[b])[j];
    }
  }
  return slip;
}

PointResult LagrangeMultiplierEnforcer::evaluate(const ContactPoint& p, const PointState& s, double* f, double* K,
                                                 const Compliance& compliance) const {
  const State& h = stateOf<State>(s);
  const ContactKinematics& k = p.kinematics;
  const double mu = p.friction;
  const double* lambda = p.lambda;
  PointResult r;
  r.active = h.active;
  if (!h.active) return r;
  constexpr int n = kPairDofs + 3, iN = kPairDofs;
  const GapDerivatives* g[3] = {&k.normal, &k.tangent1, &k.tangent2};
  r.lambdaN = lambda[0];
  for (int i = 0; i < 2; ++i) {
    r.lambdaT[i] = lambda[1 + i];
    r.slip[i] = h.slip[i];
  }
  // Displacement rows and their coupling columns.
  for (int q = 0; q < 3; ++q) {
    const double l = lambda[q];
    for (int i = 0; i < kPairDofs; ++i) f[i] += l * g[q]->R[i];
    if (!K) continue;
    for (int i = 0; i < kPairDofs; ++i) {
      for (int j = 0; j < kPairDofs; ++j) K[n * i + j] += l * g[q]->K[kPairDofs * i + j];
      K[n * i + iN + q] += g[q]->R[i];
    }
  }
  // Normal row: g_N = 0 (springs: g_N - compliance lambda_N = 0).
  f[iN] += k.normal.value - compliance.normal * lambda[0];
  if (K) {
    for (int j = 0; j < kPairDofs; ++j) K[n * iN + j] += k.normal.gradient[j];
    K[n * iN + iN] -= compliance.normal;
  }
  // Tangential rows.
  if (mu > 0.0 && p.law == FrictionLaw::IsotropicCoulomb) {
    r.slip[0] = r.slip[1] = isotropicFrictionRows(p, f, K, compliance);
    return r;
  }
  for (int t = 0; t < 2; ++t) {
    const int row = iN + 1 + t;
    if (mu <= 0.0 || !p.measured[t]) {
      f[row] += lambda[1 + t];
      if (K) K[n * row + row] += 1.0;
    } else if (!h.slip[t]) {
      f[row] += g[1 + t]->value - compliance.tangential * (lambda[1 + t] - compliance.committedT[t]);
      if (K) {
        for (int j = 0; j < kPairDofs; ++j) K[n * row + j] += g[1 + t]->gradient[j];
        K[n * row + row] -= compliance.tangential;
      }
    } else {
      const double s = h.slipSign[t];
      f[row] += s * lambda[1 + t] + mu * lambda[0];
      if (K) {
        K[n * row + row] += s;
        K[n * row + iN] += mu;
      }
    }
  }
  return r;
}

bool LagrangeMultiplierEnforcer::acceptNormal(const ContactPoint& p, PointState& s) const {
  State& h = stateOf<State>(s);
  const ContactKinematics& k = p.kinematics;
  const double mu = p.friction;
  const double* lambda = p.lambda;
  if (!h.active) {
    if (k.normal.value >= -tolerance_) return true;
    // Penetrating: activate. In friction it starts sliding in the direction it has moved since
    // the last converged step (sticking from there would put the whole motion of the step, made
    // while open, into the friction force); the stick/slip stage then decides.
    h.active = true;
    const double gT[2] = {k.tangent1.value, k.tangent2.value};
    for (int t = 0; t < 2; ++t) {
      h.slip[t] = mu > 0.0 && p.law == FrictionLaw::PerLine && p.measured[t];
      h.slipSign[t] = gT[t] >= 0.0 ? 1.0 : -1.0;
    }
    return false;
  }
  // Tension: release, but a point held by sticking friction first gets to slip (with lambda_N > 0
  // its Coulomb cone is empty, so the friction stage switches it); it is released only if it is
  // still in tension while slipping.
  const bool held = p.law == FrictionLaw::PerLine && ((p.measured[0] && !h.slip[0]) || (p.measured[1] && !h.slip[1]));
  if (lambda && lambda[0] > 0.0 && !(held && mu > 0.0)) {
    h.active = false;
    return false;
  }
  return true;
}

bool LagrangeMultiplierEnforcer::acceptPoint(const ContactPoint& p, PointState& s, double& worstViolation) const {
  State& h = stateOf<State>(s);
  const ContactKinematics& k = p.kinematics;
  const double mu = p.friction;
  const double* lambda = p.lambda;
  if (!h.active) {
    worstViolation = std::max(worstViolation, std::max(0.0, -k.normal.value));
    return true;
  }
  worstViolation = std::max(worstViolation, std::abs(k.normal.value));
  // Isotropic Coulomb: stick and slip are settled inside Newton by the complementarity rows.
  if (mu <= 0.0 || p.law == FrictionLaw::IsotropicCoulomb) return true;
  const double lN = lambda[0];
  const GapDerivatives* gt[2] = {&k.tangent1, &k.tangent2};
  bool changed = false;
  for (int t = 0; t < 2; ++t) {
    if (!p.measured[t]) continue;
    const double lT = lambda[1 + t];
    if (!h.slip[t]) {
      if (std::abs(lT) > -mu * lN * (1.0 + 1e-10)) {
        h.slip[t] = true;
        h.slipSign[t] = lT >= 0.0 ? 1.0 : -1.0;
        changed = true;
      }
    } else if (h.slipSign[t] * gt[t]->value < -tolerance_) {
      h.slip[t] = false;
      changed = true;
    }
  }
  return !changed;
}

}  // namespace bc::constraints
