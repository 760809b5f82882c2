#include "StrategyCheck.hpp"

#include <algorithm>
#include <cmath>

namespace bc::constraints {

namespace {

// Two edge lines crossing at an angle of about 80 degrees in a general orientation: beam A along X,
// beam B along Y above it, penetrating by 0.05, with finite nodal rotations. `hermite`: the lines are
// the elements' Hermite curves (point contact's default), the nodes turned five times as far, so that
// the curves bend (up to 0.15 rad at the nodes); else the chords.
LinePairInput crossing(bool hermite) {
  LinePairInput in;
  in.xA1 = {{50, 0, 0}};
  in.xA2 = {{60, 0.3, 0.2}};
  in.xB1 = {{51, -1, 7.45}};
  in.xB2 = {{52.8, 9, 7.5}};
  const Vec3d wA1{{0.02, -0.01, 0.03}}, wA2{{-0.01, 0.02, 0.01}}, wB1{{0.01, 0.03, -0.02}}, wB2{{0.02, 0.01, 0.02}};
  const double turn = hermite ? 5.0 : 1.0;
  in.RA1 = expSO3(turn * wA1);
  in.RA2 = expSO3(turn * wA2);
  in.RB1 = expSO3(turn * wB1);
  in.RB2 = expSO3(turn * wB2);
  if (hermite) {
    in.dA = in.xA2 - in.xA1;  // the reference axes: the elements straight along their chords
    in.dB = in.xB2 - in.xB1;
  }
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

namespace {

// One situation (friction law and coefficient) of the crossing `in` with the last converged point at
// (xiPrev, etaPrev): the strategy settles its active set, then its tangent is compared column by column
// with central differences of its residual.
class SituationCheck {
 public:
  SituationCheck(const ConstraintEnforcer& strategy, const LinePairInput& in, const ClosestPoints& cp, double xiPrev,
                 double etaPrev, FrictionLaw law, double mu)
      : strategy_(strategy),
        in_(in),
        cp_(cp),
        xiPrev_(xiPrev),
        etaPrev_(etaPrev),
        law_(law),
        mu_(mu),
        k_(contactKinematics(in, cp.sigma, xiPrev, etaPrev)),
        state_(strategy.newPointState()) {}

  TangentCheck run(const std::string& situation) {
    TangentCheck c;
    c.situation = situation;
    settle();
    c.acts = strategy_.contributes(k_.normal.value, *state_);
    const int n = kPairDofs + static_cast<int>(lambda_.size());
    c.size = n;
    if (!c.acts) return c;
    std::vector<double> f(n, 0.0), K(std::size_t(n) * n, 0.0);
    const PointResult r = strategy_.evaluate(view(k_), *state_, f.data(), K.data());
    c.slipping = int(r.slip[0]) + int(r.slip[1]);
    for (double v : K) c.maxEntry = std::max(c.maxEntry, std::abs(v));
    for (int j = 0; j < n; ++j) c.maxError = std::max(c.maxError, columnError(j, n, K));
    // The residual-only evaluation is the same residual.
    std::vector<double> f0(n, 0.0);
    strategy_.evaluate(view(k_), *state_, f0.data(), nullptr);
    for (int i = 0; i < n; ++i) c.maxError = std::max(c.maxError, std::abs(f0[i] - f[i]));
    return c;
  }

 private:
  ContactPoint view(const ContactKinematics& kin) const {
    return ContactPoint{kin, mu_, law_, lambda_.empty() ? nullptr : lambda_.data()};
  }
  void sizeMultipliers() {
    const int m = strategy_.multipliers(*state_);
    // A compressive normal multiplier and friction forces of both signs; further ones small.
    const double values[3] = {-20.0, 1.5, -0.7};
    lambda_.resize(m);
    for (int i = 0; i < m; ++i) lambda_[i] = i < 3 ? values[i] : 0.1 * (i + 1);
  }
  // Lets the strategy settle its active set on this configuration, as after a converged solve.
  void settle() {
    for (int round = 0; round < 6; ++round) {
      sizeMultipliers();
      if (!strategy_.acceptNormal(view(k_), *state_)) continue;
      sizeMultipliers();
      double violation = 0.0;
      if (strategy_.acceptPoint(view(k_), *state_, violation)) break;
    }
    sizeMultipliers();
  }
  // max |K e_j - (f(u + h e_j) - f(u - h e_j)) / 2h| over the rows.
  double columnError(int j, int n, const std::vector<double>& K) {
    std::vector<double> fp(n, 0.0), fm(n, 0.0);
    double h = 1e-6;
    if (j < kPairDofs) {
      const ContactKinematics kp = contactKinematics(perturbed(in_, j, h), cp_.sigma, xiPrev_, etaPrev_);
      const ContactKinematics km = contactKinematics(perturbed(in_, j, -h), cp_.sigma, xiPrev_, etaPrev_);
      strategy_.evaluate(view(kp), *state_, fp.data(), nullptr);
      strategy_.evaluate(view(km), *state_, fm.data(), nullptr);
    } else {
      double& l = lambda_[j - kPairDofs];
      const double saved = l;
      h *= std::max(1.0, std::abs(saved));
      l = saved + h;
      strategy_.evaluate(view(k_), *state_, fp.data(), nullptr);
      l = saved - h;
      strategy_.evaluate(view(k_), *state_, fm.data(), nullptr);
      l = saved;
    }
    double error = 0.0;
    for (int i = 0; i < n; ++i)
      error = std::max(error, std::abs((fp[i] - fm[i]) / (2 * h) - K[std::size_t(n) * i + j]));
    return error;
  }

  const ConstraintEnforcer& strategy_;
  const LinePairInput& in_;
  const ClosestPoints& cp_;
  const double xiPrev_, etaPrev_;
  const FrictionLaw law_;
  const double mu_;
  const ContactKinematics k_;
  std::unique_ptr<PointState> state_;
  std::vector<double> lambda_;
};

}  // namespace

std::vector<TangentCheck> checkTangent(const ConstraintEnforcer& strategy) {
  std::vector<TangentCheck> checks;
  for (const bool hermite : {false, true}) {
    const LinePairInput in = crossing(hermite);
    const ClosestPoints cp = closestPoints(in);
    // The last converged point: slid by about 0.1 along each line since then.
    const double xiPrev = cp.xi - 0.01, etaPrev = cp.eta + 0.01;
    for (FrictionLaw law : {FrictionLaw::IsotropicCoulomb, FrictionLaw::PerLine})
      for (double mu : {0.0, 0.01, 50.0}) {
        const std::string situation =
            std::string(law == FrictionLaw::IsotropicCoulomb ? "Isotropic Coulomb" : "Per Line") + ", mu = " +
            (mu == 0.0  ? "0"
             : mu < 1.0 ? "0.01"
                        : "50") +
            (hermite ? ", Hermite axes" : ", chords");
        checks.push_back(SituationCheck(strategy, in, cp, xiPrev, etaPrev, law, mu).run(situation));
      }
  }
  return checks;
}

}  // namespace bc::constraints
