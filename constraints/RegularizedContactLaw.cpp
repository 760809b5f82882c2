#include "RegularizedContactLaw.hpp"

#include <cmath>

#include "CoulombFriction.hpp"

namespace bc::constraints {

NormalLaw linearNormalLaw(double lambdaHatN, double epsN) {
  return [lambdaHatN, epsN](const LawScalar& g) -> LawScalar { return lambdaHatN + epsN * g; };
}

NormalLaw smoothedPenaltyLaw(double epsN, double g0) {
  if (!(g0 > 0.0)) return linearNormalLaw(0.0, epsN);
  return [epsN, g0](const LawScalar& g) -> LawScalar {
    if (!(g.val() < 0.0)) return LawScalar(0.0);
    if (g.val() > -g0) return -0.5 * epsN * g * g / g0;
    return epsN * (g + 0.5 * g0);
  };
}

NormalLaw smoothedAugmentedLaw(double lambdaHatN, double epsN, double g0) {
  if (!(g0 > 0.0)) return linearNormalLaw(lambdaHatN, epsN);
  return [lambdaHatN, epsN, g0](const LawScalar& g) -> LawScalar {
    const LawScalar x = g + lambdaHatN / epsN;
    if (!(x.val() < 0.5 * g0)) return LawScalar(0.0);
    if (x.val() > -0.5 * g0) return -0.5 * epsN * (x - 0.5 * g0) * (x - 0.5 * g0) / g0;
    return epsN * x;
  };
}

namespace {

// The multipliers as functions of s = (g_N, g_T1, g_T2, c); active = lambda_N < 0.
bool lawForces(const ContactPoint& p, const NormalLaw& normal, const FrictionRegularization& t, LawScalar lam[3],
               bool slip[2], bool bilateral) {
  using F = LawScalar;
  const ContactKinematics& k = p.kinematics;
  const F gN(4, 0, k.normal.value), c(4, 3, k.cosine);
  const F g[2] = {F(4, 1, k.tangent1.value), F(4, 2, k.tangent2.value)};
  lam[0] = normal(gN);
  lam[1] = lam[2] = F(0.0);
  slip[0] = slip[1] = false;
  // Exactly at the law's onset (a point touching, as two layers laid on each other at the start) the
  // point takes part with no force and the law's stiffness (the derivative from the closed side):
  // Newton's first step then sees the contact instead of passing through it.
  if (!bilateral && (lam[0].val() > 0.0 || (lam[0].val() == 0.0 && lam[0].dx(0) == 0.0))) return false;
  if (p.friction > 0.0 && !(bilateral && lam[0].val() > 0.0)) {
    F trial[2];
    frictionTrial(p.law, c, g, t.lambdaHat, t.penalty, trial);
    const F radius = -p.friction * lam[0];
    if (p.heldFriction) {
      // Held in stick (ContactPoint::heldFriction): a linear spring for the rest of the solve.
      lam[1] = trial[0];
      lam[2] = trial[1];
      return true;
    }
    returnMap(p.law, c, radius, trial, &lam[1], slip);
    if (p.secantFriction && (slip[0] || slip[1])) {
      // A slipping force whose direction cycled in this Newton solve: its tangent is the secant
      // radius / |trial| (the force's share of the trial; Per Line: of each line's) times the trial's
      // derivative, without the normal force's share. The consistent tangent has no stiffness along
      // the slip, and where the stick zone is narrower than Newton's motions the slip direction flips.
      const bool isotropic = p.law == FrictionLaw::IsotropicCoulomb;
      const double n = isotropic ? std::sqrt(cone::value(cone::lengthSquared(c, trial))) : 0.0;
      for (int i = 0; i < 2; ++i) {
        if (!slip[i]) continue;
        const double length = isotropic ? n : std::abs(trial[i].val());
        const double secant = length > 0.0 ? radius.val() / length : 0.0;
        lam[1 + i] = F(lam[1 + i].val()) + secant * (trial[i] - trial[i].val());
      }
    }
  }
  return true;
}

PointResult result(bool active, const LawScalar lam[3], const bool slip[2]) {
  PointResult r;
  r.active = active;
  if (!active) return r;
  r.lambdaN = lam[0].val();
  for (int i = 0; i < 2; ++i) {
    r.lambdaT[i] = lam[1 + i].val();
    r.slip[i] = slip[i];
  }
  return r;
}

}  // namespace

PointResult regularizedForces(const ContactPoint& p, const NormalLaw& normal, const FrictionRegularization& t,
                              bool bilateral) {
  LawScalar lam[3];
  bool slip[2];
  const bool active = lawForces(p, normal, t, lam, slip, bilateral);
  return result(active, lam, slip);
}

PointResult regularizedEvaluate(const ContactPoint& p, const NormalLaw& normal, const FrictionRegularization& t,
                                double* f, double* K, bool bilateral) {
  LawScalar lam[3];
  bool slip[2];
  const bool active = lawForces(p, normal, t, lam, slip, bilateral);
  if (!active) return result(false, lam, slip);
  const ContactKinematics& k = p.kinematics;
  constexpr int n = kPairDofs;
  const GapDerivatives* gaps[3] = {&k.normal, &k.tangent1, &k.tangent2};
  // The law's inputs are linearized by the gaps' gradients; the forces act along their variations R.
  const Vector24* Rs[4] = {&k.normal.gradient, &k.tangent1.gradient, &k.tangent2.gradient, &k.cosineR};
  for (int a = 0; a < 3; ++a) {
    const double la = lam[a].val();
    if (la == 0.0 && lam[a].dx(0) == 0.0 && lam[a].dx(1) == 0.0 && lam[a].dx(2) == 0.0 && lam[a].dx(3) == 0.0) continue;
    for (int i = 0; i < n; ++i) f[i] += la * gaps[a]->R[i];
    if (!K) continue;
    double d[n] = {};
    for (int b = 0; b < 4; ++b) {
      const double db = lam[a].dx(b);
      if (db != 0.0)
        for (int j = 0; j < n; ++j) d[j] += db * (*Rs[b])[j];
    }
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) K[n * i + j] += la * gaps[a]->K[n * i + j] + gaps[a]->R[i] * d[j];
  }
  return result(true, lam, slip);
}

}  // namespace bc::constraints
