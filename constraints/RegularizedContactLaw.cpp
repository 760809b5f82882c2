#include "RegularizedContactLaw.hpp"

#include <cmath>

#include "CoulombCone.hpp"

namespace bc::constraints {

namespace {

// Isotropic Coulomb: forces as functions of s = (g_N, g_T1, g_T2, c), differentiated by forward AD;
// residual and tangent assembled by the chain rule through the R vectors of s.
PointResult isotropicEvaluate(const ContactKinematics& k, const PointHistory& h, double mu,
                              const RegularizedParameters& p, double* f, double* K) {
  using F = Sacado::Fad::SFad<double, 4>;
  const F gN(4, 0, k.normal.value), c(4, 3, k.cosine);
  const F g[2] = {F(4, 1, k.tangent1.value), F(4, 2, k.tangent2.value)};
  PointResult r;
  const F lamN = h.lambdaN + p.normalPenalty * gN;
  r.active = lamN.val() < 0.0;
  if (!r.active) return r;
  F lam[3] = {lamN, F(0.0), F(0.0)};
  bool slip = false;
  if (mu > 0.0) {
    F Mg[2];
    cone::metric(c, g, Mg);
    const F trial[2] = {h.lambdaT[0] + p.tangentialPenalty * Mg[0], h.lambdaT[1] + p.tangentialPenalty * Mg[1]};
    const F radius = -mu * lamN;
    slip = cone::project(c, radius, trial, &lam[1]);
  }
  r.lambdaN = lam[0].val();
  for (int i = 0; i < 2; ++i) {
    r.lambdaT[i] = lam[1 + i].val();
    r.slip[i] = slip;
  }
  constexpr int n = kPairDofs;
  const GapDerivatives* gaps[3] = {&k.normal, &k.tangent1, &k.tangent2};
  const Vector24* Rs[4] = {&k.normal.R, &k.tangent1.R, &k.tangent2.R, &k.cosineR};
  for (int a = 0; a < 3; ++a) {
    const double la = lam[a].val();
    if (f)
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
  return r;
}

}  // namespace

PointResult regularizedForces(const ContactKinematics& k, const PointHistory& h, double mu,
                              const RegularizedParameters& p) {
  if (p.law == FrictionLaw::IsotropicCoulomb) return isotropicEvaluate(k, h, mu, p, nullptr, nullptr);
  PointResult r;
  r.lambdaN = h.lambdaN + p.normalPenalty * k.normal.value;
  r.active = r.lambdaN < 0.0;
  if (!r.active) {
    r.lambdaN = 0.0;
    return r;
  }
  const GapDerivatives* gt[2] = {&k.tangent1, &k.tangent2};
  for (int i = 0; i < 2; ++i) {
    if (mu <= 0.0) continue;
    const double trial = h.lambdaT[i] + p.tangentialPenalty * gt[i]->value;
    const double limit = -mu * r.lambdaN;
    if (std::abs(trial) <= limit) {
      r.lambdaT[i] = trial;
    } else {
      r.slip[i] = true;
      r.lambdaT[i] = std::copysign(limit, trial);
    }
  }
  return r;
}

PointResult regularizedEvaluate(const ContactKinematics& k, const PointHistory& h, double mu,
                                const RegularizedParameters& p, double* f, double* K) {
  if (p.law == FrictionLaw::IsotropicCoulomb) return isotropicEvaluate(k, h, mu, p, f, K);
  const PointResult r = regularizedForces(k, h, mu, p);
  if (!r.active) return r;
  constexpr int n = kPairDofs;
  const auto& RN = k.normal.R;
  for (int i = 0; i < n; ++i) f[i] += r.lambdaN * RN[i];
  if (K)
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) K[n * i + j] += p.normalPenalty * RN[i] * RN[j] + r.lambdaN * k.normal.K[n * i + j];
  const GapDerivatives* gt[2] = {&k.tangent1, &k.tangent2};
  for (int t = 0; t < 2; ++t) {
    if (mu <= 0.0) continue;
    const auto& RT = gt[t]->R;
    for (int i = 0; i < n; ++i) f[i] += r.lambdaT[t] * RT[i];
    if (!K) continue;
    const double lt = r.lambdaT[t];
    if (r.slip[t]) {
      const double c = -std::copysign(1.0, lt) * mu * p.normalPenalty;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) K[n * i + j] += c * RT[i] * RN[j] + lt * gt[t]->K[n * i + j];
    } else {
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
          K[n * i + j] += p.tangentialPenalty * RT[i] * RT[j] + lt * gt[t]->K[n * i + j];
    }
  }
  return r;
}

}  // namespace bc::constraints
