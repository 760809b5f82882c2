// Contact kinematics of one line pair: values against the geometry of crossed beams, first
// variations R against central differences of the gaps, and K against central differences of R
// (perturbing positions additively and rotations by spins, as the Newton update does); the point
// contact's written-out gradients against nested AD of its gaps.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "constraints/ContactKinematics.hpp"
#include "constraints/PointKey.hpp"
#include "support/CentralDifferences.hpp"

using namespace bc::constraints;
using namespace bc::math;

namespace {

// Example 1's crossing: beam A (10 x 10) along X, beam B (5 x 5) along Y at height 8; the top edge of
// A at y = +5 and the bottom edge of B at x = 52.5 (element from x = 50 to 60 on A, y from 0 to 10 on B).
LinePairInput crossing() {
  LinePairInput in;
  in.xA1 = {{50, 0, 0}};
  in.xA2 = {{60, 0, 0}};
  in.xB1 = {{50, 0, 8}};
  in.xB2 = {{50, 10, 8}};
  in.RA1 = in.RA2 = in.RB1 = in.RB2 = identity3<double>();
  in.oA = {{0, 5, 5}};
  in.oB = {{2.5, 0, -2.5}};
  return in;
}

Vec3d randomVec(std::mt19937& g, double s) {
  std::uniform_real_distribution<double> u(-1, 1);
  return {{s * u(g), s * u(g), s * u(g)}};
}

// A general state: the pair turned by a random rotation Q, its nodes moved by up to `moved` and turned
// by random rotations (up to 0.3 rad about each axis) before.
void placeGenerally(LinePairInput& in, std::mt19937& g, double moved) {
  const Mat3d Q = expSO3(randomVec(g, 1.0));
  for (Vec3d* x : {&in.xA1, &in.xA2, &in.xB1, &in.xB2}) *x = Q * (*x + randomVec(g, moved));
  for (Mat3d* R : {&in.RA1, &in.RA2, &in.RB1, &in.RB2}) *R = Q * expSO3(randomVec(g, 0.3));
}

LinePairInput perturbedState(const LinePairInput& in, int dof, double h) {
  LinePairInput p = in;
  Vec3d* x[4] = {&p.xA1, &p.xA2, &p.xB1, &p.xB2};
  Mat3d* R[4] = {&p.RA1, &p.RA2, &p.RB1, &p.RB2};
  const int node = dof / 6, k = dof % 6;
  if (k < 3) (*x[node])[k] += h;
  else {
    Vec3d w{};
    w[k - 3] = h;
    *R[node] = expSO3(w) * *R[node];
  }
  return p;
}

// The net force and moment (about the origin) of what a unit multiplier of each gap applies on the
// four nodes (R: the force and moment conjugate to each node's translation and spin): both zero for a
// force system that balances.
std::pair<double, double> unbalance(const LinePairInput& in, const ContactKinematics& k) {
  const Vec3d* x[4] = {&in.xA1, &in.xA2, &in.xB1, &in.xB2};
  double force = 0.0, moment = 0.0;
  for (const GapDerivatives* gap : {&k.normal, &k.tangent1, &k.tangent2}) {
    Vec3d F{}, M{};
    for (int m = 0; m < 4; ++m) {
      Vec3d f, c;
      for (int a = 0; a < 3; ++a) f[a] = gap->R[6 * m + a], c[a] = gap->R[6 * m + 3 + a];
      F = F + f;
      M = M + cross(*x[m], f) + c;
    }
    force = std::max(force, norm(F));
    moment = std::max(moment, norm(M));
  }
  return {force, moment};
}

// Largest relative errors of the gradients (against central differences of the gaps) and of K (against those of
// R) over the 24 dofs, for the gaps `which` of the kinematics `kernel(state)` computes at `in`.
template <class Kernel>
std::pair<double, double> centralDifferenceErrors(const LinePairInput& in, Kernel kernel,
                                                  std::initializer_list<GapDerivatives ContactKinematics::*> which) {
  const auto k = kernel(in);
  const double h = 1e-6;
  double rmax = 0, kmax = 0, errR = 0, errK = 0;
  for (auto gap : which) {
    const GapDerivatives& a = k.*gap;
    // The gradient: one row, the gap's value (R for point contact); K: the rows of R.
    const auto r = bc::test::centralDifferences(
        1, kPairDofs, h,
        [&](int j, double step) { return std::array<double, 1>{(kernel(perturbedState(in, j, step)).*gap).value}; },
        [&](int j) { return std::array<double, 1>{a.gradient[j]}; });
    const auto K = bc::test::centralDifferences(
        kPairDofs, kPairDofs, h, [&](int j, double step) { return (kernel(perturbedState(in, j, step)).*gap).R; },
        [&](int j) {
          std::array<double, kPairDofs> c;
          for (int i = 0; i < kPairDofs; ++i) c[i] = a.K[kPairDofs * i + j];
          return c;
        });
    errR = std::max(errR, r.error);
    rmax = std::max(rmax, r.largest);
    errK = std::max(errK, K.error);
    kmax = std::max(kmax, K.largest);
  }
  return {errR / rmax, errK / kmax};
}

// What a unit multiplier of gap g applies on B: its R summed over B's translations.
Vec3d onB(const GapDerivatives& g) {
  Vec3d f{};
  for (int a = 0; a < 3; ++a) f[a] = g.R[12 + a] + g.R[18 + a];
  return f;
}

// The segment planes' normals at B's nodes (tilted a little) and the sections: an edge of A (offset
// 0.3, 0.5) on the lower face of B (offset -0.5, half width 0.5), or circles of radii summing to
// radiusSum.
void segmentPlanesAndSections(LinePairInput& in, bool face, double radiusSum) {
  in.sB1 = Vec3d{{1, 0.05, 0}};
  in.sB2 = Vec3d{{1, -0.05, 0.02}};
  if (face) {
    in.oA = Vec3d{{0, 0.3, 0.5}};
    in.oB = Vec3d{{0, 0, -0.5}};
    in.face = true;
    in.nB = Vec3d{{0, 0, -1}};
    in.halfWidthB = 0.5;
  } else {
    in.radiusSum = radiusSum;
  }
}

// Circles' slip with their sections' turns (LinePairInput::turnSlip): the last converged state a
// little away from `in` (nodes moved by up to 0.05 and turned by up to 0.05 rad), A's radius 0.8.
void turnedSinceConverged(LinePairInput& in, std::mt19937& g) {
  LinePairInput converged = in;
  for (Vec3d* x : {&converged.xA1, &converged.xA2, &converged.xB1, &converged.xB2}) *x = *x + randomVec(g, 0.05);
  for (Mat3d* R : {&converged.RA1, &converged.RA2, &converged.RB1, &converged.RB2})
    *R = expSO3(randomVec(g, 0.05)) * *R;
  in.radiusA = 0.8;
  setTurnSlip(in, converged, (1.0 / 1.7) * Vec3d{{0.8, -1.5, 0.0}}, 0.4, 0.3);
}

// Circles in line contact, straight and unturned: A (radius 0.8) along X from the origin, B (radius
// 1.2) along X at z = 2, both 10 long (Hermite axes, segment planes normal to X).
LinePairInput circlesAlongX() {
  LinePairInput in;
  in.xA1 = {{0, 0, 0}};
  in.xA2 = {{10, 0, 0}};
  in.xB1 = {{0, 0, 2}};
  in.xB2 = {{10, 0, 2}};
  in.RA1 = in.RA2 = in.RB1 = in.RB2 = identity3<double>();
  in.dA = in.dB = Vec3d{{10, 0, 0}};
  in.radiusSum = 2.0;
  in.radiusA = 0.8;
  in.sB1 = in.sB2 = Vec3d{{1, 0, 0}};
  return in;
}

// The same with B turned by 10 degrees about Z through its middle (x = 5): axes at an angle.
LinePairInput tenDegreesApart(LinePairInput in) {
  const double apart = 10.0 * std::acos(-1.0) / 180.0;
  in.xB1 = {{5 - 5 * std::cos(apart), -5 * std::sin(apart), 2}};
  in.xB2 = {{5 + 5 * std::cos(apart), 5 * std::sin(apart), 2}};
  in.dB = in.xB2 - in.xB1;
  return in;
}

// The largest differences of kinematics a from b: the values relative to 1 + |b|, the R, gradients and
// K of the gaps and the first variations of xi, the cosines and the segment relative to b's largest
// entry.
struct KinematicsDifference {
  double value = 0.0, R = 0.0, K = 0.0;
  static double relative(const double* a, const double* b, std::size_t n) {
    double diff = 0.0, scale = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      diff = std::max(diff, std::abs(a[i] - b[i]));
      scale = std::max(scale, std::abs(b[i]));
    }
    return scale > 0.0 ? diff / scale : diff;
  }
  void add(const ContactKinematics& a, const ContactKinematics& b) {
    const double va[] = {a.xi, a.eta, a.cosine, a.segment, a.normal.value, a.tangent1.value, a.tangent2.value};
    const double vb[] = {b.xi, b.eta, b.cosine, b.segment, b.normal.value, b.tangent1.value, b.tangent2.value};
    for (int i = 0; i < 7; ++i) value = std::max(value, std::abs(va[i] - vb[i]) / (1.0 + std::abs(vb[i])));
    for (auto gap : {&ContactKinematics::normal, &ContactKinematics::tangent1, &ContactKinematics::tangent2}) {
      R = std::max(R, relative((a.*gap).R.data(), (b.*gap).R.data(), kPairDofs));
      R = std::max(R, relative((a.*gap).gradient.data(), (b.*gap).gradient.data(), kPairDofs));
      K = std::max(K, relative((a.*gap).K.data(), (b.*gap).K.data(), kPairDofs * kPairDofs));
    }
    for (auto field : {&ContactKinematics::cosineR, &ContactKinematics::xiR, &ContactKinematics::axesCosineR,
                       &ContactKinematics::segmentR})
      R = std::max(R, relative((a.*field).data(), (b.*field).data(), kPairDofs));
  }
};

}  // namespace

TEST(ContactKinematics, CrossedBeamsGapAndPoints) {
  const auto in = crossing();
  const auto cp = closestPoints(in);
  EXPECT_NEAR(cp.gap, 0.5, 1e-14);
  EXPECT_NEAR(cp.xi, 0.25, 1e-14);  // x = 52.5 on A's element from 50 to 60
  EXPECT_NEAR(cp.eta, 0.5, 1e-14);  // y = 5 on B's element from 0 to 10
  EXPECT_NEAR(cp.normal[2], 1.0, 1e-14);
  const auto k = contactKinematics(in, cp.sigma, 0.25, 0.5);
  EXPECT_NEAR(k.normal.value, 0.5, 1e-14);
  EXPECT_NEAR(k.tangent1.value, 0.0, 1e-14);
  // Moving B's nodes by dz changes the gap by dz: R of u_Bz is 1 - eta and eta.
  EXPECT_NEAR(k.normal.R[12 + 2], 0.5, 1e-14);
  EXPECT_NEAR(k.normal.R[18 + 2], 0.5, 1e-14);
  EXPECT_NEAR(k.normal.R[2], -0.75, 1e-14);
  EXPECT_NEAR(k.normal.R[6 + 2], -0.25, 1e-14);
  // Sliding B along A's edge by dx moves xi by dx / 10 and g_T1 by dx.
  EXPECT_NEAR(k.tangent1.R[12] + k.tangent1.R[18], 1.0, 1e-14);
}

TEST(ContactKinematics, VariationsMatchCentralDifferences) {
  std::mt19937 g(17);
  double worstR = 0.0, worstK = 0.0;
  for (int trial = 0; trial < 10; ++trial) {
    LinePairInput in = crossing();
    placeGenerally(in, g, 0.5);
    in.radiusSum = trial % 2 ? 0.7 : 0.0;
    const auto cp = closestPoints(in);
    const double xiP = cp.xi - 0.05, etaP = cp.eta + 0.03;
    const auto [errR, errK] = centralDifferenceErrors(
        in, [&](const LinePairInput& s) { return contactKinematics(s, cp.sigma, xiP, etaP); },
        {&ContactKinematics::normal, &ContactKinematics::tangent1, &ContactKinematics::tangent2});
    worstR = std::max(worstR, errR);
    worstK = std::max(worstK, errK);
  }
  std::printf("max relative error: R (first variations) %.2e, K (linearized variations) %.2e\n", worstR, worstK);
  EXPECT_LT(worstR, 1e-6);
  EXPECT_LT(worstK, 1e-6);
}

// Line contact at a Gauss point: two parallel circular beams (axes along X, B 2.5 above A, radii
// summing to 2): at xi = 0.3 on A's element from x = 0 to 10 the projection on B's element from
// x = -2 to 8 is eta = 0.5, the gap 0.5, the normal +Z; moving B up by dz opens the gap by dz, shared
// by B's nodes as 1 - eta and eta; A's point (material) moves with its nodes as 1 - xi and xi.
TEST(LineKinematics, ParallelBeamsGapAndProjection) {
  LinePairInput in;
  in.xA1 = {{0, 0, 0}};
  in.xA2 = {{10, 0, 0}};
  in.xB1 = {{-2, 0, 2.5}};
  in.xB2 = {{8, 0, 2.5}};
  in.RA1 = in.RA2 = in.RB1 = in.RB2 = identity3<double>();
  in.radiusSum = 2.0;
  const auto cp = lineProjection(in, 0.3);
  EXPECT_NEAR(cp.eta, 0.5, 1e-14);
  EXPECT_NEAR(cp.gap, 0.5, 1e-14);
  EXPECT_NEAR(cp.normal[2], 1.0, 1e-14);
  EXPECT_NEAR(cp.sinAngle, 0.0, 1e-14);
  const auto k = lineKinematics(in, 0.3, 0.45);
  EXPECT_NEAR(k.normal.value, 0.5, 1e-14);
  EXPECT_NEAR(k.normal.R[12 + 2], 0.5, 1e-14);
  EXPECT_NEAR(k.normal.R[18 + 2], 0.5, 1e-14);
  EXPECT_NEAR(k.normal.R[2], -0.7, 1e-14);
  EXPECT_NEAR(k.normal.R[6 + 2], -0.3, 1e-14);
  EXPECT_NEAR(k.tangent2.value, 0.05 * 10, 1e-13);  // (eta - etaPrev) |t_B|
  EXPECT_NEAR(k.tangent1.value, 0.0, 0.0);
}

// The cubic axis: B's nodes turned about Y by -phi and +phi (tangents R e1 L0), so its axis is
// z = 2.5 + L0 sin(phi) (u - u^2), x = L0 [3u^2 - 2u^3 + cos(phi) (u - 3u^2 + 2u^3)]: at u = 1/2 it passes
// (5, 0, 2.5 + 2.5 sin phi) with a horizontal tangent, so A's point (5, 0, 0) (xi = 1/2 on the straight
// element below) projects there and the gap is 0.5 + 2.5 sin phi.
TEST(LineKinematics, CubicAxisFollowsTheNodalRotations) {
  for (const double phi : {0.1, -0.2}) {
    LinePairInput in;
    in.xA1 = {{0, 0, 0}};
    in.xA2 = {{10, 0, 0}};
    in.xB1 = {{0, 0, 2.5}};
    in.xB2 = {{10, 0, 2.5}};
    in.RA1 = in.RA2 = identity3<double>();
    in.RB1 = expSO3(Vec3d{{0, -phi, 0}});
    in.RB2 = expSO3(Vec3d{{0, phi, 0}});
    in.dA = in.dB = Vec3d{{10, 0, 0}};
    in.radiusSum = 2.0;
    const auto cp = lineProjection(in, 0.5);
    EXPECT_NEAR(cp.eta, 0.5, 1e-12);
    EXPECT_NEAR(cp.gap, 0.5 + 2.5 * std::sin(phi), 1e-12);
    EXPECT_NEAR(cp.pB[0], 5.0, 1e-12);
    EXPECT_NEAR(lineKinematics(in, 0.5, 0.5).normal.value, 0.5 + 2.5 * std::sin(phi), 1e-12);
    // A point off the middle: the projection where B's tangent is normal to p_B - p_A (checked
    // against the curve sampled finely).
    const auto off = lineProjection(in, 0.2);
    double best = 1e300;
    for (int i = 0; i <= 200000; ++i) {
      const double u = i / 200000.0,
                   x = 10 * (3 * u * u - 2 * u * u * u + std::cos(phi) * (u - 3 * u * u + 2 * u * u * u));
      const double z = 2.5 + 10 * std::sin(phi) * (u - u * u);
      best = std::min(best, std::hypot(x - 2.0, z));
    }
    EXPECT_NEAR(off.distance, best, 1e-9);
  }
}

TEST(LineKinematics, VariationsMatchCentralDifferences) {
  std::mt19937 g(23);
  double worstR = 0.0, worstK = 0.0;
  for (int trial = 0; trial < 10; ++trial) {
    LinePairInput in;
    in.xA1 = {{0, 0, 0}};
    in.xA2 = {{10, 0, 0}};
    in.xB1 = {{-2, 0.3, 2.5}};
    in.xB2 = {{8, -0.2, 2.6}};  // nearly parallel, not exactly
    in.oA = trial % 2 ? Vec3d{{0, 0.4, 0.2}} : Vec3d{};  // off-axis lines too (general offsets)
    in.oB = trial % 2 ? Vec3d{{0, -0.3, 0.1}} : Vec3d{};
    // Cubic (Hermite) axes through the nodal rotations in most trials, straight chords in some.
    if (trial % 3 != 0) {
      in.dA = Vec3d{{10, 0, 0}};
      in.dB = Vec3d{{10, -0.5, 0.1}};
    }
    placeGenerally(in, g, 0.3);
    in.radiusSum = 2.0;
    if (trial % 2 == 0) turnedSinceConverged(in, g);  // (circles on the axes: their turns' slip)
    const double xi = 0.1 + 0.08 * trial, etaP = 0.4;
    const auto [errR, errK] = centralDifferenceErrors(
        in, [&](const LinePairInput& s) { return lineKinematics(s, xi, etaP); },
        {&ContactKinematics::normal, &ContactKinematics::tangent1, &ContactKinematics::tangent2});
    worstR = std::max(worstR, errR);
    worstK = std::max(worstK, errK);
  }
  std::printf("line contact, max relative error: R %.2e, K %.2e\n", worstR, worstK);
  EXPECT_LT(worstR, 1e-6);
  EXPECT_LT(worstK, 1e-6);
}

// Circles in line contact slip with their sections' turns (LinePairInput::turnSlip): A (radius 0.8)
// along X under B (radius 1.2) along X at z = 2, both straight at the last converged state. A rolled
// by phi about Y through its point at xi = 0.5 keeps that point, so its projection on B stays; its
// surface point there, (5, 0, 0.8), goes by 0.8 sin(phi) along X: g_T2 = r_A sin(phi) exactly, on the
// point's own parameters and on its segment. B rolled by phi about Y through its point above: B's
// surface point (5, 0, 0.8) goes by -r_B sin(phi), so A's slips by r_B sin(phi) relative to B: the axis
// point's slip (r_A + r_B) sin(phi) (A's point projects 2 sin(phi) further along B's turned axis) less
// r_A [(t_B - t_B,p) . n] = r_A sin(phi). Without turnSlip A's roll gives 0.
TEST(LineKinematics, CirclesSlipAsTheirSectionsTurn) {
  const LinePairInput straight = circlesAlongX();
  const auto rolled = [&](bool rollA, double phi) {
    LinePairInput in = straight;
    const Mat3d Q = expSO3(Vec3d{{0, phi, 0}});
    const Vec3d centre{{5, 0, rollA ? 0.0 : 2.0}};
    for (Vec3d* x : rollA ? std::vector<Vec3d*>{&in.xA1, &in.xA2} : std::vector<Vec3d*>{&in.xB1, &in.xB2})
      *x = centre + Q * (*x - centre);
    for (Mat3d* R : rollA ? std::vector<Mat3d*>{&in.RA1, &in.RA2} : std::vector<Mat3d*>{&in.RB1, &in.RB2}) *R = Q;
    setTurnSlip(in, straight, Vec3d{{0, 0, -1}}, 0.5, 0.5);  // (the normal from B's axis to A's)
    return in;
  };
  const double phi = 0.2;
  const LinePairInput a = rolled(true, phi);
  const LineSegment seg = lineSegment(a);
  ASSERT_NEAR(seg.length(), 1.0, 1e-12);
  const double onPoint = lineKinematics(a, 0.5, 0.5, Vec3d{}).tangent2.value;
  const double onSegment = segmentKinematics(a, seg, 0.5, LineHistory{0.5, 0.5, 1.0}, Vec3d{}).tangent2.value;
  const double nested = lineKinematicsFromGaps(a, 0.5, 0.5, Vec3d{}).tangent2.value;
  std::printf("A rolled by %.1f: g_T2 %.15f %.15f %.15f, r_A sin(phi) %.15f\n", phi, onPoint, onSegment, nested,
              0.8 * std::sin(phi));
  EXPECT_NEAR(onPoint, 0.8 * std::sin(phi), 1e-13);
  EXPECT_NEAR(onSegment, 0.8 * std::sin(phi), 1e-13);
  EXPECT_NEAR(nested, 0.8 * std::sin(phi), 1e-13);
  EXPECT_NEAR(surfaceSlips(a, 0.5, 0.5, 0.5, Vec3d{{0, 0, -1}})[1], 0.8 * std::sin(phi), 1e-13);
  LinePairInput axisOnly = a;
  axisOnly.turnSlip = false;
  EXPECT_NEAR(lineKinematics(axisOnly, 0.5, 0.5, Vec3d{}).tangent2.value, 0.0, 1e-13);
  const LinePairInput b = rolled(false, phi);
  const double slipB = lineKinematics(b, 0.5, 0.5, Vec3d{}).tangent2.value;
  std::printf("B rolled by %.1f: g_T2 %.15f, r_B sin(phi) %.15f\n", phi, slipB, 1.2 * std::sin(phi));
  EXPECT_NEAR(slipB, 1.2 * std::sin(phi), 1e-13);
  // A rigid turn of the pair, its axes 10 degrees apart (twisting rods, strands): no slip to first
  // order in the turn (the sections' turns are measured to first order: their difference is of second
  // order, and a step's turns are small). A turn part from the axes' unit tangents alone,
  // r_A [(t_A - t_A,p) - (t_B - t_B,p)] . n, is r_A (w x (t_A - t_B)) . n for a turn w: of first order
  // where the axes are apart (r_A |w| sin(10 deg) here), friction on rods that turn together.
  const LinePairInput crossed = tenDegreesApart(straight);
  const ClosestPoints before = lineProjection(crossed, 0.3);
  for (const Vec3d axis : {Vec3d{{0, 0, 1}}, Vec3d{{0.6, -0.48, 0.64}}, Vec3d{{1, 0, 0}}}) {
    double previous = 0.0;
    for (const double angle : {1e-2, 5e-3}) {
      LinePairInput turned = crossed;
      const Mat3d Q = expSO3(angle * axis);
      for (Vec3d* x : {&turned.xA1, &turned.xA2, &turned.xB1, &turned.xB2}) *x = Q * *x;
      for (Mat3d* R : {&turned.RA1, &turned.RA2, &turned.RB1, &turned.RB2}) *R = Q;
      setTurnSlip(turned, crossed, -1.0 * before.normal, 0.3, before.eta);
      const double rigid = lineKinematics(turned, 0.3, before.eta, Vec3d{}).tangent2.value;
      const double firstOrder = 0.8 * angle * std::sin(10.0 * std::acos(-1.0) / 180.0);
      std::printf(
          "pair 10 degrees apart turned rigidly by %.0e about (%.2f, %.2f, %.2f): g_T2 %.2e, r_A w sin(10) %.2e\n",
          angle, axis[0], axis[1], axis[2], rigid, firstOrder);
      EXPECT_LT(std::abs(rigid), 0.02 * firstOrder);
      EXPECT_NEAR(surfaceSlips(turned, 0.3, before.eta, before.eta, -1.0 * (Q * before.normal))[1], rigid, 1e-15);
      if (previous != 0.0) {
        EXPECT_NEAR(rigid / previous, 0.25, 0.02);  // (second order)
      }
      previous = rigid;
    }
  }
}

// Circles in line contact slip across their axes (g_T1, LinePairInput::turnSlip) as their sections
// twist: A (radius 0.8) along X under B (radius 1.2) along X at z = 2, the normal from B's axis to A's
// -Z, b = n x t_B = -Y. A twisted by phi about X: its surface point (5, 0, 0.8) goes to (5, -0.8 sin(phi),
// 0.8 cos(phi)), g_T1 = r_A sin(phi) exactly; B twisted: r_B sin(phi); both, as gears (r_A sin(phi_A) =
// -r_B sin(phi_B)): 0. A pushed across by 0.1 along -Y (b): the slip is the push. A rigid turn of the
// pair 10 degrees apart
// slips by 0 to round-off (the converged normal made normal to each axis is carried by the nodes).
// The unit multiplier applies a unit force along -b on B at its contact point, x_B + r_B n.
TEST(LineKinematics, CirclesSlipAcrossAsTheirSectionsTwist) {
  const LinePairInput straight = circlesAlongX();
  const auto twisted = [&](double phiA, double phiB, double pushed) {
    LinePairInput in = straight;
    for (Mat3d* R : {&in.RA1, &in.RA2}) *R = expSO3(Vec3d{{phiA, 0, 0}});
    for (Mat3d* R : {&in.RB1, &in.RB2}) *R = expSO3(Vec3d{{phiB, 0, 0}});
    for (Vec3d* x : {&in.xA1, &in.xA2}) *x = *x + Vec3d{{0, -pushed, 0}};
    setTurnSlip(in, straight, Vec3d{{0, 0, -1}}, 0.5, 0.5);
    return in;
  };
  const auto across = [](const LinePairInput& in, double xi) {
    const ClosestPoints cp = lineProjection(in, xi);
    const double values[4] = {
        lineKinematics(in, xi, 0.5, Vec3d{}).tangent1.value,
        lineKinematicsFromGaps(in, xi, 0.5, Vec3d{}).tangent1.value,
        segmentKinematics(in, lineSegment(in), xi, LineHistory{xi, 0.5, 1.0}, Vec3d{}).tangent1.value,
        surfaceSlips(in, xi, 0.5, cp.eta, -1.0 * cp.normal)[0]};
    for (double v : values) EXPECT_NEAR(v, values[0], 1e-14);
    return values[0];
  };
  const double phi = 0.3, rA = 0.8, rB = 1.2;
  const double twistA = across(twisted(phi, 0.0, 0.0), 0.5), twistB = across(twisted(0.0, phi, 0.0), 0.3);
  const double gears = across(twisted(phi, -std::asin(rA * std::sin(phi) / rB), 0.0), 0.7);
  std::printf("twisted by %.1f: A %.15f (r_A sin %.15f), B %.15f (r_B sin %.15f), as gears %.1e\n", phi, twistA,
              rA * std::sin(phi), twistB, rB * std::sin(phi), gears);
  EXPECT_NEAR(twistA, rA * std::sin(phi), 1e-14);
  EXPECT_NEAR(twistB, rB * std::sin(phi), 1e-14);
  EXPECT_NEAR(gears, 0.0, 1e-14);
  // Pushed across by 0.1: the normal turns by psi, tan(psi) = 0.1 / 2, and the axes move apart, g =
  // sqrt(4.01) - 2. The contact point lies midway between the surfaces (rho = r + g / 2, rho_A + rho_B
  // the axes' distance), its material points have not turned: -(rho_A + rho_B) n_p . b =
  // sqrt(4.01) sin(psi) = 0.1, the push.
  const double pushed = across(twisted(0.0, 0.0, 0.1), 0.5);
  std::printf("pushed across by 0.1: %.15f\n", pushed);
  EXPECT_NEAR(pushed, 0.1, 1e-14);
  LinePairInput none = twisted(phi, 0.0, 0.0);
  none.turnSlip = false;
  EXPECT_EQ(lineKinematics(none, 0.5, 0.5, Vec3d{}).tangent1.value, 0.0);
  // A unit multiplier: a unit force along -b = +Y on B (its translations' rows) at B's contact point.
  const ContactKinematics k = lineKinematics(twisted(0.0, 0.0, 0.0), 0.5, 0.5, Vec3d{});
  Vec3d forceB{}, momentB{};
  for (int m = 2; m < 4; ++m)
    for (int a = 0; a < 3; ++a) forceB[a] += k.tangent1.R[6 * m + a], momentB[a] += k.tangent1.R[6 * m + 3 + a];
  std::printf("unit multiplier across on B: force (%.3f, %.3f, %.3f), moment about its axis %.15f\n", forceB[0],
              forceB[1], forceB[2], momentB[0]);
  EXPECT_NEAR(norm(forceB - Vec3d{{0, 1, 0}}), 0.0, 1e-14);
  EXPECT_NEAR(momentB[0], rB, 1e-14);  // ((r_B n) x (0, 1, 0), n = -Z)
  // Overlapping by 0.05 (a penalty's state): the unit multiplier's forces on the two bodies act at one
  // point, midway between the surfaces, so they balance in force and moment. Twisted since the last
  // converged state by s and -2 s, they act at the two material points that were there: apart along
  // n by (rho_A + rho_B) (1 - cos) terms, a moment of second order in the twist (a step's).
  const auto netMoment = [&](double s) {
    LinePairInput deep = twisted(s, -2.0 * s, 0.0);
    for (Vec3d* x : {&deep.xA1, &deep.xA2}) *x = *x + Vec3d{{0, 0, 0.05}};
    const ContactKinematics kd = lineKinematics(deep, 0.4, 0.5, Vec3d{});
    Vec3d F{}, M{};
    const Vec3d* nodesAt[4] = {&deep.xA1, &deep.xA2, &deep.xB1, &deep.xB2};
    for (int m = 0; m < 4; ++m) {
      Vec3d f, c;
      for (int a = 0; a < 3; ++a) f[a] = kd.tangent1.R[6 * m + a], c[a] = kd.tangent1.R[6 * m + 3 + a];
      F = F + f;
      M = M + cross(*nodesAt[m], f) + c;
    }
    EXPECT_LT(norm(F), 1e-14) << s;
    return norm(M);
  };
  const double m0 = netMoment(0.0), m1 = netMoment(1e-2), m2 = netMoment(5e-3);
  std::printf("overlapping by 0.05: unit multiplier across, net moment %.1e; twisted by 1e-2 / 5e-3: %.2e / %.2e\n", m0,
              m1, m2);
  EXPECT_LT(m0, 1e-14);
  EXPECT_NEAR(m1 / m2, 4.0, 0.2);
  // A rigid turn of a pair whose axes lie 10 degrees apart.
  const LinePairInput crossed = tenDegreesApart(straight);
  const ClosestPoints before = lineProjection(crossed, 0.3);
  double worst = 0.0;
  for (const Vec3d axis : {Vec3d{{0, 0, 1}}, Vec3d{{0.6, -0.48, 0.64}}, Vec3d{{1, 0, 0}}}) {
    LinePairInput turned = crossed;
    const Mat3d Q = expSO3(0.2 * axis);
    for (Vec3d* x : {&turned.xA1, &turned.xA2, &turned.xB1, &turned.xB2}) *x = Q * *x;
    for (Mat3d* R : {&turned.RA1, &turned.RA2, &turned.RB1, &turned.RB2}) *R = Q;
    setTurnSlip(turned, crossed, -1.0 * before.normal, 0.3, before.eta);
    worst = std::max(worst, std::abs(lineKinematics(turned, 0.3, before.eta, Vec3d{}).tangent1.value));
  }
  std::printf("pair 10 degrees apart turned rigidly by 0.2: g_T1 %.1e\n", worst);
  EXPECT_LT(worst, 1e-14);
}

// Face contact of rectangular sections: an edge of A (axis at z = 0.5, edge offset (0, 0.3, 0.5), so
// at y = 0.3, z = 1) under the lower face of B (axis at z = 1.6, face offset (0, 0, -0.5), outward
// normal -Z, half width 0.5): gap 0.1 along the normal, lateral offset 0.3; lifting B by dz opens the
// gap by dz. Then R and K against central differences at general states.
TEST(LineKinematics, FaceContactOfRectangles) {
  LinePairInput in;
  in.xA1 = {{0, 0, 0.5}};
  in.xA2 = {{10, 0, 0.5}};
  in.xB1 = {{-2, 0, 1.6}};
  in.xB2 = {{8, 0, 1.6}};
  in.RA1 = in.RA2 = in.RB1 = in.RB2 = identity3<double>();
  in.oA = Vec3d{{0, 0.3, 0.5}};
  in.oB = Vec3d{{0, 0, -0.5}};
  in.dA = in.dB = Vec3d{{10, 0, 0}};
  in.face = true;
  in.nB = Vec3d{{0, 0, -1}};
  in.halfWidthB = 0.5;
  const auto cp = lineProjection(in, 0.3);
  EXPECT_NEAR(cp.eta, 0.5, 1e-14);
  EXPECT_NEAR(cp.gap, 0.1, 1e-14);
  EXPECT_NEAR(cp.lateral, 0.3, 1e-14);
  const auto k = lineKinematics(in, 0.3, 0.45);
  EXPECT_NEAR(k.normal.value, 0.1, 1e-14);
  EXPECT_NEAR(k.normal.R[12 + 2], 0.5, 1e-14);
  EXPECT_NEAR(k.normal.R[18 + 2], 0.5, 1e-14);
  // A's point moves with its nodes by the cubic shape functions H1(0.3) = 0.784, H3(0.3) = 0.216.
  EXPECT_NEAR(k.normal.R[2], -0.784, 1e-14);
  EXPECT_NEAR(k.normal.R[6 + 2], -0.216, 1e-14);
  std::mt19937 g(31);
  double worstR = 0.0, worstK = 0.0, worstNormal = 0.0, worstTangent = 0.0;
  for (int trial = 0; trial < 10; ++trial) {
    LinePairInput t = in;
    placeGenerally(t, g, 0.3);
    const double xi = 0.1 + 0.08 * trial;
    const auto [errR, errK] =
        centralDifferenceErrors(t, [&](const LinePairInput& s) { return lineKinematics(s, xi, 0.4); },
                                {&ContactKinematics::normal, &ContactKinematics::tangent2});
    worstR = std::max(worstR, errR);
    worstK = std::max(worstK, errK);
    // What unit multipliers apply on B (R summed over its translations): the face's normal at the
    // projection (cp.normal, from A towards B) and a unit vector along B, so that the friction force
    // is mu times the normal one (docs/contact.md, "The Coulomb cone on lines"). The bent, turned
    // elements' interpolated normal is not normal to B's cubic axis: with the projection's motion in
    // the normal gap's variation, R_N was off the normal by up to 0.31 here.
    const auto k = lineKinematics(t, xi, 0.4);
    const auto cp = lineProjection(t, xi);
    worstNormal = std::max(worstNormal, norm(onB(k.normal) + (-1.0) * cp.normal));
    worstTangent = std::max(worstTangent, std::abs(norm(onB(k.tangent2)) - 1.0));
  }
  std::printf(
      "face contact, max relative error: R %.2e, K %.2e; unit multipliers on B: normal off by %.2e, "
      "tangent's length off by %.2e\n",
      worstR, worstK, worstNormal, worstTangent);
  EXPECT_LT(worstR, 1e-6);
  EXPECT_LT(worstK, 1e-6);
  EXPECT_LT(worstNormal, 1e-13);
  EXPECT_LT(worstTangent, 1e-13);
}

// Segments of line contact. A's axis runs along X from 0 to 10; B, parallel at height 2.5, from x0 to
// x0 + 10 with its node planes normal to X: A's points between the planes are x in [x0, x0 + 10], so
// the segment is [max(0, x0 / 10), min(1, x0 / 10 + 1)] of A's element, bounded by a plane where it
// lies inside. Then R and K of the gaps, and the first variations of the Gauss point's xi and of the
// segment's length, against central differences at general states (both bounds planes, one, none;
// circles and faces; cubic axes and chords), the plane normals turning with B's nodes.
// A segment's bounds against brute force: A's element (cubic, its nodes turned by up to 0.6 rad, so
// that its extension beyond the element's ends bends away) and B's element nearly parallel, its node
// planes tilted by up to 0.3 rad and placed so that they cut A inside its element, just beyond its
// ends, or far beyond. The reference marks 200001 points of A's element between the planes (the
// segment: from the first to the last). A root of the plane's equation on the cubic's extension,
// where Newton's method from the chord's root wanders between roots or diverges, must not decide
// the segment: before, such configurations lost their segment (empty) while A's element lay between
// the planes, and the contact force jumped with the dofs.
TEST(LineKinematics, SegmentEqualsThePointsBetweenThePlanes) {
  std::mt19937 g(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  constexpr int kSamples = 200000;
  int cut = 0, whole = 0, none = 0;
  double worst = 0.0, worstRoot = 0.0;
  for (int trial = 0; trial < 400; ++trial) {
    LinePairInput in;
    in.xA1 = {{0, 0, 0}};
    in.xA2 = {{10, 0, 0}};
    in.dA = in.dB = Vec3d{{10, 0, 0}};
    in.RA1 = expSO3(Vec3d{{0.0, 0.6 * u(g), 0.6 * u(g)}});
    in.RA2 = expSO3(Vec3d{{0.0, 0.6 * u(g), 0.6 * u(g)}});
    const double x0 = 14.0 * u(g), lB = 10.0 + 4.0 * u(g);
    in.xB1 = {{x0, 0.2 * u(g), 2.5}};
    in.xB2 = {{x0 + lB, 0.2 * u(g), 2.5}};
    in.RB1 = expSO3(Vec3d{{0.0, 0.3 * u(g), 0.3 * u(g)}});
    in.RB2 = expSO3(Vec3d{{0.0, 0.3 * u(g), 0.3 * u(g)}});
    in.sB1 = in.sB2 = Vec3d{{1, 0, 0}};
    in.radiusSum = 2.0;
    const Vec3d P[2] = {in.xA1, in.xA2}, V[2] = {in.RA1 * in.dA, in.RA2 * in.dA};
    const Vec3d tau[2] = {in.RB1 * in.sB1, in.RB2 * in.sB2};
    const auto plane = [&](int j, double xi) {
      // The Hermite cubic (docs/contact.md, "The axes are cubic curves").
      const double h1 = 1 - 3 * xi * xi + 2 * xi * xi * xi, h2 = xi - 2 * xi * xi + xi * xi * xi,
                   h3 = 3 * xi * xi - 2 * xi * xi * xi, h4 = xi * xi * xi - xi * xi;
      const Vec3d x = h1 * P[0] + h2 * V[0] + h3 * P[1] + h4 * V[1];
      return dot(tau[j], x - (j == 0 ? in.xB1 : in.xB2));
    };
    double first = 2.0, last = -1.0;
    for (int i = 0; i <= kSamples; ++i) {
      const double xi = double(i) / kSamples;
      if (plane(0, xi) >= 0.0 && plane(1, xi) <= 0.0) first = std::min(first, xi), last = std::max(last, xi);
    }
    const LineSegment seg = lineSegment(in);
    if (last < first) {
      ++none;
      EXPECT_EQ(seg.length(), 0.0) << trial;
      continue;
    }
    (first == 0.0 && last == 1.0 ? whole : cut)++;
    ASSERT_GT(seg.length(), 0.0) << trial;
    worst = std::max({worst, std::abs(seg.lo - first), std::abs(seg.hi - last)});
    for (const auto [kind, at] : {std::make_pair(seg.loKind, seg.lo), std::make_pair(seg.hiKind, seg.hi)}) {
      if (kind < 0) {
        EXPECT_TRUE(at == 0.0 || at == 1.0) << trial;
      } else {
        worstRoot = std::max(worstRoot, std::abs(plane(kind, at)));
      }
    }
  }
  std::printf(
      "segments: %d cut by a plane, %d whole, %d none; bounds within %.1e of the sampled ones, plane "
      "residual at the roots %.1e\n",
      cut, whole, none, worst, worstRoot);
  EXPECT_GT(cut, 50);
  EXPECT_GT(whole, 10);
  EXPECT_GT(none, 10);
  EXPECT_LT(worst, 1.0 / kSamples);
  EXPECT_LT(worstRoot, 1e-12);
}

TEST(LineKinematics, SegmentBoundsAndTheirVariations) {
  LinePairInput in;
  in.xA1 = {{0, 0, 0}};
  in.xA2 = {{10, 0, 0}};
  in.RA1 = in.RA2 = in.RB1 = in.RB2 = identity3<double>();
  in.dA = in.dB = Vec3d{{10, 0, 0}};
  in.sB1 = in.sB2 = Vec3d{{1, 0, 0}};
  in.radiusSum = 2.0;
  for (double x0 : {-2.0, 3.0, -12.0, 11.0}) {
    in.xB1 = {{x0, 0, 2.5}};
    in.xB2 = {{x0 + 10, 0, 2.5}};
    const LineSegment seg = lineSegment(in);
    const double lo = std::max(0.0, x0 / 10), hi = std::min(1.0, x0 / 10 + 1);
    if (hi <= lo) {
      EXPECT_EQ(seg.length(), 0.0) << x0;
      continue;
    }
    EXPECT_NEAR(seg.lo, lo, 1e-14) << x0;
    EXPECT_NEAR(seg.hi, hi, 1e-14) << x0;
    EXPECT_EQ(seg.loKind, x0 > 0 ? 0 : -1);
    EXPECT_EQ(seg.hiKind, x0 < 0 ? 1 : -1);
    // At the segment's midpoint: gap 0.5, xi and the length as above; moving B's node 2 along X by dx
    // moves the upper plane (x0 < 0) and so the length by dx / 10 and the midpoint by dx / 20.
    const auto k = segmentKinematics(in, seg, 0.5, LineHistory{});
    EXPECT_NEAR(k.normal.value, 0.5, 1e-13);
    EXPECT_NEAR(k.xi, 0.5 * (lo + hi), 1e-14);
    EXPECT_NEAR(k.segment, hi - lo, 1e-14);
    EXPECT_NEAR(k.segmentR[18], x0 < 0 ? 0.1 : 0.0, 1e-14);
    EXPECT_NEAR(k.xiR[18], x0 < 0 ? 0.05 : 0.0, 1e-14);
  }
  std::mt19937 g(37);
  double worstR = 0.0, worstK = 0.0, worstXi = 0.0, worstLength = 0.0;
  int planes = 0;
  for (int trial = 0; trial < 12; ++trial) {
    LinePairInput t;
    t.xA1 = {{0, 0, 0}};
    t.xA2 = {{10, 0, 0}};
    const double x0 = trial % 3 == 0 ? 2.0 : (trial % 3 == 1 ? -3.0 : 1.0), lB = trial % 3 == 2 ? 6.0 : 10.0;
    t.xB1 = {{x0, 0.3, 2.5}};
    t.xB2 = {{x0 + lB, -0.2, 2.6}};
    if (trial % 4 != 3) {
      t.dA = Vec3d{{10, 0, 0}};
      t.dB = Vec3d{{lB, -0.5, 0.1}};
    }
    segmentPlanesAndSections(t, trial % 2, 2.0);
    placeGenerally(t, g, 0.3);
    if (trial % 4 == 0) turnedSinceConverged(t, g);  // (circles: some with their turns' slips)
    const LineHistory history{0.4, 0.3, 0.9};
    const double s = 0.15 + 0.06 * trial;
    const auto kernel = [&](const LinePairInput& state) {
      return segmentKinematics(state, lineSegment(state), s, history);
    };
    const LineSegment seg = lineSegment(t);
    planes += (seg.loKind >= 0) + (seg.hiKind >= 0);
    ASSERT_GT(seg.length(), 0.1);
    const auto [errR, errK] = centralDifferenceErrors(
        t, kernel, {&ContactKinematics::normal, &ContactKinematics::tangent1, &ContactKinematics::tangent2});
    worstR = std::max(worstR, errR);
    worstK = std::max(worstK, errK);
    const auto k = kernel(t);
    // The Gauss point's parameter and length: one row each.
    const auto xi = bc::test::centralDifferences(
        1, kPairDofs, 1e-6, [&](int j, double h) { return std::array<double, 1>{kernel(perturbedState(t, j, h)).xi}; },
        [&](int j) { return std::array<double, 1>{k.xiR[j]}; });
    const auto length = bc::test::centralDifferences(
        1, kPairDofs, 1e-6,
        [&](int j, double h) { return std::array<double, 1>{kernel(perturbedState(t, j, h)).segment}; },
        [&](int j) { return std::array<double, 1>{k.segmentR[j]}; });
    const double xiMax = xi.largest, lengthMax = length.largest, xiErr = xi.error, lengthErr = length.error;
    worstXi = std::max(worstXi, xiErr / xiMax);
    if (lengthMax > 0.0) worstLength = std::max(worstLength, lengthErr / lengthMax);
  }
  std::printf("segments (%d plane bounds), max relative error: R %.2e, K %.2e, xi %.2e, length %.2e\n", planes, worstR,
              worstK, worstXi, worstLength);
  EXPECT_GE(planes, 12);
  EXPECT_LT(worstR, 1e-6);
  EXPECT_LT(worstK, 1e-6);
  EXPECT_LT(worstXi, 1e-6);
  EXPECT_LT(worstLength, 1e-6);
}

// Variations::First (one AD level) gives what Variations::Second gives for the values and the first
// variations, and leaves K zero: point contact at general states, and line contact on a segment.
TEST(ContactKinematics, FirstVariationsOnlyAgreeWithTheFullKinematics) {
  const auto compare = [](const ContactKinematics& full, const ContactKinematics& first) {
    double worst = 0.0, scale = 0.0, kNorm = 0.0;
    const auto take = [&](double a, double b) {
      worst = std::max(worst, std::abs(a - b));
      scale = std::max(scale, std::abs(a));
    };
    take(full.xi, first.xi);
    take(full.eta, first.eta);
    take(full.cosine, first.cosine);
    take(full.segment, first.segment);
    for (auto gap : {&ContactKinematics::normal, &ContactKinematics::tangent1, &ContactKinematics::tangent2}) {
      take((full.*gap).value, (first.*gap).value);
      for (int i = 0; i < kPairDofs; ++i) take((full.*gap).R[i], (first.*gap).R[i]);
      for (double v : (first.*gap).K) kNorm = std::max(kNorm, std::abs(v));
    }
    for (int i = 0; i < kPairDofs; ++i) {
      take(full.cosineR[i], first.cosineR[i]);
      take(full.xiR[i], first.xiR[i]);
      take(full.segmentR[i], first.segmentR[i]);
    }
    return std::make_tuple(worst / scale, kNorm);
  };
  std::mt19937 g(23);
  double worstPoint = 0.0, worstLine = 0.0;
  for (int trial = 0; trial < 6; ++trial) {
    LinePairInput in = crossing();
    placeGenerally(in, g, 0.5);
    in.radiusSum = trial % 2 ? 0.7 : 0.0;
    const auto cp = closestPoints(in);
    const auto [err, kNorm] = compare(contactKinematics(in, cp.sigma, cp.xi - 0.05, cp.eta + 0.03),
                                      contactKinematics(in, cp.sigma, cp.xi - 0.05, cp.eta + 0.03, Variations::First));
    worstPoint = std::max(worstPoint, err);
    EXPECT_EQ(kNorm, 0.0);
  }
  for (int trial = 0; trial < 4; ++trial) {
    LinePairInput in;
    in.xA1 = {{0, 0, 0}};
    in.xA2 = {{10, 0, 0}};
    in.xB1 = {{-3.0 + trial, 0.3, 2.5}};
    in.xB2 = {{7.0 + trial, -0.2, 2.6}};
    in.RA1 = in.RA2 = in.RB1 = in.RB2 = identity3<double>();
    in.dA = in.dB = Vec3d{{10, 0, 0}};
    in.sB1 = in.sB2 = Vec3d{{1, 0, 0}};
    in.radiusSum = 2.0;
    placeGenerally(in, g, 0.05);
    const LineSegment seg = lineSegment(in);
    ASSERT_GT(seg.length(), 0.0);
    const auto [err, kNorm] = compare(segmentKinematics(in, seg, 0.3, LineHistory{}),
                                      segmentKinematics(in, seg, 0.3, LineHistory{}, {}, Variations::First));
    worstLine = std::max(worstLine, err);
    EXPECT_EQ(kNorm, 0.0);
  }
  std::printf(
      "first variations only vs full kinematics, largest difference relative to the largest entry: point "
      "%.1e, line %.1e\n",
      worstPoint, worstLine);
  EXPECT_LT(worstPoint, 1e-14);
  EXPECT_LT(worstLine, 1e-14);
}

// The point contact's written-out gradients (and their AD Hessians) against nested AD of the gaps:
// every value, first variation and K at general states, with and without radii and history offsets,
// with both variation orders, on the chords and on the Hermite axes.
TEST(ContactKinematics, WrittenOutPointGradientsMatchNestedAdOfTheGaps) {
  std::mt19937 g(31);
  KinematicsDifference worst;
  for (int trial = 0; trial < 24; ++trial) {
    LinePairInput in = crossing();
    if (trial >= 12) {  // on the Hermite axes, the nodes turned by up to 0.3 rad (curved)
      in.dA = Vec3d{{10, 0, 0}};
      in.dB = Vec3d{{0, 10, 0}};
    }
    if (trial >= 18) {  // smoothed axes: node 2's reference tangent differs from node 1's
      in.dA2 = Vec3d{{9.97, 0.4, -0.5}};
      in.dB2 = Vec3d{{-0.4, 9.98, 0.3}};
    }
    placeGenerally(in, g, 0.5);
    in.radiusSum = trial % 2 ? 0.7 : 0.0;
    const auto cp = closestPoints(in);
    for (const Variations order : {Variations::Second, Variations::First}) {
      const double xiPrev = cp.xi - 0.05 * (trial % 3), etaPrev = cp.eta + 0.03 * (trial % 4);
      worst.add(contactKinematics(in, cp.sigma, xiPrev, etaPrev, order),
                contactKinematicsFromGaps(in, cp.sigma, xiPrev, etaPrev, order));
    }
  }
  std::printf("written-out point gradients against nested AD: values %.2e, R %.2e, K %.2e (largest relative)\n",
              worst.value, worst.R, worst.K);
  EXPECT_LT(worst.value, 1e-13);
  EXPECT_LT(worst.R, 1e-12);
  EXPECT_LT(worst.K, 1e-11);
}

// Line contact's held variations written out (lineKinematics, segmentKinematics) against nested AD of
// the gaps with the held quantities frozen (the ...FromGaps references): circles and faces, at a fixed
// xi and on a segment, Hermite axes and chords, a kept normal pointing either way, general states.
TEST(LineKinematics, WrittenOutHeldVariationsMatchNestedAdOfTheGaps) {
  std::mt19937 g(43);
  KinematicsDifference worst;
  int compared = 0;
  for (int trial = 0; trial < 16; ++trial) {
    LinePairInput t;
    t.xA1 = {{0, 0, 0}};
    t.xA2 = {{10, 0, 0}};
    const double x0 = trial % 3 == 0 ? 2.0 : -3.0;
    t.xB1 = {{x0, 0.3, 2.5}};
    t.xB2 = {{x0 + 10, -0.2, 2.6}};
    if (trial % 4 != 3) {
      t.dA = Vec3d{{10, 0, 0}};
      t.dB = Vec3d{{10, -0.5, 0.1}};
    }
    segmentPlanesAndSections(t, trial % 2, 2.0);
    placeGenerally(t, g, 0.3);
    if (trial % 2 == 0 && trial % 8 != 0) turnedSinceConverged(t, g);  // (circles: most with their turns' slip)
    const Vec3d kept = trial % 4 == 2 ? Vec3d{{0, 0, -1}} : Vec3d{};
    const LineHistory history{0.4, 0.3, 0.9};
    const LineSegment seg = lineSegment(t);
    ASSERT_GT(seg.length(), 0.1);
    for (const Variations order : {Variations::Second, Variations::First}) {
      const double xi = 0.2 + 0.04 * trial, s = 0.15 + 0.05 * trial;
      const std::pair<ContactKinematics, ContactKinematics> pairs[] = {
          {lineKinematics(t, xi, 0.45, kept, order), lineKinematicsFromGaps(t, xi, 0.45, kept, order)},
          {segmentKinematics(t, seg, s, history, kept, order),
           segmentKinematicsFromGaps(t, seg, s, history, kept, order)}};
      for (const auto& [a, b] : pairs) {
        ++compared;
        worst.add(a, b);
      }
    }
  }
  std::printf("written-out held line variations against nested AD (%d kinematics): values %.2e, R %.2e, K %.2e\n",
              compared, worst.value, worst.R, worst.K);
  EXPECT_LT(worst.value, 1e-13);
  EXPECT_LT(worst.R, 1e-12);
  EXPECT_LT(worst.K, 1e-11);
}

// Point contact on the elements' Hermite axes (LinePairInput::dA, dB set). Straight, unturned elements:
// the curves are the chords, so the values of CrossedBeamsGapAndPoints. B's nodes turned about X by
// +phi and -phi (tangents R_m (0, 10, 0)): B's axis is y = 10 [3u^2 - 2u^3 + cos(phi) (u - 3u^2 + 2u^3)]
// - 5, z = 8 + 10 sin(phi) (u - u^2) (as in CubicAxisFollowsTheNodalRotations), symmetric about u = 1/2,
// where it passes (x, 0, 8 + 2.5 sin phi) with tangent +Y. A's edge line y = 5 is moved to y = 0 here
// (A's axis along X at the origin, circles of radii summing to 3): the closest points are A's (x_B, 0, 0)
// and B's crest, the gap 8 + 2.5 sin(phi) - 3, the normal +Z; the chords' gap is 8 - 3.
TEST(ContactKinematics, HermiteAxesOfBentElements) {
  LinePairInput in = crossing();
  in.dA = Vec3d{{10, 0, 0}};
  in.dB = Vec3d{{0, 10, 0}};
  const auto straight = closestPoints(in);
  EXPECT_NEAR(straight.gap, 0.5, 1e-14);
  EXPECT_NEAR(straight.xi, 0.25, 1e-14);
  EXPECT_NEAR(straight.eta, 0.5, 1e-14);
  EXPECT_NEAR(straight.normal[2], 1.0, 1e-14);
  const auto k = contactKinematics(in, straight.sigma, 0.25, 0.5);
  EXPECT_NEAR(k.normal.value, 0.5, 1e-14);
  // The curves' points move with their nodes by the cubic shape functions (the tangents do not move
  // with translations): H1(1/2) = 1/2 on B, H1(1/4) = 0.84375, H3(1/4) = 0.15625 on A.
  EXPECT_NEAR(k.normal.R[12 + 2], 0.5, 1e-14);
  EXPECT_NEAR(k.normal.R[2], -0.84375, 1e-14);
  EXPECT_NEAR(k.normal.R[6 + 2], -0.15625, 1e-14);
  EXPECT_NEAR(k.tangent1.R[12] + k.tangent1.R[18], 1.0, 1e-14);
  for (const double phi : {0.1, -0.15}) {
    LinePairInput b;
    b.xA1 = {{-3, 0, 0}};
    b.xA2 = {{7, 0, 0}};
    b.xB1 = {{1.5, -5, 8}};
    b.xB2 = {{1.5, 5, 8}};
    b.RA1 = b.RA2 = identity3<double>();
    b.RB1 = expSO3(Vec3d{{phi, 0, 0}});
    b.RB2 = expSO3(Vec3d{{-phi, 0, 0}});
    b.dA = Vec3d{{10, 0, 0}};
    b.dB = Vec3d{{0, 10, 0}};
    b.radiusSum = 3.0;
    const auto cp = closestPoints(b);
    EXPECT_NEAR(cp.xi, 0.45, 1e-13);
    EXPECT_NEAR(cp.eta, 0.5, 1e-13);
    EXPECT_NEAR(cp.gap, 5.0 + 2.5 * std::sin(phi), 1e-12);
    EXPECT_NEAR(cp.normal[2], 1.0, 1e-13);
    const auto kb = contactKinematics(b, cp.sigma, 0.45, 0.5);
    EXPECT_NEAR(kb.normal.value, 5.0 + 2.5 * std::sin(phi), 1e-12);
    // B's crest bends with curvature kappa = 0.2 sin(phi) at distance d = 8 + 2.5 sin(phi) from A's
    // axis: translating A along B's tangent (+Y) moves the projection by 1 / (|x_B'| (1 - kappa d)) per
    // unit, and the slip metric m_B = (|x_B'|^2 + x_B'' . w) / |x_B'| makes the slip one unit per unit
    // (|x_B'| alone: 1 / (1 - kappa d), 1.198 at phi = 0.1); along A (straight), one unit too.
    const double slipPerY = -(kb.tangent2.R[1] + kb.tangent2.R[6 + 1]);
    const double kappaD = 0.2 * std::sin(phi) * (8.0 + 2.5 * std::sin(phi));
    std::printf("B bent by phi = %.2f (kappa d = %.3f): slip per unit motion along B %.15f (|x_B'| alone: %.4f)\n", phi,
                kappaD, slipPerY, 1.0 / (1.0 - kappaD));
    EXPECT_NEAR(std::abs(slipPerY), 1.0, 1e-12);
    EXPECT_NEAR(std::abs(kb.tangent1.R[0] + kb.tangent1.R[6]), 1.0, 1e-12);
    b.dA = b.dB = Vec3d{};
    EXPECT_NEAR(closestPoints(b).gap, 5.0, 1e-12);  // the chords
  }
}

// The slips on the Hermite axes make a friction multiplier apply the force the Coulomb law means at
// any angle: a unit lambda_T1 (lambda_T2) applies on B, summed over its nodes' translations, F_1
// (F_2) with t_A . F_1 = 1, t_B . F_1 = 0, t_A . F_2 = 0, t_B . F_2 = -1 (F = Q M^-1 lambda_T, Q =
// [t_A, -t_B], M = Q^T Q), t the curves' unit tangents at the closest points; so its length is the
// law's |lambda_T|_{M^-1}. General states: circles' axes, nodes turned by up to 0.5 rad (the curves
// bend), crossing at 35 to 145 degrees, node 2's reference tangents differing from node 1's, no slip
// yet in the increment. (|x'| alone as the metric missed by the curves' curvature times their distance.)
TEST(ContactKinematics, FrictionOnHermiteAxesAppliesTheCoulombLawsForceAtAnyAngle) {
  std::mt19937 g(57);
  // The unit tangent of the Hermite curve (P1, V1, P2, V2) at u.
  const auto tangent = [](const Vec3d& P1, const Vec3d& V1, const Vec3d& P2, const Vec3d& V2, double u) {
    const Vec3d t =
        (6 * u * u - 6 * u) * P1 + (6 * u - 6 * u * u) * P2 + (1 - 4 * u + 3 * u * u) * V1 + (3 * u * u - 2 * u) * V2;
    return (1.0 / norm(t)) * t;
  };
  double worst = 0.0, worstCosine = 0.0;
  int tried = 0;
  for (int trial = 0; trial < 40 && tried < 12; ++trial) {
    LinePairInput in = crossing();
    in.oA = in.oB = Vec3d{};
    in.radiusSum = 0.7;
    const double angle = (35.0 + 110.0 * (trial % 12) / 11.0) * M_PI / 180.0;
    in.xB1 = Vec3d{{55, 0, 3}} - 5.0 * Vec3d{{std::cos(angle), std::sin(angle), 0}};
    in.xB2 = Vec3d{{55, 0, 3}} + 5.0 * Vec3d{{std::cos(angle), std::sin(angle), 0}};
    in.dA = Vec3d{{10, 0, 0}};
    in.dA2 = Vec3d{{9.97, 0.4, -0.5}};
    in.dB = in.xB2 - in.xB1;
    in.dB2 = in.dB + Vec3d{{0.3, -0.2, 0.4}};
    placeGenerally(in, g, 0.3);
    const auto cp = closestPoints(in);
    if (cp.sinAngle < 0.3 || cp.xi < 0 || cp.xi > 1 || cp.eta < 0 || cp.eta > 1) continue;
    ++tried;
    const auto k = contactKinematics(in, cp.sigma, cp.xi, cp.eta);
    const Vec3d tA = tangent(in.xA1, in.RA1 * in.dA, in.xA2, in.RA2 * in.dA2, cp.xi);
    const Vec3d tB = tangent(in.xB1, in.RB1 * in.dB, in.xB2, in.RB2 * in.dB2, cp.eta);
    Vec3d F[2];
    const GapDerivatives* gaps[2] = {&k.tangent1, &k.tangent2};
    for (int i = 0; i < 2; ++i)
      for (int c = 0; c < 3; ++c) F[i][c] = gaps[i]->R[12 + c] + gaps[i]->R[18 + c];
    const double errors[4] = {dot(tA, F[0]) - 1.0, dot(tB, F[0]), dot(tA, F[1]), dot(tB, F[1]) + 1.0};
    for (const double e : errors) worst = std::max(worst, std::abs(e));
    worstCosine = std::max(worstCosine, std::abs(dot(tA, tB)));
  }
  std::printf("friction on bent Hermite curves, %d crossings (|cos| up to %.2f): largest error of t . F %.2e\n", tried,
              worstCosine, worst);
  EXPECT_GE(tried, 8);
  EXPECT_GT(worstCosine, 0.5);
  EXPECT_LT(worst, 1e-10);
}

// R and K of the three gaps of point contact on Hermite axes against central differences: general
// states with the nodes turned by up to 0.3 rad about each axis (the curves bend), rectangles' edge lines
// (offsets of Example 1's sections) and circles (the axes, radii summing to 0.7), history offsets so that
// the tangential gaps are not zero.
TEST(ContactKinematics, HermiteAxesVariationsMatchCentralDifferences) {
  std::mt19937 g(41);
  double worstR = 0.0, worstK = 0.0;
  for (int trial = 0; trial < 10; ++trial) {
    LinePairInput in = crossing();
    in.dA = Vec3d{{10, 0, 0}};
    in.dB = Vec3d{{0, 10, 0}};
    if (trial % 2) {
      in.oA = in.oB = Vec3d{};
      in.radiusSum = 0.7;
    }
    if (trial % 2 == 0 && trial > 0) {  // smoothed axes: node 2's reference tangent differs from node 1's
      in.dA2 = Vec3d{{9.97, 0.4, -0.5}};
      in.dB2 = Vec3d{{-0.4, 9.98, 0.3}};
    }
    placeGenerally(in, g, 0.5);
    const auto cp = closestPoints(in);
    ASSERT_GT(cp.sinAngle, 0.1);
    const double xiP = cp.xi - 0.05, etaP = cp.eta + 0.03;
    const auto [errR, errK] = centralDifferenceErrors(
        in, [&](const LinePairInput& s) { return contactKinematics(s, cp.sigma, xiP, etaP); },
        {&ContactKinematics::normal, &ContactKinematics::tangent1, &ContactKinematics::tangent2});
    worstR = std::max(worstR, errR);
    worstK = std::max(worstK, errK);
    // The closest points are those of the kinematics, and the curves' (not the chords').
    const auto k = contactKinematics(in, cp.sigma, xiP, etaP, Variations::First);
    EXPECT_NEAR(k.xi, cp.xi, 1e-12);
    EXPECT_NEAR(k.eta, cp.eta, 1e-12);
    EXPECT_NEAR(k.normal.value, cp.gap, 1e-12);
    LinePairInput chord = in;
    chord.dA = chord.dB = Vec3d{};
    EXPECT_GT(std::abs(closestPoints(chord).gap - cp.gap), 1e-4);
  }
  std::printf("Hermite axes, max relative error: R (first variations) %.2e, K (linearized variations) %.2e\n", worstR,
              worstK);
  EXPECT_LT(worstR, 1e-6);
  EXPECT_LT(worstK, 1e-6);
}

// The normal is continuous across a node: beam A bent smoothly (its nodes on a circle of radius 30 in
// the XZ plane at angles -0.25, 0, 0.15 rad, unequal elements, each node turned about Y to the circle's
// tangent), B a straight line through (0, 0, 0) + h m, with m normal to A's tangent at the middle node
// and B's direction normal to m: the orthogonality conditions hold at A's middle node, i.e. at xi = 1
// of element 0 and at xi = 0 of element 1. On the Hermite axes both elements give that point, the gap
// h - r and the normal m to round-off; on the chords the two normals differ by about the kink (0.2 rad).
TEST(ContactKinematics, HermiteNormalIsContinuousAcrossANode) {
  const double rc = 30.0, h = 2.0, r = 0.5;
  const double angle[3] = {-0.25, 0.0, 0.15};
  Vec3d node[3];
  Mat3d rot[3];
  for (int i = 0; i < 3; ++i) {
    node[i] = Vec3d{{rc * std::sin(angle[i]), 0.0, rc * (std::cos(angle[i]) - 1.0)}};
    rot[i] = expSO3(Vec3d{{0.0, angle[i], 0.0}});  // e1 -> (cos a, 0, -sin a), the circle's tangent
  }
  const Vec3d m{{0.0, -std::sin(0.3), std::cos(0.3)}};  // normal to A's tangent (1, 0, 0) at the node
  const Vec3d across = cross(m, Vec3d{{1, 0, 0}});
  const Vec3d tB = std::cos(1.2) * Vec3d{{1, 0, 0}} + std::sin(1.2) * across;  // normal to m
  ClosestPoints cp[2][2];  // [chords, Hermite][element]
  for (int hermite = 0; hermite < 2; ++hermite)
    for (int e = 0; e < 2; ++e) {
      LinePairInput in;
      in.xA1 = node[e];
      in.xA2 = node[e + 1];
      in.RA1 = rot[e];
      in.RA2 = rot[e + 1];
      in.xB1 = h * m - 4.0 * tB;  // B's point over the node at eta = 0.4
      in.xB2 = h * m + 6.0 * tB;
      in.RB1 = in.RB2 = identity3<double>();
      if (hermite) {
        in.dA = Vec3d{{norm(node[e + 1] - node[e]), 0, 0}};  // the reference: straight along X
        in.dB = in.xB2 - in.xB1;
      }
      in.radiusSum = r;
      cp[hermite][e] = closestPoints(in);
    }
  const auto& s = cp[1];
  EXPECT_NEAR(s[0].xi, 1.0, 1e-12);
  EXPECT_NEAR(s[1].xi, 0.0, 1e-12);
  EXPECT_NEAR(s[0].eta, 0.4, 1e-12);
  EXPECT_NEAR(s[1].eta, 0.4, 1e-12);
  EXPECT_NEAR(s[0].gap, h - r, 1e-12);
  EXPECT_NEAR(s[1].gap, h - r, 1e-12);
  const double jump = norm(s[0].normal - s[1].normal), chordJump = norm(cp[0][0].normal - cp[0][1].normal);
  std::printf("normal at the node from the two elements: Hermite axes differ by %.1e, chords by %.3f\n", jump,
              chordJump);
  EXPECT_LT(jump, 1e-13);
  EXPECT_LT(norm(s[0].normal - m), 1e-13);
  EXPECT_GT(chordJump, 0.1);
}

// Smoothed axes across a node of a polyline in its initial shape (no node turned): A's three nodes on
// a circle of radius 30 at angles -0.25, 0, 0.15 rad, straight elements meeting at 0.2 rad. Each
// element's Hermite curve takes at the middle node the bisector b of the two elements' directions
// (ContactGeometry::pointContactAxes), at the outer nodes its own direction. B is a line through h m, m
// normal to b, B's direction normal to m: both elements give the point at the middle node (xi = 1 and
// xi = 0), the gap h - r and the normal m; with each element's own direction (dA2 zero) the two curves
// are the chords and their normals differ by the kink.
TEST(ContactKinematics, SmoothedAxesOfAPolylineAreContinuousAcrossItsNode) {
  const double rc = 30.0, h = 2.0, r = 0.5;
  const double angle[3] = {-0.25, 0.0, 0.15};
  Vec3d node[3];
  for (int i = 0; i < 3; ++i) node[i] = Vec3d{{rc * std::sin(angle[i]), 0.0, rc * (std::cos(angle[i]) - 1.0)}};
  const Vec3d t0 = (1.0 / norm(node[1] - node[0])) * (node[1] - node[0]);
  const Vec3d t1 = (1.0 / norm(node[2] - node[1])) * (node[2] - node[1]);
  const Vec3d b = (1.0 / norm(t0 + t1)) * (t0 + t1);
  const Vec3d m = std::cos(0.3) * cross(Vec3d{{0, 1, 0}}, b) - std::sin(0.3) * Vec3d{{0, 1, 0}};  // normal to b
  const Vec3d across = cross(m, b);
  const Vec3d tB = std::cos(1.2) * b + std::sin(1.2) * across;  // normal to m
  ClosestPoints cp[2][2];  // [own directions, smoothed][element]
  for (int smoothed = 0; smoothed < 2; ++smoothed)
    for (int e = 0; e < 2; ++e) {
      LinePairInput in;
      in.xA1 = node[e];
      in.xA2 = node[e + 1];
      in.RA1 = in.RA2 = in.RB1 = in.RB2 = identity3<double>();
      in.xB1 = node[1] + h * m - 4.0 * tB;
      in.xB2 = node[1] + h * m + 6.0 * tB;
      const double L = norm(node[e + 1] - node[e]);
      in.dA = L * (e == 0 ? t0 : (smoothed ? b : t1));
      if (smoothed) in.dA2 = L * (e == 0 ? b : t1);
      in.dB = in.xB2 - in.xB1;
      in.radiusSum = r;
      cp[smoothed][e] = closestPoints(in);
    }
  const auto& s = cp[1];
  EXPECT_NEAR(s[0].xi, 1.0, 1e-12);
  EXPECT_NEAR(s[1].xi, 0.0, 1e-12);
  EXPECT_NEAR(s[0].gap, h - r, 1e-12);
  EXPECT_NEAR(s[1].gap, h - r, 1e-12);
  const double jump = norm(s[0].normal - s[1].normal), ownJump = norm(cp[0][0].normal - cp[0][1].normal);
  std::printf(
      "normal at a polyline's node from its two elements: smoothed axes differ by %.1e, own directions by %.3f\n", jump,
      ownJump);
  EXPECT_LT(jump, 1e-12);
  EXPECT_LT(norm(s[0].normal - m), 1e-12);
  EXPECT_GT(ownJump, 0.1);
}

namespace {
// A column (beam A, element from z = -10 to its free end at z = 0, end face a disc of radius 0.5 or a
// 1 x 0.6 rectangle) under beam B along X at height 1.2, radius 1 (circles) or with its lower face
// (normal -Z) at z = 0.2 (rectangles: B's axis at z = 0.7, half height 0.5, face half width 0.4).
LinePairInput column(bool rectangles) {
  LinePairInput in;
  in.xA1 = {{0, 0, -10}};
  in.xA2 = {{0, 0, 0}};
  in.xB1 = {{-5, rectangles ? 0.1 : 0.0, rectangles ? 0.7 : 1.2}};
  in.xB2 = {{5, rectangles ? 0.1 : 0.0, rectangles ? 0.7 : 1.2}};
  in.RA1 = in.RA2 = in.RB1 = in.RB2 = identity3<double>();
  in.endNode = 1;
  in.outward = 1.0;
  in.endAxes[0] = {{0, 0, 1}};
  in.endAxes[1] = {{1, 0, 0}};
  in.endAxes[2] = {{0, 1, 0}};
  in.endRectangle = rectangles;
  in.endRadius = 0.5;
  in.endHalf[0] = 0.5;
  in.endHalf[1] = 0.3;
  if (rectangles) {
    in.face = true;
    in.oB = {{0, 0, -0.5}};
    in.nB = {{0, 0, -1}};
    in.halfWidthB = 0.4;
  } else {
    in.radiusB = 1.0;
    in.acrossB = {{0, 1, 0}};
  }
  return in;
}
}  // namespace

namespace {
// Two coaxial columns end to end: A from z = -10 to its free end at z = 0, B from z = 10.2 down to its
// free end at z = 0.2 (0.2 apart). A's end face a disc of radius 0.5 or a 1 x 0.6 rectangle; B's end
// face (the plane A presses on) its outward normal -Z.
LinePairInput endToEnd(bool rectangles) {
  LinePairInput in = column(rectangles);
  in.face = false;
  in.oB = Vec3d{};
  in.xB1 = {{0, 0, 10.2}};
  in.xB2 = {{0, 0, 0.2}};
  in.otherEnd = 1;
  in.otherRectangle = rectangles;
  in.otherRadius = 0.5;
  in.otherHalf[0] = 0.5;
  in.otherHalf[1] = 0.3;
  in.otherAxes[0] = {{0, 0, -1}};
  in.otherAxes[1] = {{1, 0, 0}};
  in.otherAxes[2] = {{0, -1, 0}};
  return in;
}
}  // namespace

namespace {
// An end contact input varied for a central-difference trial (in place): the end at A's node 1 where
// trial % 4 >= 2, Hermite axes where trial % 3 != 0, then placed generally; and the largest relative
// errors of R and K of its three gaps (history: eta - 0.01, across + 0.02 of the placed state's).
std::pair<double, double> endVariationErrors(LinePairInput& in, int trial, std::mt19937& g) {
  if (trial % 4 >= 2) {
    std::swap(in.xA1, in.xA2);
    in.endNode = 0;
    in.outward = -1.0;
    in.endAxes[0] = -1.0 * in.endAxes[0];
  }
  if (trial % 3 != 0) {
    in.dA = in.xA2 - in.xA1;
    in.dB = in.xB2 - in.xB1;
  }
  placeGenerally(in, g, 0.3);
  const ClosestPoints cp = endProjection(in, 1.0);
  const double etaP = cp.eta - 0.01, acrossP = cp.etaRate + 0.02;
  return centralDifferenceErrors(
      in, [&](const LinePairInput& s) { return endKinematics(s, 1.0, etaP, acrossP); },
      {&ContactKinematics::normal, &ContactKinematics::tangent1, &ContactKinematics::tangent2});
}

// What a unit multiplier of each of end contact's three gaps applies on B (the sum of R over B's
// translations), in f; returns their largest departure from an orthonormal triad.
double orthonormalDeparture(const ContactKinematics& k, Vec3d (&f)[3]) {
  const GapDerivatives* gaps[3] = {&k.normal, &k.tangent1, &k.tangent2};
  for (int q = 0; q < 3; ++q) f[q] = onB(*gaps[q]);
  double worst = 0.0;
  for (int q = 0; q < 3; ++q) {
    worst = std::max(worst, std::abs(norm(f[q]) - 1.0));
    for (int r = q + 1; r < 3; ++r) worst = std::max(worst, std::abs(dot(f[q], f[r])));
  }
  return worst;
}
}  // namespace

// End contact: the column's end face pressed flat on B: the gap is the clearance (0.2); sliding the
// end along B by s gives g_T2 = s, across B by s gives g_T1 = s (rectangles: the face offset; circles:
// the end's distance from B's axis times the angle, s at first order); moved across B within its
// face's half size it stays flat on B; tilted by theta about B's axis its rim comes towards B (the
// exact distances of the tilted face; the smoothing makes the gap larger by at most 1.64 % of the
// face's half size). Then R and K against central differences at general states, each section,
// either end of A, chords and Hermite axes.
TEST(EndKinematics, ColumnEndOnABeam) {
  for (bool rect : {false, true}) {
    LinePairInput in = column(rect);
    const ClosestPoints cp = endProjection(in, 1.0);
    EXPECT_NEAR(cp.gap, 0.2, 1e-12);
    EXPECT_NEAR(cp.eta, 0.5, 1e-12);
    EXPECT_NEAR(cp.normal[2], 1.0, 1e-12);
    const ContactKinematics k0 = endKinematics(in, 1.0, cp.eta, cp.etaRate);
    EXPECT_NEAR(k0.normal.value, 0.2, 1e-12);
    EXPECT_NEAR(k0.tangent1.value, 0.0, 1e-12);
    EXPECT_NEAR(k0.tangent2.value, 0.0, 1e-12);
    EXPECT_EQ(k0.cosine, 0.0);
    const double s = 1e-3;
    LinePairInput along = in, across = in;
    along.xA2[0] += s;
    across.xA2[1] += s;
    const ContactKinematics ka = endKinematics(along, 1.0, cp.eta, cp.etaRate);
    const ContactKinematics kc = endKinematics(across, 1.0, cp.eta, cp.etaRate);
    EXPECT_NEAR(ka.tangent2.value, s, 1e-12);
    EXPECT_NEAR(std::abs(kc.tangent1.value), s, rect ? 1e-12 : 1e-8);  // (circles: s^2 / 1.2)
    EXPECT_NEAR(kc.tangent2.value, 0.0, 1e-12);
    // moved across B by less than the face's half size: still flat on B's top line (exact: 0.2; the
    // smoothing's error is below 1.6 % of the half size)
    LinePairInput shifted = in;
    shifted.xA2[1] += 0.25;
    const ClosestPoints flat = endProjection(shifted, 1.0);
    std::printf("%s end moved across by 0.25: gap %.6f (flat 0.2), normal (%.4f, %.4f, %.4f)\n",
                rect ? "rectangular" : "circular", flat.gap, flat.normal[0], flat.normal[1], flat.normal[2]);
    EXPECT_GE(flat.gap, 0.2 - 1e-12);
    EXPECT_LE(flat.gap, 0.2 + 0.0164 * (rect ? in.endHalf[1] : in.endRadius));
    // tilt about X (B's axis): the end face's rim towards +-Y
    for (double theta : {0.05, 0.2, 0.5}) {
      LinePairInput tilted = in;
      tilted.RA2 = expSO3(Vec3d{{theta, 0, 0}});
      // exact: rectangles, the face's plane 0.2 above the end less the rim's rise h/2 sin(theta);
      // circles, the distance of the tilted disc from B's axis (its point nearest the axis at y =
      // min(1.2 sin cos, r cos), z = y tan(theta)) less r_B
      const double half = rect ? in.endHalf[1] : in.endRadius;
      const double y = std::min(1.2 * std::sin(theta) * std::cos(theta), half * std::cos(theta));
      const double exact = rect ? 0.2 - half * std::sin(theta) : std::hypot(y, 1.2 - y * std::tan(theta)) - in.radiusB;
      const double gap = endProjection(tilted, 1.0).gap;
      EXPECT_GE(gap, exact - 1e-12) << theta;
      EXPECT_LE(gap, exact + 0.0164 * half + 1e-12) << theta;
    }
  }
  std::mt19937 g(31);
  double worstR = 0.0, worstK = 0.0;
  for (int trial = 0; trial < 8; ++trial) {
    const bool rect = trial % 2;
    LinePairInput in = column(rect);
    const auto [errR, errK] = endVariationErrors(in, trial, g);
    worstR = std::max(worstR, errR);
    worstK = std::max(worstK, errK);
  }
  std::printf("end contact, max relative error: R %.2e, K %.2e\n", worstR, worstK);
  EXPECT_LT(worstR, 1e-6);
  EXPECT_LT(worstK, 1e-6);
}

namespace {
// A beam end lying along a face: A's element from x = -10 to its free end at x = 0 (axis along X,
// a 1 x 0.6 rectangle: e2 = Y half 0.5, e3 = Z half 0.3), over B's top face (normal +Z) at z = -0.5
// (B along Y at z = -1, half height 0.5, the face 4 wide): A's lower corners 0.2 above the face.
LinePairInput lyingEnd(int corner) {
  LinePairInput in = column(true);
  in.xA1 = {{-10, 0, 0}};
  in.xA2 = {{0, 0, 0}};
  in.xB1 = {{0, -5, -1}};
  in.xB2 = {{0, 5, -1}};
  in.endAxes[0] = {{1, 0, 0}};
  in.endAxes[1] = {{0, 1, 0}};
  in.endAxes[2] = {{0, 0, 1}};
  in.oB = {{0, 0, 0.5}};
  in.nB = {{0, 0, 1}};
  in.halfWidthB = 2.0;
  in.endCorner = corner;
  return in;
}
}  // namespace

// End corners: one corner of a rectangular end against a face, its gap the corner's distance from
// the face's plane, unsmoothed: the lower corners (2: +e2 -e3, 3: -e2 -e3) 0.2 above the face, the
// upper ones 0.8; the end turned by theta about its axis puts the corner (y, z) at y sin(theta) +
// z cos(theta) + 0.5 above the face; the point carries the corner's position. Then R and K against central differences
// at general states (each corner, either end of A, chords and Hermite axes, a lying end and a standing column), and a
// unit multiplier applies orthonormal forces on B that balance.
TEST(EndKinematics, CornerOfAnEndOnAFace) {
  for (int c = 0; c < 4; ++c) {
    const ClosestPoints cp = endProjection(lyingEnd(c), 1.0);
    EXPECT_NEAR(cp.gap, c >= 2 ? 0.2 : 0.8, 1e-12) << c;
    EXPECT_NEAR(cp.eta, 0.5, 1e-12);
    EXPECT_NEAR(norm(cp.pA - Vec3d{{0, c & 1 ? -0.5 : 0.5, c & 2 ? -0.3 : 0.3}}), 0.0, 1e-12) << c;
    for (double theta : {0.05, 0.3}) {
      LinePairInput turned = lyingEnd(c);
      turned.RA2 = expSO3(Vec3d{{theta, 0, 0}});
      const double y = c & 1 ? -0.5 : 0.5, z = c & 2 ? -0.3 : 0.3;
      const double exact = y * std::sin(theta) + z * std::cos(theta) + 0.5;
      EXPECT_NEAR(endProjection(turned, 1.0).gap, exact, 1e-12) << c << " " << theta;
    }
  }
  std::mt19937 g(37);
  double worstR = 0.0, worstK = 0.0, worstF = 0.0, worstM = 0.0, worstO = 0.0;
  for (int trial = 0; trial < 16; ++trial) {
    LinePairInput in = trial % 2 ? lyingEnd(trial / 4) : column(true);
    in.endCorner = trial / 4;
    const auto [errR, errK] = endVariationErrors(in, trial, g);
    worstR = std::max(worstR, errR);
    worstK = std::max(worstK, errK);
    const ClosestPoints cp = endProjection(in, 1.0);
    const ContactKinematics k = endKinematics(in, 1.0, cp.eta - 0.01, cp.etaRate + 0.02);
    const auto [f, m] = unbalance(in, k);
    worstF = std::max(worstF, f);
    worstM = std::max(worstM, m);
    Vec3d onB[3];
    worstO = std::max(worstO, orthonormalDeparture(k, onB));
  }
  std::printf(
      "end corners, max relative error: R %.2e, K %.2e; unbalance force %.1e, moment %.1e; "
      "orthonormal to %.1e\n",
      worstR, worstK, worstF, worstM, worstO);
  EXPECT_LT(worstR, 1e-6);
  EXPECT_LT(worstK, 1e-6);
  EXPECT_LT(worstM, 1e-12);
  EXPECT_LT(worstO, 1e-9);
}

// What a unit multiplier applies on B (the sum of R over B's translations): for each gap of end
// contact a unit vector, the three orthogonal (the normal along the face's normal or across B's
// axis, the friction along and across B), so |F_T| = |lambda_T| and the cone of the multipliers is
// the cone of the applied force. General states, both sections.
TEST(EndKinematics, UnitMultipliersApplyOrthonormalForcesOnB) {
  std::mt19937 g(5);
  double worst = 0.0;
  for (int trial = 0; trial < 8; ++trial) {
    const bool rect = trial % 2;
    LinePairInput in = column(rect);
    in.dA = in.xA2 - in.xA1;
    in.dB = in.xB2 - in.xB1;
    placeGenerally(in, g, 0.3);
    const ClosestPoints cp = endProjection(in, 1.0);
    const ContactKinematics k = endKinematics(in, 1.0, cp.eta - 0.01, cp.etaRate + 0.01);
    Vec3d f[3];
    worst = std::max(worst, orthonormalDeparture(k, f));
    if (trial < 2)
      std::printf("%s: |f_N| %.12f |f_T1| %.12f |f_T2| %.12f, f_T1 . f_T2 %.2e, f_N . f_T1 %.2e, f_N . f_T2 %.2e\n",
                  rect ? "rectangles" : "circles", norm(f[0]), norm(f[1]), norm(f[2]), dot(f[1], f[2]), dot(f[0], f[1]),
                  dot(f[0], f[2]));
  }
  std::printf("end contact: largest departure from orthonormal %.2e\n", worst);
  EXPECT_LT(worst, 1e-9);
}

// Every kernel's unit-multiplier forces balance, force and moment, at general states: point contact
// (chords and Hermite axes, lines on and off the axes), line contact at a Gauss point and on a segment
// (circles, and an edge on a face), end contact (both sections, friction along and across). Each
// applies its force at one place on both bodies (end contact: the end face's support point), so
// nothing is lost to a couple of the axes' separation or of an offset across a face.
TEST(ContactKinematics, UnitMultipliersForcesBalance) {
  std::mt19937 g(23);
  double worstF = 0.0, worstM = 0.0;
  const auto record = [&](const char* what, const LinePairInput& in, const ContactKinematics& k) {
    const auto [f, m] = unbalance(in, k);
    worstF = std::max(worstF, f);
    worstM = std::max(worstM, m);
    EXPECT_LT(m, 1e-12) << what;
  };
  for (int trial = 0; trial < 6; ++trial) {
    LinePairInput in = crossing();
    in.radiusSum = trial % 2 ? 0.7 : 0.0;
    if (trial % 3 == 2) in.dA = in.xA2 - in.xA1, in.dB = in.xB2 - in.xB1;
    placeGenerally(in, g, 0.5);
    const auto cp = closestPoints(in);
    record("point", in, contactKinematics(in, cp.sigma, cp.xi - 0.05, cp.eta + 0.03));
  }
  for (int trial = 0; trial < 6; ++trial) {
    LinePairInput in;
    in.xA1 = {{0, 0, 0.5}};
    in.xA2 = {{10, 0, 0.5}};
    in.xB1 = {{-2, 0, 1.6}};
    in.xB2 = {{8, 0, 1.6}};
    in.RA1 = in.RA2 = in.RB1 = in.RB2 = identity3<double>();
    in.dA = in.dB = Vec3d{{10, 0, 0}};
    segmentPlanesAndSections(in, trial % 2, 1.1);
    placeGenerally(in, g, 0.3);
    record("line", in, lineKinematics(in, 0.3, 0.4));
    const LineSegment seg = lineSegment(in);
    if (seg.length() > 0.0) record("segment", in, segmentKinematics(in, seg, 0.4, LineHistory{0.4, 0.3, 0.9}));
  }
  for (int trial = 0; trial < 8; ++trial) {
    LinePairInput in = column(trial % 2);
    if (trial % 4 >= 2) in.dA = in.xA2 - in.xA1, in.dB = in.xB2 - in.xB1;
    placeGenerally(in, g, 0.3);
    const ClosestPoints cp = endProjection(in, 1.0);
    record("end", in, endKinematics(in, 1.0, cp.eta - 0.01, cp.etaRate + 0.02));
  }
  for (int trial = 0; trial < 8; ++trial) {
    LinePairInput in = endToEnd(trial % 2);
    if (trial % 4 >= 2) in.dA = in.xA2 - in.xA1, in.dB = in.xB2 - in.xB1;
    placeGenerally(in, g, 0.3);
    const ClosestPoints cp = endToEndProjection(in);
    record("end to end", in, endToEndKinematics(in, cp.etaRate - 0.01, cp.across2 + 0.02));
  }
  std::printf("unit multipliers' forces, largest net force %.2e, net moment %.2e\n", worstF, worstM);
  EXPECT_LT(worstF, 1e-12);
}

// End-to-end contact: the faces 0.2 apart give gap 0.2, the normal from A to B +Z; A's end moved
// across by s along B's e2 and e3 gives g_T1 = s, g_T2 = -s (e3 = -Y); tilted by theta about X its
// face's rim comes towards B: 0.2 - r sin(theta) (disc) or - h/2 sin(theta) (rectangle), up to the
// smoothing's 1.64 % of the half size. Then R and K against central differences at general states,
// both sections, either end of each beam, chords and Hermite axes; what a unit multiplier applies on
// B is a unit vector per gap, the three orthogonal.
TEST(EndToEndKinematics, CoaxialEnds) {
  for (bool rect : {false, true}) {
    const LinePairInput in = endToEnd(rect);
    const ClosestPoints cp = endToEndProjection(in);
    EXPECT_NEAR(cp.gap, 0.2, 1e-12);
    EXPECT_NEAR(cp.normal[2], 1.0, 1e-12);
    const ContactKinematics k0 = endToEndKinematics(in, cp.etaRate, cp.across2);
    EXPECT_NEAR(k0.normal.value, 0.2, 1e-12);
    EXPECT_NEAR(k0.tangent1.value, 0.0, 1e-12);
    const double s = 1e-3;
    LinePairInput moved = in;
    moved.xA2[0] += s;
    moved.xA2[1] += s;
    const ContactKinematics km = endToEndKinematics(moved, cp.etaRate, cp.across2);
    EXPECT_NEAR(km.tangent1.value, s, 1e-12);
    EXPECT_NEAR(km.tangent2.value, -s, 1e-12);
    EXPECT_NEAR(km.normal.value, 0.2, 1e-12);
    for (double theta : {0.05, 0.2, 0.5}) {
      LinePairInput tilted = in;
      tilted.RA2 = expSO3(Vec3d{{theta, 0, 0}});
      const double half = rect ? in.endHalf[1] : in.endRadius;
      const double exact = 0.2 - half * std::sin(theta);
      const double gap = endToEndProjection(tilted).gap;
      EXPECT_GE(gap, exact - 1e-12) << theta;
      EXPECT_LE(gap, exact + 0.0164 * half + 1e-12) << theta;
    }
  }
  std::mt19937 g(41);
  double worstR = 0.0, worstK = 0.0, worstUnit = 0.0;
  for (int trial = 0; trial < 8; ++trial) {
    const bool rect = trial % 2;
    LinePairInput in = endToEnd(rect);
    if (trial % 4 >= 2) {  // the ends at the elements' first nodes
      std::swap(in.xA1, in.xA2);
      in.endNode = 0;
      in.outward = -1.0;
      in.endAxes[0] = {{0, 0, -1}};
      std::swap(in.xB1, in.xB2);
      in.otherEnd = 0;
    }
    if (trial % 3 != 0) {
      in.dA = in.xA2 - in.xA1;
      in.dB = in.xB2 - in.xB1;
    }
    placeGenerally(in, g, 0.3);
    const ClosestPoints cp = endToEndProjection(in);
    const double p1 = cp.etaRate - 0.01, p2 = cp.across2 + 0.02;
    const auto [errR, errK] = centralDifferenceErrors(
        in, [&](const LinePairInput& s) { return endToEndKinematics(s, p1, p2); },
        {&ContactKinematics::normal, &ContactKinematics::tangent1, &ContactKinematics::tangent2});
    worstR = std::max(worstR, errR);
    worstK = std::max(worstK, errK);
    const ContactKinematics k = endToEndKinematics(in, p1, p2);
    Vec3d f[3];
    worstUnit = std::max(worstUnit, orthonormalDeparture(k, f));
  }
  std::printf("end-to-end contact, max relative error: R %.2e, K %.2e; forces' departure from orthonormal %.2e\n",
              worstR, worstK, worstUnit);
  EXPECT_LT(worstR, 1e-6);
  EXPECT_LT(worstK, 1e-6);
  EXPECT_LT(worstUnit, 1e-9);
}

// PointKey::first(pair) is the least key of its pair: ContactManager::held looks a pair's points up
// from it in the points' map (the pair first in the order, then line nodes by edge descending, Gauss
// points, point contacts), so no point of the pair may sort before it and none of the pair before.
TEST(PointKey, FirstOfAPairComesBeforeEachOfItsKeysAndAfterThoseOfThePairBefore) {
  const auto keysOf = [](int pair) {
    std::vector<PointKey> keys;
    for (int edge = 0; edge < 4; ++edge)
      for (int node : {0, 1, 37}) keys.push_back(PointKey::lineNode(pair, edge, node));
    for (int g = 0; g < 3; ++g) keys.push_back(PointKey::gaussPoint(pair, 5, 40000, 3, 3, 4095 - g));
    keys.push_back(PointKey::gaussPoint(pair, 0, 0, 0, 0, 0));
    keys.push_back(PointKey::contact(pair, 0, 0));
    keys.push_back(PointKey::contact(pair, 3, 2));
    keys.push_back(PointKey::endPoint(pair, true, 1, 3));
    keys.push_back(PointKey::cornerPoint(pair, false, 0, 2, 3));
    keys.push_back(PointKey::endToEndPoint(pair, true, 1, 0));
    return keys;
  };
  const PointKey first = PointKey::first(3);
  for (const PointKey& k : keysOf(3)) EXPECT_FALSE(k < first) << k;
  for (const PointKey& k : keysOf(2)) EXPECT_TRUE(k < first) << k;
  for (const PointKey& k : keysOf(4)) EXPECT_TRUE(first < k) << k;
}
