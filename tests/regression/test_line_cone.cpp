// The Coulomb cone on lines: the force a Gauss point of line contact applies on beam B (its residual
// lambda_N R_N + lambda_T R_T2 on B's nodal translations, ContactPointRecord::normalForce and
// tangentialForce) obeys |F_T| <= mu |F_N| at every Gauss point, with equality where a Penalty point
// slips, for every strategy: the slip along B is measured so that its variation is the unit tangent
// of B at the projection, the slip across so that its variation is b = n x t_B (docs/contact.md,
// "The Coulomb cone on lines", "Friction across the axes").
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "support/ContactDecks.hpp"

using namespace bc;
using namespace bc::test;

namespace {

// Per run, over the active Gauss points at the end: ratio = |F_T| / (mu |F_N|) with F the force the
// point applies on beam B, F_N its part along the point's normal and F_T the rest (the definition of
// the force the residual applies); the largest, the smallest and largest of the slipping points; in
// sum, |sum F_T| / (mu sum |F_N|) (the resultant friction force against mu times the total normal
// force: at most 1 by Coulomb's law at every point) and sum |F_T| / (mu sum |F_N|) (1 in full slip).
// A multiplier field's line nodes (Lagrange, Augmented Lagrange, Penalty's springs on the nodes):
// their multipliers' |lambda_T| / (mu |lambda_N|), smallest and largest over the slipping ones. Circles
// slip along and across the axes (two orthogonal slips, M = I). A node's slip rows are its Gauss
// points' rows with its multipliers, tested with its hat function: where those points slip in
// different directions, the rows average the directions and the node lies inside the cone by the
// spread (docs/contact.md, "Friction across the axes"); a Gauss point between two nodes applies
// their interpolation, inside too (|N_a a + N_b b| < N_a |a| + N_b |b|).
struct Cone {
  int active = 0, slipping = 0, slippingNodes = 0;
  double worst = 0.0, slipLow = 1e300, slipHigh = 0.0, sum = 0.0, slipSum = 0.0;
  double nodeLow = 1e300, nodeHigh = 0.0;
};
Cone cone(const input::Problem& p, double mu) {
  Cone c;
  double T = 0.0, N = 0.0;
  elements::Vec3d FT{};
  for (const auto& [key, q] : p.contact->points()) {
    if (q.node() && q.result.active && q.result.slip[1] && q.result.lambdaN < 0.0) {
      const double ratio = std::hypot(q.result.lambdaT[0], q.result.lambdaT[1]) / (-mu * q.result.lambdaN);
      ++c.slippingNodes;
      c.nodeLow = std::min(c.nodeLow, ratio);
      c.nodeHigh = std::max(c.nodeHigh, ratio);
    }
    if (!q.line() || !q.result.active) continue;
    const double n = norm(q.normalForce), t = norm(q.tangentialForce);
    if (!(n > 0.0)) continue;
    ++c.active;
    const double ratio = t / (mu * n);
    c.worst = std::max(c.worst, ratio);
    if (q.result.slip[1]) {
      ++c.slipping;
      c.slipLow = std::min(c.slipLow, ratio);
      c.slipHigh = std::max(c.slipHigh, ratio);
    }
    T += t;
    N += n;
    FT = FT + q.tangentialForce;
  }
  c.sum = norm(FT) / (mu * N);
  c.slipSum = T / (mu * N);
  return c;
}

void print(const std::string& what, const std::string& type, const core::RunResult& r, const Cone& c) {
  std::printf(
      "%s, %s: %d active, %d slipping; |F_T| / mu |F_N| largest %.12f, slipping %.12f .. %.12f; in sum: "
      "|sum F_T| / mu sum |F_N| %.12f, sum |F_T| / mu sum |F_N| %.12f; %d Newton iterations\n",
      what.c_str(), type.c_str(), c.active, c.slipping, c.worst, c.slipLow, c.slipHigh, c.sum, c.slipSum,
      r.report.newtonIterations);
  if (c.slippingNodes > 0)
    std::printf("  %d field nodes slipping, |lambda_T| / mu |lambda_N| %.12f .. %.12f\n", c.slippingNodes, c.nodeLow,
                c.nodeHigh);
}

// Two circular beams at 3 degrees (parallelBeams: ground 20 elements, rod 12, lifted 0.1, E 1e5),
// clamped at their ends, every inner node held sideways; the rod's ends pressed down by 0.2 (closure
// 0.1) while T goes to 0.5, then dragged along X by 0.3 while T goes to 1 (20 increments), mu 0.3.
Deck drag(const std::string& type) {
  Deck deck = parallelBeams(type, 20, 12, 0.0, 1e5, 6, 3.0, 0.1);
  input::replaceAtPath(deck, "Load Stepping/Number of Increments", 20);
  input::replaceAtPath(deck, "Contact/Pairs/line/Friction Coefficient", 0.3);
  support(deck, "ground", 0, "all");
  support(deck, "ground", 20, "all");
  for (int i = 1; i < 20; ++i) support(deck, "ground", i, "uy");
  for (int i = 1; i < 12; ++i) support(deck, "rod", i, "uy");
  for (const int node : {0, 12}) {
    support(deck, "rod", node, "uy uz rx ry rz", -0.2);
    const std::string s = "Supports/rod " + std::to_string(node);
    input::setAtPath(deck, s + "/Load Curve", vec("0, 0, 0.5, 1, 1, 1"));
    Deck& move = input::sublistAtPath(deck, s + " drag");
    move.set("Beam", std::string("rod"));
    move.set("Node", std::to_string(node));
    move.set("Fixed", std::string("ux"));
    move.set("Displacement", vec("0.3, 0, 0"));
    move.set("Load Curve", vec("0, 0, 0.5, 0, 1, 1"));
  }
  return deck;
}

// A wire wound on a straight core: the core (beam A, r = 0.5, along Z, 16 elements) held at every
// node; the wire (beam B, r = 0.5) a helix of radius 1 about the core's axis (touching it) with a lay
// angle of 10 degrees, one turn, 16 elements, pressed on the core by radial forces of 0.02 at its
// inner nodes and slid along Z by 0.05 at every node (its end nodes held across), mu 0.3. B is
// curved (kappa = sin^2(10 deg) / 1 = 0.030) and A's point lies on the inside of its bend at
// r_A + r_B = 1: the slip along B's chord (before) was 1 / (1 - 0.030) = 1.031 times too short.
Deck helix(const std::string& type) {
  const double pi = std::acos(-1.0), alpha = 10.0 * pi / 180.0, pitch = 2.0 * pi / std::tan(alpha);
  const int n = 16;
  Deck deck("BeamContact");
  const auto material = [](Deck& b) {
    b.sublist("Section").set("Shape", std::string("Circle"));
    b.sublist("Section").set("Radius", 0.5);
    b.sublist("Material").set("Young's Modulus", 1e5);
    b.sublist("Material").set("Poisson's Ratio", 0.3);
  };
  Deck& core = deck.sublist("Beams").sublist("core");
  core.set("Start", vec("0, 0, 0"));
  core.set("End", vec("0, 0, " + num(pitch)));
  core.set("Elements", n);
  material(core);
  Deck& wire = deck.sublist("Beams").sublist("wire");
  Deck& h = wire.sublist("Helix");
  h.set("Axis Point", vec("0, 0, 0"));
  h.set("Axis Direction", vec("0, 0, 1"));
  h.set("Radius", 1.0);
  h.set("Pitch", pitch);
  h.set("Turns", 1.0);
  h.set("Reference Direction", vec("1, 0, 0"));
  h.set("Start Angle", 0.0);
  wire.set("Elements", n);
  material(wire);
  for (int i = 0; i <= n; ++i) {
    support(deck, "core", i, "all");
    Deck& s = deck.sublist("Supports").sublist("wire " + std::to_string(i));
    s.set("Beam", std::string("wire"));
    s.set("Node", std::to_string(i));
    s.set("Fixed", std::string(i == 0 || i == n ? "ux uy uz rz" : "uz"));
    s.set("Displacement", vec("0, 0, 0.05"));
    if (i == 0 || i == n) continue;
    const double t = 2.0 * pi * i / n;
    Deck& load = deck.sublist("Loads").sublist("wire " + std::to_string(i));
    load.set("Beam", std::string("wire"));
    load.set("Node", std::to_string(i));
    load.set("Force", vec(num(-0.02 * std::cos(t)) + ", " + num(-0.02 * std::sin(t)) + ", 0"));
  }
  Deck& c = deck.sublist("Contact");
  Deck& pair = c.sublist("Pairs").sublist("wound");
  pair.set("Beam A", std::string("core"));
  pair.set("Beam B", std::string("wire"));
  pair.set("Friction Coefficient", 0.3);
  c.set("Line Contact Angle", 12.0);
  c.set("Point Contact Angle", 17.0);
  c.set("Allow Initial Penetration", true);
  c.sublist("Enforcement").set("Type", type);
  for (const char* s : {"Penalty", "Augmented Lagrange"}) {
    c.sublist("Enforcement").sublist(s).set("Normal Penalty Parameter", 1e4);
    c.sublist("Enforcement").sublist(s).set("Tangential Penalty Parameter", 1e3);
  }
  deck.sublist("Load Stepping").set("Number of Increments", 2);
  deck.sublist("Output").set("Write VTK", false);
  return deck;
}

// Runs `deck` with each strategy; each must complete with every active point slipping (at least
// `slipping` of them), within the cone (|F_T| <= mu |F_N| to 1e-9) and their sums within it, with no
// cone warning. On it: Penalty's Gauss points; the field strategies' slipping nodes and Gauss points
// at least `fieldLow` of the way (Cone). Then `more` (the problem, its result, the strategy) may check
// more.
template <class DeckOf, class More>
void expectEveryStrategyOnTheCone(const DeckOf& deckOf, const std::string& name, const std::string& what, int slipping,
                                  double fieldLow, const More& more) {
  for (const std::string type : {"Penalty", "Penalty Nodes", "Augmented Lagrange", "Lagrange Multiplier"}) {
    // ("Penalty Nodes": Penalty with Line Springs = Nodes, its springs eps_N, eps_T on Lagrange's field.)
    auto deck = deckOf(type == "Penalty Nodes" ? "Penalty" : type);
    if (type == "Penalty Nodes")
      input::setAtPath(deck, "Contact/Enforcement/Penalty/Line Springs", std::string("Nodes"));
    auto p = input::buildProblem(deck, name);
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), name);
    EXPECT_TRUE(r.report.completed) << type << ": " << r.report.failure;
    if (!r.report.completed) continue;
    const Cone c = cone(p, 0.3);
    print(what, type, r, c);
    for (const std::string& w : r.report.warnings) EXPECT_EQ(w.find("Coulomb cone"), std::string::npos) << w;
    EXPECT_GE(c.slipping, slipping) << type;
    EXPECT_EQ(c.slipping, c.active) << type;
    EXPECT_LE(c.worst, 1.0 + 1e-9) << type;
    EXPECT_LE(c.sum, 1.0 + 1e-9) << type;
    if (type == "Penalty") {
      EXPECT_NEAR(c.slipHigh, 1.0, 1e-9) << type;
      EXPECT_NEAR(c.slipLow, 1.0, 1e-9) << type;
      EXPECT_NEAR(c.slipSum, 1.0, 1e-9) << type;
    } else {
      EXPECT_GT(c.slippingNodes, 0) << type;
      EXPECT_GT(c.nodeLow, fieldLow) << type;
      EXPECT_LE(c.nodeHigh, 1.0 + 1e-9) << type;
      EXPECT_GT(c.slipLow, fieldLow) << type;
      EXPECT_GT(c.slipSum, fieldLow) << type;
    }
    more(p, r, type);
  }
}

}  // namespace

TEST(LineCone, DragAtThreeDegreesStaysOnTheCone) {
  expectEveryStrategyOnTheCone(
      drag, "cone_drag", "drag at 3 degrees", 2, 0.999,
      [](const input::Problem& p, const core::RunResult& r, const std::string& type) {
        // The tangent of the new residual: the rod dragged on by 1e-3 from the end, every line point
        // slipping, against central differences of the contact residual.
        core::State s = r.finalState;
        for (int n : p.beams->beams()[1].nodes)
          s.applyNodeIncrement(n, std::array<double, 6>{1e-3, 0, 0, 0, 0, 0}.data());
        double kmax = 0.0;
        const double err = assembledContactTangentError(p, s, kmax);
        std::printf("  %s, dragged on: contact tangent vs central differences, max error / max |K| = %.2e\n",
                    type.c_str(), err / kmax);
        EXPECT_LT(err / kmax, 1e-6) << type;
      });
}

TEST(LineCone, WireSlidOnACoreStaysOnTheCone) {
  expectEveryStrategyOnTheCone(helix, "cone_helix", "wire on a core", 10, 0.95,
                               [](const input::Problem&, const core::RunResult&, const std::string&) {});
}

// Partial slip along a line. A rod (beam B) lies on a ground held at every node (both circles,
// r = 0.5, touching, 100 long, n elements each), pressed by a uniform line load q = 0.01 while T goes
// to 0.5 (nodal forces q h, half at the ends; its end nodes held at the ground's height), then pulled
// at its far end along X by F = 0.15 while T goes to 1 (20 increments); its near end held along X,
// mu 0.3. Friction carries the pull: a zone at the pulled end slips (force mu q per length), the rest
// sticks, and with the contact exact the slipping zone's length tends to F / (mu q) = 50 and the held
// end's reaction to 0 as the mesh is refined (the stick zone then carries nothing). Lagrange's
// friction rows on the field's nodes, tested with the field's hat functions (consistent), put a
// slipping node beside a sticking one outside the cone: 1.046 mu N at T = 1 with 20 elements (1.064
// during the run), warned, before its slip rows were lumped on the node (LineContact::evaluateNodal).
namespace {
Deck pull(const std::string& type, int n) {
  Deck deck = parallelBeams(type, n, n, 0.0, 1e5, 6);
  input::replaceAtPath(deck, "Load Stepping/Number of Increments", 20);
  input::replaceAtPath(deck, "Contact/Pairs/line/Friction Coefficient", 0.3);
  const double q = 0.01, h = 100.0 / n;
  for (int i = 0; i <= n; ++i) {
    support(deck, "ground", i, "all");
    support(deck, "rod", i, i == 0 ? "ux uy uz rx rz" : i == n ? "uy uz rx rz" : "uy rx rz");
    Deck& load = input::sublistAtPath(deck, "Loads/press " + std::to_string(i));
    load.set("Beam", std::string("rod"));
    load.set("Node", std::to_string(i));
    load.set("Force", vec("0, 0, " + num(-q * h * (i == 0 || i == n ? 0.5 : 1.0))));
    load.set("Load Curve", vec("0, 0, 0.5, 1, 1, 1"));
  }
  Deck& load = input::sublistAtPath(deck, "Loads/pull");
  load.set("Beam", std::string("rod"));
  load.set("Node", std::to_string(n));
  load.set("Force", vec("0.15, 0, 0"));
  load.set("Load Curve", vec("0, 0, 0.5, 0, 1, 1"));
  return deck;
}
}  // namespace

TEST(LineCone, PartialSlipUnderAPullStaysInTheCone) {
  const double mu = 0.3, F = 0.15;
  std::map<int, std::pair<double, double>> lagrange;  // elements -> (held end's share of F, first slipping x)
  for (const auto& [type, n] : std::vector<std::pair<std::string, int>>{{"Penalty", 20},
                                                                        {"Penalty Nodes", 20},
                                                                        {"Augmented Lagrange", 20},
                                                                        {"Lagrange Multiplier", 20},
                                                                        {"Lagrange Multiplier", 40}}) {
    const std::string name = "cone_pull";
    // ("Penalty Nodes": Penalty with Line Springs = Nodes, its springs eps_N, eps_T on Lagrange's field.)
    auto deck = pull(type == "Penalty Nodes" ? "Penalty" : type, n);
    if (type == "Penalty Nodes")
      input::setAtPath(deck, "Contact/Enforcement/Penalty/Line Springs", std::string("Nodes"));
    auto p = input::buildProblem(deck, name);
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), name);
    ASSERT_TRUE(r.report.completed) << type << ": " << r.report.failure;
    for (const std::string& w : r.report.warnings) EXPECT_EQ(w.find("Coulomb cone"), std::string::npos) << w;
    const Cone c = cone(p, mu);
    // The rod's balance along X: the contact's forces on it, the held end's reaction and the pull.
    double friction = 0.0, firstSlip = 1e300;
    int sticking = 0;
    for (const auto& [key, q] : p.contact->points()) {
      if (!q.line() || !q.result.active) continue;
      friction += q.tangentialForce[0] + q.normalForce[0];
      // (Points carrying a force: at x = 10 some of the field's points carry 1e-10, and their
      // friction, at that scale, may lie on the cone.)
      if (q.result.slip[1] && norm(q.normalForce) > 1e-6) firstSlip = std::min(firstSlip, q.position[0]);
      sticking += !q.result.slip[1] && norm(q.normalForce) > 1e-6;
    }
    const double held = lastReactions(test::scratchDirectory(name + "_np1")).at("rod 0_Fx");
    print("pulled rod, " + std::to_string(n) + " elements", type, r, c);
    std::printf(
        "  sticking %d; friction on the rod %.9f, held end %.3e (%.2f %% of the pull), balance %.1e; first "
        "slipping point at x = %.3f (limit 50)\n",
        sticking, friction, held, 100.0 * std::abs(held) / F, (friction + held + F) / F, firstSlip);
    EXPECT_LE(c.worst, 1.0 + 1e-9) << type;
    EXPECT_NEAR(c.slipHigh, 1.0, 1e-9) << type;
    // (A field's Gauss point takes the state of its nearer node: between a slipping node and a sticking
    // one it reports slip with the force interpolated between them, inside the cone.)
    if (type == "Penalty") {
      EXPECT_NEAR(c.slipLow, 1.0, 1e-9) << type;
    }
    EXPECT_GT(sticking, 10) << type;
    EXPECT_GT(c.slipping, 10) << type;
    EXPECT_LT(std::abs(friction + held + F), 1e-8 * F) << type;
    if (type == "Lagrange Multiplier") lagrange[n] = {std::abs(held) / F, firstSlip};
  }
  // Towards the exact partial slip: the held end's share falls as h^2 (measured 5.2 % and 1.5 %), the
  // slipping zone's start towards x = 50 (53.10, 51.55).
  EXPECT_LT(lagrange[40].first, lagrange[20].first / 3.0);
  EXPECT_LT(lagrange[40].second - 50.0, lagrange[20].second - 50.0);
  EXPECT_GT(lagrange[40].second, 50.0);
}
