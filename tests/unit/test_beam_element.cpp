// Unit tests of the co-rotational beam kernel (no MPI): tangent against central finite differences
// of the internal force at random large-rotation states; force against finite differences of the
// strain energy; the written-out force and its tangent against nested AD of the energy; rigid-body
// invariance; section constants against tabulated values.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "elements/CorotationalBeam.hpp"
#include "elements/CrossSection.hpp"
#include "support/CentralDifferences.hpp"

using namespace bc::elements;

namespace {

BeamElementData sampleElement() {
  const CrossSection cs = CrossSection::rectangle(5.0, 10.0);
  const Material m{30000.0, 0.17};
  return makeBeamElement({{1.0, 2.0, -1.0}}, {{9.0, 3.0, 1.0}}, {{0.0, 0.0, 1.0}}, m.youngsModulus * cs.area(),
                         m.shearModulus() * cs.torsionConstant(), m.youngsModulus * cs.inertiaY(),
                         m.youngsModulus * cs.inertiaZ());
}

Vec3d randomVec(std::mt19937& g, double scale) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return {{scale * u(g), scale * u(g), scale * u(g)}};
}

// A large-rotation state: a rigid rotation of up to ~2.5 rad plus deformations with local
// rotations of ~0.2 rad and a stretch of ~1 %.
BeamElementState randomState(const BeamElementData& d, std::mt19937& g) {
  const Mat3d Q = expSO3(randomVec(g, 1.4));
  const Vec3d shift = randomVec(g, 3.0);
  BeamElementState s;
  s.x1 = Q * d.X1 + shift;
  s.x2 = Q * (d.X2 + randomVec(g, 0.05 * d.L0)) + shift;
  s.R1 = Q * expSO3(randomVec(g, 0.2));
  s.R2 = Q * expSO3(randomVec(g, 0.2));
  return s;
}

BeamElementState perturbed(BeamElementState s, int dof, double h) {
  Vec3d w{};
  if (dof < 3) s.x1[dof] += h;
  else if (dof < 6) {
    w[dof - 3] = h;
    s.R1 = expSO3(w) * s.R1;
  } else if (dof < 9) s.x2[dof - 6] += h;
  else {
    w[dof - 9] = h;
    s.R2 = expSO3(w) * s.R2;
  }
  return s;
}

// The internal force at `s` with dof j moved by h, and column j of the tangent K, for the central
// differences.
auto forceAt(const BeamElementData& d, const BeamElementState& s) {
  return [&d, s](int j, double h) {
    Vector12 f;
    internalForce(d, perturbed(s, j, h), f);
    return f;
  };
}
auto columnOf(const Matrix12& K) {
  return [&K](int j) {
    Vector12 c;
    for (int i = 0; i < 12; ++i) c[i] = K[12 * i + j];
    return c;
  };
}

}  // namespace

TEST(BeamElement, TangentMatchesCentralDifferencesAtLargeRotations) {
  std::mt19937 g(42);
  const BeamElementData d = sampleElement();
  double worst = 0.0;
  for (int trial = 0; trial < 20; ++trial) {
    const BeamElementState s = randomState(d, g);
    Vector12 f;
    Matrix12 K;
    internalForceAndTangent(d, s, f, K);
    const auto [err, kmax] = bc::test::centralDifferences(12, 12, 1e-6, forceAt(d, s), columnOf(K));
    worst = std::max(worst, err / kmax);
  }
  std::printf("max relative error of the tangent over 20 random states: %.3e\n", worst);
  EXPECT_LT(worst, 1e-6);
}

TEST(BeamElement, WrittenOutGradientMatchesNestedAdOfTheEnergy) {
  // The force (the energy's gradient written out) and its AD tangent against nested AD of the
  // energy alone, at large-rotation states and at states with local rotations from 0.2 rad down to
  // 1e-7 rad (both branches of the inverse Jacobian's series switch at 1e-2 rad): equal to round-off.
  std::mt19937 g(11);
  const BeamElementData d = sampleElement();
  double worstF = 0.0, worstK = 0.0;
  for (int trial = 0; trial < 24; ++trial) {
    BeamElementState s = randomState(d, g);
    if (trial >= 12) {
      const double local = std::pow(10.0, -1.0 - 0.5 * (trial - 12));
      const Mat3d Q = expSO3(randomVec(g, 1.0));
      s.x1 = Q * d.X1;
      s.x2 = Q * (d.X2 + randomVec(g, 1e-3));
      s.R1 = Q * expSO3(randomVec(g, local));
      s.R2 = Q * expSO3(randomVec(g, local));
    }
    Vector12 f, fRef;
    Matrix12 K, KRef;
    internalForceAndTangent(d, s, f, K);
    internalForceAndTangentFromEnergy(d, s, fRef, KRef);
    double fmax = 0.0, kmax = 0.0, ef = 0.0, ek = 0.0;
    for (int i = 0; i < 12; ++i) {
      fmax = std::max(fmax, std::abs(fRef[i]));
      ef = std::max(ef, std::abs(f[i] - fRef[i]));
    }
    for (int k = 0; k < 144; ++k) {
      kmax = std::max(kmax, std::abs(KRef[k]));
      ek = std::max(ek, std::abs(K[k] - KRef[k]));
    }
    worstF = std::max(worstF, ef / fmax);
    worstK = std::max(worstK, ek / kmax);
  }
  std::printf("written-out gradient against nested AD: force %.3e, tangent %.3e (largest relative)\n", worstF, worstK);
  EXPECT_LT(worstF, 1e-11);
  EXPECT_LT(worstK, 1e-11);
}

TEST(BeamElement, ForceIsTheEnergyDerivativeAlongSpins) {
  std::mt19937 g(7);
  const BeamElementData d = sampleElement();
  double worst = 0.0;
  for (int trial = 0; trial < 10; ++trial) {
    const BeamElementState s = randomState(d, g);
    Vector12 f, f2;
    Matrix12 K;
    internalForce(d, s, f);
    internalForceAndTangent(d, s, f2, K);
    double fmax = 0.0;
    for (double v : f) fmax = std::max(fmax, std::abs(v));
    const double h = 1e-5;
    for (int j = 0; j < 12; ++j) {
      const double fd = (strainEnergy(d, perturbed(s, j, h)) - strainEnergy(d, perturbed(s, j, -h))) / (2 * h);
      worst = std::max(worst, std::abs(fd - f[j]) / fmax);
      EXPECT_NEAR(f[j], f2[j], 1e-12 * fmax);
    }
  }
  std::printf("max relative error of the force vs energy differences: %.3e\n", worst);
  EXPECT_LT(worst, 1e-6);
}

TEST(BeamElement, RigidRotationKeepsEnergyAndRotatesForces) {
  std::mt19937 g(3);
  const BeamElementData d = sampleElement();
  for (int trial = 0; trial < 10; ++trial) {
    const BeamElementState s = randomState(d, g);
    const Mat3d Q = expSO3(randomVec(g, 2.0));
    const Vec3d c = randomVec(g, 10.0);
    BeamElementState r = s;
    r.x1 = Q * s.x1 + c;
    r.x2 = Q * s.x2 + c;
    r.R1 = Q * s.R1;
    r.R2 = Q * s.R2;
    const double E = strainEnergy(d, s), Er = strainEnergy(d, r);
    EXPECT_GT(E, 0.0);
    EXPECT_NEAR(Er, E, 1e-10 * E);
    Vector12 f, fr;
    internalForce(d, s, f);
    internalForce(d, r, fr);
    double fmax = 0.0;
    for (double v : f) fmax = std::max(fmax, std::abs(v));
    for (int blk = 0; blk < 4; ++blk) {
      const Vec3d fb{{f[3 * blk], f[3 * blk + 1], f[3 * blk + 2]}};
      const Vec3d rot = Q * fb;
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(fr[3 * blk + k], rot[k], 1e-10 * fmax);
    }
  }
}

TEST(BeamElement, UndeformedStateHasNoForce) {
  const BeamElementData d = sampleElement();
  BeamElementState s{d.X1, d.X2, identity3<double>(), identity3<double>()};
  Vector12 f;
  Matrix12 K;
  internalForceAndTangent(d, s, f, K);
  for (double v : f) EXPECT_NEAR(v, 0.0, 1e-9);
  // Axial stiffness EA/L0 along the axis.
  const Vec3d e1 = column(d.T0, 0);
  double kax = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) kax += e1[i] * K[12 * (6 + i) + 6 + j] * e1[j];
  EXPECT_NEAR(kax, d.EA / d.L0, 1e-9 * d.EA / d.L0);
}

TEST(CrossSection, RectangleTorsionConstantMatchesTabulatedFactors) {
  // Timoshenko & Goodier, table of k1 in J = k1 a b^3 (a >= b): a/b = 1: 0.1406, 2: 0.229, 10: 0.312.
  EXPECT_NEAR(rectangleTorsionConstant(1.0, 1.0), 0.1406, 5e-5);
  EXPECT_NEAR(rectangleTorsionConstant(2.0, 1.0) / 2.0, 0.229, 5e-4);
  EXPECT_NEAR(rectangleTorsionConstant(1.0, 10.0) / 10.0, 0.312, 5e-4);
  // Thin-strip limit a b^3 / 3 (1 - 0.630 b/a).
  EXPECT_NEAR(rectangleTorsionConstant(1000.0, 1.0), 1000.0 / 3.0 * (1 - 0.630247 / 1000.0), 1e-3);
  const CrossSection c = CrossSection::circle(2.0);
  EXPECT_NEAR(c.torsionConstant(), std::acos(-1.0) * 8.0, 1e-12);
}

TEST(Rotation, LogInvertsExpIncludingNearPi) {
  std::mt19937 g(11);
  for (int trial = 0; trial < 200; ++trial) {
    Vec3d w = randomVec(g, 1.0);
    const double target = std::acos(-1.0) * (trial % 10) / 9.5;  // 0 .. ~0.95 pi... up to pi
    const double a = norm(w);
    w = (target / a) * w;
    const Vec3d back = logSO3(expSO3(w));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(back[k], w[k], 1e-9);
  }
}

TEST(BeamElement, TangentMatchesCentralDifferencesAtSmallLocalRotations) {
  // Short element (L0 = 0.5), large rigid rotation, local rotations from 1e-3 down to 1e-7 rad:
  // both branches of the log map (series below ~2e-5 rad) and the switch between them.
  const CrossSection cs = CrossSection::rectangle(10.0, 10.0);
  const BeamElementData d =
      makeBeamElement({{0.0, 0.0, 0.0}}, {{0.5, 0.0, 0.0}}, {{0.0, 1.0, 0.0}}, 30000.0 * cs.area(),
                      12000.0 * cs.torsionConstant(), 30000.0 * cs.inertiaY(), 30000.0 * cs.inertiaZ());
  std::mt19937 g(5);
  double worst = 0.0;
  for (double local : {1e-3, 1e-4, 3e-5, 1e-5, 1e-6, 1e-7}) {
    const Mat3d Q = expSO3(randomVec(g, 1.0));
    BeamElementState s;
    s.x1 = Q * d.X1;
    s.x2 = Q * (d.X2 + randomVec(g, 1e-4));
    s.R1 = Q * expSO3(randomVec(g, local));
    s.R2 = Q * expSO3(randomVec(g, local));
    Vector12 f;
    Matrix12 K;
    internalForceAndTangent(d, s, f, K);
    const auto [err, kmax] = bc::test::centralDifferences(12, 12, 1e-7, forceAt(d, s), columnOf(K));
    std::printf("local rotations %.0e: max relative tangent error %.3e\n", local, err / kmax);
    worst = std::max(worst, err / kmax);
  }
  EXPECT_LT(worst, 1e-6);
}
