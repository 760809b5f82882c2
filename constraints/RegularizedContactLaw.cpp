#include "RegularizedContactLaw.hpp"

#include <cmath>

namespace bc::constraints {

PointResult regularizedForces(const ContactKinematics& k, const PointHistory& h, double mu,
                              const RegularizedParameters& p) {
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
