// Every registered enforcement strategy (iterated from the registry, no names here): it constructs
// from its parameter specification (defaults, and the documented example of each required value), it
// acts on a penetrating point, and its tangent matches central differences of its residual for both
// friction laws, frictionless, slipping and sticking (StrategyCheck.hpp). No Tpetra, no MPI.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "constraints/EnforcerRegistry.hpp"
#include "constraints/RegularizedContactLaw.hpp"
#include "constraints/StrategyCheck.hpp"
#include "core/Parameters.hpp"

using namespace bc;

TEST(Strategies, EveryRegisteredStrategyHasATangentMatchingCentralDifferences) {
  constraints::registerBuiltinEnforcers();
  ASSERT_GE(constraints::enforcers().size(), 3u);
  for (const auto& entry : constraints::enforcers()) {
    Teuchos::ParameterList params = entry.spec->example();
    entry.spec->apply(params, entry.name);  // the example list is a valid one
    const auto strategy = entry.create(params);
    EXPECT_EQ(strategy->type(), entry.name);
    int slipping = 0, sticking = 0;
    for (const auto& c : constraints::checkTangent(*strategy)) {
      std::printf(
          "%-20s %-28s size %2d, slipping lines %d: max |K| %.3e, max |K - central differences| / max |K| = %.2e\n",
          entry.name.c_str(), c.situation.c_str(), c.size, c.slipping, c.maxEntry, c.relativeError());
      EXPECT_TRUE(c.acts) << entry.name << ", " << c.situation << ": does not act on a penetrating point";
      EXPECT_GT(c.maxEntry, 0.0) << entry.name << ", " << c.situation;
      EXPECT_LT(c.relativeError(), 1e-6) << entry.name << ", " << c.situation;
      if (c.situation.find("mu = 0.01") != std::string::npos) slipping += c.slipping;
      if (c.situation.find("mu = 50") != std::string::npos) sticking += 2 - c.slipping;
    }
    // The situations reach both branches of the return mapping.
    EXPECT_GT(slipping, 0) << entry.name;
    EXPECT_GT(sticking, 0) << entry.name;
  }
}

// Penalty with Active Set = Between Solves: an engaged point's spring is linear and bilateral for the
// Newton solve (no Regularization Gap), so its tangent is checked as the registry's default is, in every
// situation (both laws, frictionless, slipping and sticking); a Regularization Gap with it is an input
// error (it would be ignored).
TEST(Strategies, PenaltyWithItsActiveSetBetweenSolvesHasATangentMatchingCentralDifferences) {
  constraints::registerBuiltinEnforcers();
  for (const auto& entry : constraints::enforcers()) {
    if (entry.name != "Penalty") continue;
    Teuchos::ParameterList params = entry.spec->example();
    params.set("Active Set", std::string("Between Solves"));
    entry.spec->apply(params, entry.name);
    const auto strategy = entry.create(params);
    int checked = 0;
    for (const auto& c : constraints::checkTangent(*strategy)) {
      std::printf("Penalty, Between Solves: %-28s slipping lines %d: max |K - central differences| / max |K| = %.2e\n",
                  c.situation.c_str(), c.slipping, c.relativeError());
      EXPECT_TRUE(c.acts) << c.situation;
      EXPECT_LT(c.relativeError(), 1e-6) << c.situation;
      ++checked;
    }
    EXPECT_GT(checked, 0);
    Teuchos::ParameterList both = entry.spec->example();
    both.set("Active Set", std::string("Between Solves"));
    both.set("Regularization Gap", 1e-3);
    entry.spec->apply(both, entry.name);
    EXPECT_THROW(entry.create(both), core::InputError);
  }
}

// Augmented Lagrange with its active set fixed for a retried increment (ConstraintEnforcer::fixActiveSet,
// as AutomaticPenalty::relaxAfterFailure sets it where the active set changed within Newton's
// iterations): an engaged point takes the linear law lambda_hat_N + eps_N g_N, bilateral, for the
// solve; its tangent is checked as the registry's default is, in every situation (both laws,
// frictionless, slipping and sticking). With a Regularization Gap the set is not fixed.
TEST(Strategies, AugmentedLagrangeWithItsActiveSetFixedForARetryHasATangentMatchingCentralDifferences) {
  constraints::registerBuiltinEnforcers();
  for (const auto& entry : constraints::enforcers()) {
    if (entry.name != "Augmented Lagrange") continue;
    Teuchos::ParameterList params = entry.spec->example();
    params.set("Regularization Gap", 0.0);
    entry.spec->apply(params, entry.name);
    const auto strategy = entry.create(params);
    ASSERT_TRUE(strategy->canFixActiveSet());
    strategy->fixActiveSet(true);
    int checked = 0;
    for (const auto& c : constraints::checkTangent(*strategy)) {
      std::printf(
          "Augmented Lagrange, fixed set: %-28s slipping lines %d: max |K - central differences| / max |K| = "
          "%.2e\n",
          c.situation.c_str(), c.slipping, c.relativeError());
      EXPECT_TRUE(c.acts) << c.situation;
      EXPECT_LT(c.relativeError(), 1e-6) << c.situation;
      ++checked;
    }
    EXPECT_GT(checked, 0);
    strategy->fixActiveSet(false);
    Teuchos::ParameterList smooth = entry.spec->example();
    smooth.set("Regularization Gap", 1e-3);
    entry.spec->apply(smooth, entry.name);
    EXPECT_FALSE(entry.create(smooth)->canFixActiveSet());
  }
}

// The friction secant a point takes once its slip direction cycles (ContactPoint::secantFriction):
// a sliding point (g_N = -0.01, eps_N 1e4: lambda_N = -100, cone radius mu |lambda_N| = 20; slip
// g_T = (0.05, -0.03) with eps_T 1e3, lines at cosine 0.3: both lines slip under either law) with unit gap gradients,
// so that K's rows and columns 0, 1, 2 are d lambda_a / d g_b. The residual must be the law's to the
// last bit; the friction rows must not depend on g_N, and map the slip to the friction force
// (K_TT g_T = lambda_T, the secant's definition with no estimate); Newton's own tangent has no
// stiffness along the slip (K_TT M^-1 trial = 0, the projection's derivative). Both laws.
TEST(RegularizedLaw, FrictionSecantKeepsTheResidualAndMapsTheSlipToTheForce) {
  using namespace constraints;
  constexpr int n = kPairDofs;
  ContactKinematics k;
  k.normal.value = -0.01;
  k.tangent1.value = 0.05;
  k.tangent2.value = -0.03;
  k.cosine = 0.3;
  GapDerivatives* g[3] = {&k.normal, &k.tangent1, &k.tangent2};
  for (int a = 0; a < 3; ++a) g[a]->R[a] = g[a]->gradient[a] = 1.0;
  for (const FrictionLaw law : {FrictionLaw::IsotropicCoulomb, FrictionLaw::PerLine}) {
    FrictionRegularization t;
    t.penalty = 1e3;
    double f[2][n] = {}, K[2][n * n] = {};
    for (int secant = 0; secant < 2; ++secant) {
      ContactPoint p{k, 0.2, law};
      p.secantFriction = secant == 1;
      const PointResult r = regularizedEvaluate(p, linearNormalLaw(0.0, 1e4), t, f[secant], K[secant]);
      ASSERT_TRUE(r.active && r.slip[0] && r.slip[1]);
    }
    for (int i = 0; i < n; ++i) EXPECT_EQ(f[0][i], f[1][i]);
    const double gT[2] = {k.tangent1.value, k.tangent2.value}, c = k.cosine;
    // (The trial, eps_T M g_T for Isotropic Coulomb, eps_T g_T Per Line; M^-1 of it.)
    const double trial[2] = {law == FrictionLaw::IsotropicCoulomb ? 1e3 * (gT[0] - c * gT[1]) : 1e3 * gT[0],
                             law == FrictionLaw::IsotropicCoulomb ? 1e3 * (gT[1] - c * gT[0]) : 1e3 * gT[1]};
    const double along[2] = {(trial[0] + c * trial[1]) / (1 - c * c), (c * trial[0] + trial[1]) / (1 - c * c)};
    for (int i = 1; i < 3; ++i) {
      const double force = f[1][i], mapped = K[1][n * i + 1] * gT[0] + K[1][n * i + 2] * gT[1];
      const double consistent = K[0][n * i + 1] * along[0] + K[0][n * i + 2] * along[1];
      std::printf(
          "%s, friction row %d: force %.12g, secant K_TT g_T %.12g, normal coupling %g (Newton's %g), "
          "Newton's K_TT M^-1 trial %.3g\n",
          law == FrictionLaw::IsotropicCoulomb ? "Isotropic Coulomb" : "Per Line", i, force, mapped, K[1][n * i],
          K[0][n * i], consistent);
      EXPECT_NEAR(mapped, force, 1e-12 * std::abs(force));
      EXPECT_EQ(K[1][n * i], 0.0);
      EXPECT_NE(K[0][n * i], 0.0);
      if (law == FrictionLaw::IsotropicCoulomb) {
        EXPECT_NEAR(consistent, 0.0, 1e-12 * std::abs(force));
      }
    }
    // The normal row is the law's in both.
    for (int j = 0; j < n; ++j) EXPECT_EQ(K[0][j], K[1][j]);
  }
}

// Friction held in stick once its direction cycles (ContactPoint::heldFriction): the force is the
// trial, a linear spring, whatever the cone; inside the cone that is the law itself. The same point as
// above (lambda_N = -100, radius mu |lambda_N| = 20), both laws, unit gap gradients (K's rows and
// columns 0, 1, 2 are d lambda_a / d g_b):
//  - sliding (g_T = (0.05, -0.03), trial beyond the cone): held, the friction rows are the trial
//    (eps_T M g_T; Per Line eps_T g_T), no line slips, K_TT = eps_T M (Per Line eps_T I), no coupling
//    to g_N, and the tangent matches central differences of the residual (step 1e-7);
//  - sticking (g_T = (1e-3, -5e-4), trial inside): held and free give the same residual and tangent.
TEST(RegularizedLaw, HeldFrictionIsTheTrialSpringAndTheLawInsideTheCone) {
  using namespace constraints;
  constexpr int n = kPairDofs;
  const auto point = [](double gT1, double gT2) {
    ContactKinematics k;
    k.normal.value = -0.01;
    k.tangent1.value = gT1;
    k.tangent2.value = gT2;
    k.cosine = 0.3;
    GapDerivatives* g[3] = {&k.normal, &k.tangent1, &k.tangent2};
    for (int a = 0; a < 3; ++a) g[a]->R[a] = g[a]->gradient[a] = 1.0;
    return k;
  };
  const double epsT = 1e3, c = 0.3;
  for (const FrictionLaw law : {FrictionLaw::IsotropicCoulomb, FrictionLaw::PerLine}) {
    const bool isotropic = law == FrictionLaw::IsotropicCoulomb;
    FrictionRegularization t;
    t.penalty = epsT;
    const auto evaluate = [&](const ContactKinematics& k, bool held, double* f, double* K) {
      ContactPoint p{k, 0.2, law};
      p.heldFriction = held;
      return regularizedEvaluate(p, linearNormalLaw(0.0, 1e4), t, f, K);
    };
    // Sliding, held.
    std::vector<double> f(n, 0.0), K(n * n, 0.0);
    const double gT[2] = {0.05, -0.03};
    const PointResult r = evaluate(point(gT[0], gT[1]), true, f.data(), K.data());
    ASSERT_TRUE(r.active);
    EXPECT_FALSE(r.slip[0] || r.slip[1]);
    const double M[2][2] = {{1.0, isotropic ? -c : 0.0}, {isotropic ? -c : 0.0, 1.0}};
    double worst = 0.0, scale = 0.0;
    for (int i = 1; i < 3; ++i) {
      const double trial = epsT * (M[i - 1][0] * gT[0] + M[i - 1][1] * gT[1]);
      EXPECT_NEAR(f[i], trial, 1e-12 * std::abs(trial)) << "friction row " << i;
      EXPECT_EQ(K[n * i], 0.0) << "friction row " << i << " against g_N";
      for (int j = 1; j < 3; ++j) EXPECT_NEAR(K[n * i + j], epsT * M[i - 1][j - 1], 1e-9 * epsT);
    }
    // Central differences of the residual in g_N, g_T1, g_T2.
    const double h = 1e-7;
    for (int b = 0; b < 3; ++b) {
      double gp[3] = {-0.01, gT[0], gT[1]}, gm[3] = {-0.01, gT[0], gT[1]};
      gp[b] += h;
      gm[b] -= h;
      std::vector<double> fp(n, 0.0), fm(n, 0.0);
      ContactKinematics kp = point(gp[1], gp[2]), km = point(gm[1], gm[2]);
      kp.normal.value = gp[0];
      km.normal.value = gm[0];
      evaluate(kp, true, fp.data(), nullptr);
      evaluate(km, true, fm.data(), nullptr);
      for (int a = 0; a < 3; ++a) {
        worst = std::max(worst, std::abs(K[n * a + b] - (fp[a] - fm[a]) / (2 * h)));
        scale = std::max(scale, std::abs(K[n * a + b]));
      }
    }
    std::printf("%s, held: friction force (%.6g, %.6g) = trial, max |K - central differences| / max |K| = %.2e\n",
                isotropic ? "Isotropic Coulomb" : "Per Line", f[1], f[2], worst / scale);
    EXPECT_LT(worst, 1e-6 * scale);
    // Sticking: held is the law.
    std::vector<double> fh(n, 0.0), Kh(n * n, 0.0), fl(n, 0.0), Kl(n * n, 0.0);
    const PointResult rh = evaluate(point(1e-3, -5e-4), true, fh.data(), Kh.data());
    const PointResult rl = evaluate(point(1e-3, -5e-4), false, fl.data(), Kl.data());
    ASSERT_TRUE(rh.active && rl.active);
    EXPECT_FALSE(rl.slip[0] || rl.slip[1]);
    for (int i = 0; i < n; ++i) EXPECT_EQ(fh[i], fl[i]);
    for (int i = 0; i < n * n; ++i) EXPECT_EQ(Kh[i], Kl[i]);
  }
}
