// Twisting rods (input/twisting_rods.xml, docs/contact.md "Twisting rods: the double helix"): two
// rods in line contact, stretched by 1 % and twisted by half a turn, end on the double helix with
// each strategy. The full table (16, 32, 64 elements x 10, 20, 50 increments) is
// bench/bench_twisting.py.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "support/ContactDecks.hpp"

using namespace bc;
using namespace bc::test;

namespace {
// The deck's values (bench/twisting_deck.py).
constexpr double kR = 1.0, kL = 100.0, kE = 2e5, kNu = 0.3, kStretch = 0.01, kEpsN = 1e4;
const double kTheta = std::acos(-1.0);

struct Helix {
  double phaseError = 0.0;  // the mid node's phase - theta / 2 [rad]
  double load = 0.0, closedForm = 0.0;  // line load on the middle quarter, per reference length
  double gap = 0.0;  // its Gauss points' mean gap (weighted by length)
  double radius = 0.0;  // the mid node's distance from the axis
  double layer = 0.0, layerClosedForm = 0.0;  // the ends' boundary layer: (H - theta c) / 2 and sqrt(EI / N)
  int newton = 0;
};

// The run's helix on rod 1's middle quarter, between its nodes at L/8 below and above the middle, and
// the closed form P = kappa (N + EI tau^2) - kappa tau M_t for its measured radius R, pitch 2 pi c,
// tension N = EA (stretch - 1) and twisting moment M_t (the top clamp's reaction about z; the same
// along the wire), times the stretch (the line traction is per reference length).
Helix measure(const input::Problem& p, const core::RunResult& r, const std::string& directory) {
  const auto& nodes = p.beams->beams()[0].nodes;
  const int n = static_cast<int>(nodes.size()) - 1;
  const auto at = [&](int i) { return r.finalState.position[nodes[i]]; };
  const core::Vec3d mid = at(n / 2), below = at(n / 2 - n / 8), above = at(n / 2 + n / 8);
  Helix h;
  h.phaseError = std::atan2(mid[1], mid[0]) - 0.5 * kTheta;
  h.radius = std::hypot(mid[0], mid[1]);
  const double dphi = std::atan2(above[1], above[0]) - std::atan2(below[1], below[0]), dz = above[2] - below[2];
  const double c = dz / dphi, R = h.radius;
  const double stretch = std::hypot(dz, R * dphi) / (kL / 4);
  const double pi = std::acos(-1.0), EA = kE * pi * kR * kR, EI = kE * pi * std::pow(kR, 4) / 4;
  const double N = EA * (stretch - 1.0), Mt = lastReactions(directory).at("rod1 top z_Mz");
  const double kappa = R / (R * R + c * c), tau = c / (R * R + c * c);
  h.closedForm = (kappa * (N + EI * tau * tau) - kappa * tau * Mt) * stretch;
  h.layer = 0.5 * (kL * (1 + kStretch) - kTheta * c);
  h.layerClosedForm = std::sqrt(EI / N);
  double force = 0.0, length = 0.0, gap = 0.0;
  for (const auto& [key, q] : p.contact->points()) {
    if (!q.line() || !q.result.active || q.position[2] < below[2] || q.position[2] > above[2]) continue;
    force += -q.result.lambdaN;
    length += q.length;
    gap += q.gap * q.length;
  }
  h.load = force / length;
  h.gap = gap / length;
  for (const auto& s : r.steps) h.newton += s.iterations;
  return h;
}
}  // namespace

// 16 elements on rod 1 (15 on rod 2: docs/contact.md says why), 10 increments, each strategy: the run
// is complete, the mid node at theta / 2 (exact by symmetry: 1e-9 rad; on another branch it is degrees
// off), the gap on the middle quarter within 1e-2 of -P / eps_N (Penalty: its law) or 2e-5 r of 0
// (Lagrange measured 6.9e-6; Augmented Lagrange, which converges to Lagrange's field, the same), the
// boundary layer within 15 % of sqrt(EI / N) (its linear estimate; measured 8 %, 3.5 %, 3.4 % with 16,
// 32, 64 elements), and the line load there against the closed form: Lagrange and Augmented Lagrange
// within 5e-3 (measured -2.5e-3, -5.3e-4, +4.1e-4 with 16, 32, 64 elements: the last is the boundary
// layer's 5e-4 at the quarter's ends), Penalty within 1e-2 (measured -7.3e-3).
TEST(TwistingRods, EveryStrategyEndsOnTheHelix) {
  for (const std::string type : {"Penalty", "Lagrange Multiplier", "Augmented Lagrange"}) {
    Deck deck = inputDeck("twisting_rods.xml", type);
    auto p = input::buildProblem(deck, "twisting");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "twisting");
    ASSERT_TRUE(r.report.completed) << type << ": " << r.report.failure;
    const Helix h = measure(p, r, scratchDirectory("twisting_np1"));
    const double gapReference = type == "Penalty" ? -h.closedForm / kEpsN : 0.0;
    std::printf(
        "%s, 16 elements, 10 increments: %d Newton iterations, phase error %.1e rad, line load %.6f against %.6f "
        "(%.1e), gap %.3e (reference %.3e), radius %.8f, boundary layer %.3f (sqrt(EI / N) %.3f)\n",
        type.c_str(), h.newton, h.phaseError, h.load, h.closedForm, h.load / h.closedForm - 1.0, h.gap, gapReference,
        h.radius, h.layer, h.layerClosedForm);
    EXPECT_LT(std::abs(h.phaseError), 1e-9) << type;
    if (type == "Penalty") {
      EXPECT_LT(std::abs(h.load / h.closedForm - 1.0), 1e-2);
      EXPECT_LT(std::abs(h.gap / gapReference - 1.0), 1e-2);
    } else {
      EXPECT_LT(std::abs(h.load / h.closedForm - 1.0), 5e-3) << type;
      EXPECT_LT(std::abs(h.gap), 2e-5 * kR) << type;
    }
    EXPECT_NEAR(h.layer, h.layerClosedForm, 0.15 * h.layerClosedForm) << type;
  }
}

// The line step bound (docs/contact.md, "Newton with contact"): a rod lying on a ground (r = 0.5
// each, every node held, touching at gap 0; or lifted by 0.2) and a step that moves the rod down by
// d. The gap falls linearly with the step's fraction s, g(s) = g_0 - d s (also beyond the ground's
// axis: a line point keeps its side), so a step the bound shortens stops where the gap is
// min(g_0, 0) - 0.1 r_min: s = (g_0 + 0.05) / d, when g_0 - d < -0.2 r_min. A step that goes no deeper
// than that is not shortened, nor is one that opens the contact. The same for every strategy.
TEST(LineStepBound, AStepIntoOrThroughTheOtherBeamStopsAtATenthOfTheRadius) {
  for (const std::string type : {"Penalty", "Lagrange Multiplier", "Augmented Lagrange"})
    for (const double lift : {0.0, 0.2}) {
      auto deck = parallelBeams(type, 10, 10, 0.0, 1e5, 2, 0.0, lift);
      for (int i = 0; i <= 10; ++i) {
        support(deck, "ground", i, "all");
        support(deck, "rod", i, "all");
      }
      auto p = input::buildProblem(deck, "line_step_bound");
      const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "line_step_bound");
      ASSERT_TRUE(r.report.completed) << r.report.failure;
      ASSERT_GT(p.contact->points().size(), 0u);
      const core::State& s = r.finalState;
      const auto down = [&](double d) {
        std::vector<double> du(s.numDofs(), 0.0);
        for (int n : p.beams->beams()[1].nodes) du[std::size_t(core::kDofsPerNode) * n + 2] = -d;
        return du;
      };
      for (const double d : {1.5, 0.5, 0.15}) {
        const double expected = lift - d < -0.1 ? (lift + 0.05) / d : 1.0;
        const double bound = p.contact->stepBound(s, down(d));
        std::printf("%s, gap %.1f, step down by %.2f: bound %.15f (closed form %.15f)\n", type.c_str(), lift, d, bound,
                    expected);
        EXPECT_NEAR(bound, expected, 1e-9) << type << " lift " << lift << " d " << d;
      }
      EXPECT_EQ(p.contact->stepBound(s, down(lift + 0.09)), 1.0) << type;
      EXPECT_EQ(p.contact->stepBound(s, down(-0.3)), 1.0) << type;
    }
}
