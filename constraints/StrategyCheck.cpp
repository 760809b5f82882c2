#include "StrategyCheck.hpp"

#include <algorithm>
#include <cmath>

namespace bc::constraints {

namespace {

// Two edge lines crossing at an angle of about 80 degrees in a general orientation: beam A along X,
// beam B along Y above it, penetrating by 0.05, with finite nodal rotations.
LinePairInput crossing() {
  LinePairInput in;
  in.xA1 = {{50, 0, 0}};
  in.xA2 = {{60, 0.3, 0.2}};
  in.xB1 = {{51, -1, 7.45}};
  in.xB2 = {{52.8, 9, 7.5}};
  const Vec3d wA1{{0.02, -0.01, 0.03}}, wA2{{-0.01, 0.02, 0.01}}, wB1{{0.01, 0.03, -0.02}}, wB2{{0.02, 0.01, 0.02}};
  in.RA1 = expSO3(wA1);
  in.RA2 = expSO3(wA2);
  in.RB1 = expSO3(wB1);
  in.RB2 = expSO3(wB2);
  in.oA = {{0, 5, 5}};
  in.oB = {{2.5, 0, -2.5}};
  const Mat3d Q = expSO3(Vec3d{{0.3, -0.2, 0.5}});
  for (Vec3d* x : {&in.xA1, &in.xA2, &in.xB1, &in.xB2}) *x = Q * *x;
  for (Mat3d* R : {&in.RA1, &in.RA2, &in.RB1, &in.RB2}) *R = Q * *R;
  // Beam B moved along the normal so that the lines penetrate by 0.05.
  const ClosestPoints cp = closestPoints(in);
  const Vec3d shift = -(cp.gap + 0.05) * cp.normal;
  in.xB1 = in.xB1 + shift;
  in.xB2 = in.xB2 + shift;
  return in;
}

LinePairInput perturbed(const LinePairInput& in, int dof, double h) {
  LinePairInput p = in;
  Vec3d* x[4] = {&p.xA1, &p.xA2, &p.xB1, &p.xB2};
  Mat3d* R[4] = {&p.RA1, &p.RA2, &p.RB1, &p.RB2};
  const int node = dof / 6, k = dof % 6;
  if (k < 3) {
    (*x[node])[k] += h;
  } else {
    Vec3d w{};
    w[k - 3] = h;
    *R[node] = expSO3(w) * *R[node];
  }
  return p;
}

}  // namespace

std::vector<TangentCheck> checkTangent(const ConstraintEnforcer& strategy) {
  std::vector<TangentCheck> checks;
  const LinePairInput in = crossing();
  const ClosestPoints cp = closestPoints(in);
  // The last converged point: slid by about 0.1 along each line since then.
  const double xiPrev = cp.xi - 0.01, etaPrev = cp.eta + 0.01;
  const ContactKinematics k = contactKinematics(in, cp.sigma, xiPrev, etaPrev);
  for (FrictionLaw law : {FrictionLaw::IsotropicCoulomb, FrictionLaw::PerLine})
    for (double mu : {0.0, 0.01, 50.0}) {
      TangentCheck c;
      c.situation = std::string(law == FrictionLaw::IsotropicCoulomb ? "Isotropic Coulomb" : "Per Line") +
                    ", mu = " + (mu == 0.0 ? "0" : mu < 1.0 ? "0.01" : "50");
      auto state = strategy.newPointState();
      std::vector<double> lambda;
      auto view = [&](const ContactKinematics& kin) {
        return ContactPoint{kin, mu, law, lambda.empty() ? nullptr : lambda.data()};
      };
      auto sizeMultipliers = [&] {
        const int m = strategy.multipliers(*state);
        // A compressive normal multiplier and friction forces of both signs; further ones small.
        const double values[3] = {-20.0, 1.5, -0.7};
        lambda.resize(m);
        for (int i = 0; i < m; ++i) lambda[i] = i < 3 ? values[i] : 0.1 * (i + 1);
      };
      // Let the strategy settle its active set on this configuration, as after a converged solve.
      for (int round = 0; round < 6; ++round) {
        sizeMultipliers();
        if (!strategy.acceptNormal(view(k), *state)) continue;
        sizeMultipliers();
        double violation = 0.0;
        if (strategy.acceptPoint(view(k), *state, violation)) break;
      }
      sizeMultipliers();
      c.acts = strategy.contributes(k.normal.value, *state);
      const int n = kPairDofs + static_cast<int>(lambda.size());
      c.size = n;
      if (!c.acts) {
        checks.push_back(c);
        continue;
      }
      std::vector<double> f(n, 0.0), K(std::size_t(n) * n, 0.0), fp(n), fm(n);
      const PointResult r = strategy.evaluate(view(k), *state, f.data(), K.data());
      c.slipping = int(r.slip[0]) + int(r.slip[1]);
      for (double v : K) c.maxEntry = std::max(c.maxEntry, std::abs(v));
      for (int j = 0; j < n; ++j) {
        std::fill(fp.begin(), fp.end(), 0.0);
        std::fill(fm.begin(), fm.end(), 0.0);
        double h = 1e-6;
        if (j < kPairDofs) {
          const ContactKinematics kp = contactKinematics(perturbed(in, j, h), cp.sigma, xiPrev, etaPrev);
          const ContactKinematics km = contactKinematics(perturbed(in, j, -h), cp.sigma, xiPrev, etaPrev);
          strategy.evaluate(view(kp), *state, fp.data(), nullptr);
          strategy.evaluate(view(km), *state, fm.data(), nullptr);
        } else {
          double& l = lambda[j - kPairDofs];
          const double saved = l;
          h *= std::max(1.0, std::abs(saved));
          l = saved + h;
          strategy.evaluate(view(k), *state, fp.data(), nullptr);
          l = saved - h;
          strategy.evaluate(view(k), *state, fm.data(), nullptr);
          l = saved;
        }
        for (int i = 0; i < n; ++i)
          c.maxError = std::max(c.maxError, std::abs((fp[i] - fm[i]) / (2 * h) - K[std::size_t(n) * i + j]));
      }
      // The residual-only evaluation is the same residual.
      std::vector<double> f0(n, 0.0);
      strategy.evaluate(view(k), *state, f0.data(), nullptr);
      for (int i = 0; i < n; ++i) c.maxError = std::max(c.maxError, std::abs(f0[i] - f[i]));
      checks.push_back(c);
    }
  return checks;
}

}  // namespace bc::constraints
