// The contact contribution's assembled tangent against central differences of its residual, for each
// strategy: Example 1 in states with sliding and sticking lines (per-line and isotropic friction), and
// line contact of parallel and slightly crossed beams.
#include <gtest/gtest.h>

#include <cmath>
#include <array>
#include <fstream>
#include <map>
#include <random>
#include <regex>
#include <sstream>

#include "constraints/AugmentedLagrangeEnforcer.hpp"
#include "constraints/ContactManager.hpp"
#include "constraints/LagrangeMultiplierEnforcer.hpp"
#include "constraints/EnforcerRegistry.hpp"
#include "constraints/RegularizedContactLaw.hpp"
#include "core/Assembler.hpp"
#include "support/ContactDecks.hpp"

using namespace bc;
using namespace bc::test;

TEST(ContactTangent, PenaltySlipAndStick) {
  checkContactTangent("Penalty", example1("Penalty", "40.0, 0.0, -20.0", 10), 0.3, true, true, 0.5);
}
TEST(ContactTangent, AugmentedLagrangeSlip) {
  // Without the predictor: with these coarse increments (0.1) the extrapolated start of the step to
  // T = 0.2 leads to the four-point contact state, where the augmentations then stall at T = 0.25;
  // from the last converged state the path keeps two points up to T = 0.3, the state wanted here.
  Deck deck = example1("Augmented Lagrange", "40.0, 0.0, -20.0", 10);
  input::setAtPath(deck, "Nonlinear Solver/Predictor", std::string("None"));
  checkContactTangent("Augmented Lagrange", deck, 0.3, true, false, 0.5);
}
TEST(ContactTangent, LagrangeMultiplierSlipWithMultiplierRows) {
  // The 27-dof point elements: displacement rows, multiplier columns and the constraint rows.
  checkContactTangent("Lagrange Multiplier", example1("Lagrange Multiplier", "40.0, 0.0, -20.0", 10), 0.3, true, false,
                      0.5);
}
TEST(ContactTangent, LagrangeMultiplierStick) {
  Deck deck = circles("Lagrange Multiplier", 3.0, 1e4);
  input::replaceAtPath(deck, "Contact/Pairs/crossing/Friction Coefficient", 5.0);
  checkContactTangent("Lagrange Multiplier", deck, 1e-3, false, true, 5.0);
}
TEST(ContactTangent, AugmentedLagrangeStick) {
  // One pressed point (circular sections) with mu = 5: both lines stick well inside the Coulomb cone.
  Deck deck = circles("Augmented Lagrange", 3.0, 1e4);
  input::replaceAtPath(deck, "Contact/Pairs/crossing/Friction Coefficient", 5.0);
  checkContactTangent("Augmented Lagrange", deck, 1e-3, false, true, 5.0);
}

// The isotropic Coulomb tangents against central differences of the residual: slip on Example 1
// (penalty, augmented Lagrange, Lagrange multiplier rows from the complementarity function), stick
// with one pressed circular point and mu = 5.
TEST(ContactTangent, IsotropicSlip) {
  checkContactTangent("Penalty", withLaw(example1("Penalty", "40.0, 0.0, -20.0", 10), "Isotropic Coulomb"), 0.3, true,
                      false, 0.5);
  checkContactTangent("Lagrange Multiplier",
                      withLaw(example1("Lagrange Multiplier", "40.0, 0.0, -20.0", 10), "Isotropic Coulomb"), 0.3, true,
                      false, 0.5);
  Deck deck = withLaw(example1("Augmented Lagrange", "40.0, 0.0, -20.0", 10), "Isotropic Coulomb");
  input::setAtPath(deck, "Nonlinear Solver/Predictor", std::string("None"));
  checkContactTangent("Augmented Lagrange", deck, 0.3, true, false, 0.5);
}
TEST(ContactTangent, IsotropicStick) {
  for (const std::string type : {"Penalty", "Lagrange Multiplier", "Augmented Lagrange"}) {
    Deck deck = withLaw(circles(type, 3.0, 1e4), "Isotropic Coulomb");
    input::replaceAtPath(deck, "Contact/Pairs/crossing/Friction Coefficient", 5.0);
    checkContactTangent(type, deck, 1e-3, false, true, 5.0);
  }
}

// The assembled line-contact tangent against central differences of the residual, for each strategy
// (Lagrange's and Augmented Lagrange's multiplier fields on line A's nodes): non-matching meshes (ground 6 elements,
// rod 5 shifted by 2, 4 Gauss points, so projections cross the rod's element boundaries), both beams clamped at their
// ends and touching, the rod's inner nodes then pushed 0.05 into the ground with finite rotations and sideways motion.
TEST(LineContact, TangentMatchesCentralDifferences) {
  // Parallel, and turned by 10 degrees (inside the blend of point and line contact, whose weight
  // depends on the angle: its gradient enters the tangent).
  // Rectangular sections too (face to face: A's upper edges on B's lower face; with the rod half as
  // wide, its lower edges on the ground's upper face, the points' roles swapped; 2 Gauss points).
  // The rod starting at x = 20 (shift), inside the ground's second element (16.7 .. 33.3): its free end
  // cuts that element's field (a point at the end carries the node beyond it). The narrow rod so
  // placed carries the field on its own edges, whose end nodes (held, but no held node of the ground
  // beside them) keep their multipliers: points at the rod's own ends.
  struct Case {
    std::string type;
    double degrees;
    bool rectangles;
    double rodWidth = 2.0;
    int gauss = 4;
    double shift = 2.0;
  };
  for (const Case& c : std::vector<Case>{{"Penalty", 0.0, false},
                                         {"Augmented Lagrange", 0.0, false},
                                         {"Lagrange Multiplier", 0.0, false},
                                         {"Penalty", 10.0, false},
                                         {"Augmented Lagrange", 10.0, false},
                                         {"Lagrange Multiplier", 10.0, false},
                                         {"Penalty", 0.0, true},
                                         {"Lagrange Multiplier", 0.0, true},
                                         {"Penalty", 0.0, true, 1.0, 2},
                                         {"Lagrange Multiplier", 0.0, true, 1.0, 2},
                                         {"Augmented Lagrange", 0.0, true, 1.0, 2},
                                         {"Lagrange Multiplier", 0.0, false, 2.0, 4, 20.0},
                                         {"Augmented Lagrange", 0.0, false, 2.0, 4, 20.0},
                                         {"Lagrange Multiplier", 0.0, true, 1.0, 2, 20.0},
                                         {"Augmented Lagrange", 0.0, true, 1.0, 2, 20.0}}) {
    const std::string& type = c.type;
    const double degrees = c.degrees;
    // (Lifted by 1e-6: touching at exactly zero gap, the crossing's point carries a round-off force
    // in an unloaded step, which Newton's relative tolerance cannot accept.)
    // (Lagrange multipliers act on line nodes' weighted gaps: at 10 degrees shorter elements and a
    // deeper push make some of them negative.)
    // (Lagrange and Augmented Lagrange carry multipliers on a field of line nodes.)
    const bool field = type != "Penalty";
    const bool lm = field && degrees > 0;
    const int nGround = lm ? 30 : 6, nRod = lm ? 25 : 5;
    auto deck = parallelBeams(type, nGround, nRod, c.shift, 1e5, c.gauss, degrees, 1e-6);
    if (c.rectangles) deck = toRectangles(deck, c.rodWidth);
    // Friction along the axes.
    input::replaceAtPath(deck, "Contact/Pairs/line/Friction Coefficient", 0.3);
    for (int i = 0; i <= nGround; ++i) support(deck, "ground", i, i == 0 || i == nGround ? "all" : "ux uy rx");
    support(deck, "rod", 0, "all");
    support(deck, "rod", nRod, "all");
    auto p = input::buildProblem(deck, "line_tangent");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "line_tangent");
    ASSERT_TRUE(r.report.completed) << r.report.failure;
    core::State s = r.finalState;
    const auto& rod = p.beams->beams()[1].nodes;
    // (Where the rod starts inside the ground's element, its free first node goes down too, so that
    // the point at its end presses.)
    for (std::size_t i = c.shift > 2.0 ? 0 : 1; i + 1 < rod.size(); ++i) {
      const double a = 0.01 * static_cast<double>(i);
      const double dz = lm ? -0.4 : -0.05;
      // (Circles' slip is their surfaces': the rod's turn -a about y takes back r a of its slide, so
      // it slides further than the rectangles for some of its points to slip.)
      const double along = c.rectangles ? 0.3 : 0.6;
      s.applyNodeIncrement(rod[i], std::array<double, 6>{along * a, -0.2 * a, dz, 2 * a, -a, 3 * a}.data());
      // At 10 degrees the rod's inner nodes go further down, so the crossing and its neighbourhood
      // penetrate (point contact and line points at once).
    }
    int slippingNodes = 0;
    if (field) {
      // The active set of the pushed state (penetrating points and line nodes), with multipliers
      // of either sign so that every term of the tangent counts (Augmented Lagrange's estimates
      // stay 0, so its nodes' rows hold their regularization).
      // At 10 degrees the ground's field is refined at the crossing (its middle elements, to 2 and
      // 4 parts: interior field nodes, and Gauss points whose parts' hat functions are those of
      // interior and beam nodes).
      p.contact->prepareIteration(s);  // (the run's last step's refinement goes here)
      if (degrees > 0) {
        const auto& ground = p.beams->beams()[p.contact->pairs()[0].beamA].nodes;
        const int middle = static_cast<int>(ground.size()) / 2 - 1;
        const auto& elems = p.beams->elements();
        for (std::size_t e = 0; e < elems.size(); ++e)
          if (elems[e].beam == p.contact->pairs()[0].beamA && std::abs(elems[e].index - middle) <= 1)
            p.contact->refineLineFieldAt(0, static_cast<int>(e), elems[e].index == middle ? 2 : 1);
      }
      p.contact->prepareIteration(s);
      EXPECT_FALSE(p.contact->acceptSolution(s));
      p.contact->prepareIteration(s);
      ASSERT_GT(s.extra.size(), 0u);
      for (std::size_t i = 0; i < s.extra.size(); ++i) s.extra[i] = -0.1 * (1.0 + 0.37 * i) * (i % 4 == 3 ? -1 : 1);
      // Every other field node slipping (Per Line), either way: its friction row is its own
      // multipliers' s Lambda_T + mu Lambda_N, tested with its hat function (lumped), beside sticking
      // nodes whose rows are their weighted slips.
      int n = 0;
      for (const auto& [key, q] : p.contact->points()) {
        if (!q.node() || q.extraCount == 0 || n++ % 2 == 0) continue;
        auto* lm = dynamic_cast<constraints::LagrangeMultiplierEnforcer::State*>(&*q.state);
        auto* al = dynamic_cast<constraints::AugmentedLagrangeEnforcer::State*>(&*q.state);
        auto& h = lm ? *lm : al->field;
        h.slip[1] = true;
        h.slipSign[1] = n % 4 == 0 ? 1.0 : -1.0;
        ++slippingNodes;
      }
    }
    int active = 0, points = 0, slipping = 0, swapped = 0, interior = 0, cut = 0, ends = 0;
    for (const auto& [key, q] : p.contact->points()) {
      interior += q.node() && constraints::LineContact::interiorNode(q.key.node) && q.extraCount > 0;
      if (q.node()) continue;
      const auto* acting = p.contact->actingState(q);
      const auto k = p.contact->kinematics(q, s);
      const bool on = acting && p.contact->enforcer().contributes(k.normal.value, *acting);
      active += on;
      cut += on && q.line() && q.endCut && p.beams->elements()[q.elementA].index > 0;
      ends += on && constraints::LineContact::endPoint(q);  // the point at the rod's end
      swapped += on && q.line() && p.beams->elements()[q.elementA].beam != p.contact->pairs()[0].beamA;
      points += on && !q.line();
      if (on && q.line() && !field) {
        std::vector<double> f(constraints::kPairDofs, 0.0);
        slipping +=
            p.contact->enforcer().evaluate(p.contact->strategyView(q, k, s), *acting, f.data(), nullptr).slip[1];
      }
    }
    double kmax = 0.0;
    const double err = assembledContactTangentError(p, s, kmax);
    std::printf(
        "%s, %s, %.0f degrees: line contact tangent vs central differences: max error / max |K| = %.2e (%d "
        "points active, %d of them point contacts, %d with swapped roles, %d line points slipping, %d interior field "
        "nodes, %d on a part cut by the rod's end, %d of them at the end, %d field nodes slipping)\n",
        type.c_str(), c.rectangles ? (c.rodWidth < 2.0 ? "narrow rod on rectangle" : "rectangles") : "circles", degrees,
        err / kmax, active, points, swapped, slipping, interior, cut, ends, slippingNodes);
    if (field) {
      EXPECT_GT(slippingNodes, 1) << type;
    }
    if (field && degrees > 0) {
      EXPECT_GT(interior, 0) << type;
    }
    if (field && c.shift > 2.0) {
      EXPECT_GT(cut, 0) << type;  // Gauss points of a cut part, off the ground's end element
      EXPECT_GT(ends, 0) << type;  // and the point at the rod's end
    }
    // The narrow rod's edges on the ground's face carry the contact, with the roles swapped. (With
    // equal widths the push turns the rod's nodes by up to 0.12 about z, and where its edges swing
    // inside the ground's face they carry the contact there: 27 of Lagrange's 65 points.)
    if (c.rodWidth < 2.0) {
      EXPECT_EQ(swapped, active - points);
    }
    if (!field && degrees == 0) {
      EXPECT_GT(slipping, 0);  // friction along the axes, slipping ...
      EXPECT_LT(slipping, active);  // ... and sticking
    }
    EXPECT_GT(active - points, degrees > 0 ? 0 : 10);  // line points
    if (degrees > 0) {
      EXPECT_GT(points, 0);  // and, in the blend, a point contact
    }
    EXPECT_LT(err / kmax, 1e-6);
  }
}
