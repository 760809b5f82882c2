// Contact robustness: pass-through within one increment, deep penalty penetration, overlaps no
// contact point sees, contact points on nodes, and the contact search against a brute force.
#include <gtest/gtest.h>

#include <cmath>
#include <array>
#include <fstream>
#include <map>
#include <random>
#include <regex>
#include <sstream>

#include "constraints/ContactManager.hpp"
#include "constraints/EnforcerRegistry.hpp"
#include "constraints/RegularizedContactLaw.hpp"
#include "core/Assembler.hpp"
#include "support/ContactDecks.hpp"

using namespace bc;
using namespace bc::test;

// ---------------------------------------------------------------------------------------------
// Contact robustness: pass-through within one increment, deep penalty penetration, points on
// nodes, the friction cone, the reported force, stiff penalties.
namespace {
// Two thin crossed circular beams (r = 0.5): "lower" along X, clamped at both ends, 10 elements;
// "upper" along Y at x = 45 and 3 above (gap 2), 11 elements (the crossing lies inside an element
// of each beam), pinned ends driven down by 16 T. In 2 increments the first Newton step of the first
// increment carries "upper" 5 below "lower" before the search has seen the pair.
Deck pushedThrough(const std::string& type, int increments, double epsN) {
  const std::string beam =
      R"X(<ParameterList name="Section"><Parameter name="Shape" type="string" value="Circle"/>)X"
      R"X(<Parameter name="Radius" type="double" value="0.5"/></ParameterList>)X"
      R"X(<ParameterList name="Material"><Parameter name="Young's Modulus" type="double" value="30000.0"/>)X"
      R"X(<Parameter name="Poisson's Ratio" type="double" value="0.3"/></ParameterList>)X";
  const std::string end = R"X(<Parameter name="Fixed" type="string" value="ux uy uz ry"/>)X"
                          R"X(<Parameter name="Displacement" type="Array(double)" value="{0.0, 0.0, -16.0}"/>)X";
  return input::parseParameterXml(R"X(<ParameterList name="BeamContact"><ParameterList name="Beams">
    <ParameterList name="lower"><Parameter name="Start" type="Array(double)" value="{0.0, 0.0, 0.0}"/>
      <Parameter name="End" type="Array(double)" value="{100.0, 0.0, 0.0}"/><Parameter name="Elements" type="int" value="10"/>)X" +
                                      beam + R"X(</ParameterList>
    <ParameterList name="upper"><Parameter name="Start" type="Array(double)" value="{45.0, -50.0, 3.0}"/>
      <Parameter name="End" type="Array(double)" value="{45.0, 50.0, 3.0}"/><Parameter name="Elements" type="int" value="11"/>)X" +
                                      beam + R"X(</ParameterList></ParameterList>
  <ParameterList name="Supports">
    <ParameterList name="a"><Parameter name="Beam" type="string" value="lower"/><Parameter name="Node" type="string" value="start"/></ParameterList>
    <ParameterList name="b"><Parameter name="Beam" type="string" value="lower"/><Parameter name="Node" type="string" value="end"/></ParameterList>
    <ParameterList name="c"><Parameter name="Beam" type="string" value="upper"/><Parameter name="Node" type="string" value="start"/>)X" +
                                      end + R"X(</ParameterList>
    <ParameterList name="d"><Parameter name="Beam" type="string" value="upper"/><Parameter name="Node" type="string" value="end"/>)X" +
                                      end + R"X(</ParameterList></ParameterList>
  <ParameterList name="Contact"><ParameterList name="Pairs"><ParameterList name="crossing">
      <Parameter name="Beam A" type="string" value="lower"/><Parameter name="Beam B" type="string" value="upper"/>
      <Parameter name="Friction Coefficient" type="double" value="0.0"/></ParameterList></ParameterList>
    <ParameterList name="Enforcement"><Parameter name="Type" type="string" value=")X" +
                                      type + R"X("/>
      <ParameterList name="Penalty"><Parameter name="Normal Penalty Parameter" type="double" value=")X" +
                                      test::num(epsN) + R"X("/>
        <Parameter name="Tangential Penalty Parameter" type="double" value="10.0"/></ParameterList>
      <ParameterList name="Augmented Lagrange"><Parameter name="Normal Penalty Parameter" type="double" value="100.0"/>
        <Parameter name="Tangential Penalty Parameter" type="double" value="10.0"/></ParameterList></ParameterList></ParameterList>
  <ParameterList name="Load Stepping"><Parameter name="Number of Increments" type="int" value=")X" +
                                      std::to_string(increments) + R"X("/></ParameterList>
</ParameterList>)X",
                                  "pushed-through deck");
}
}  // namespace

TEST(PassThrough, TwoIncrementsGiveTheAnswerOfTwenty) {
  // Before: 2 increments ended "complete" with no contact force (20 increments: N = 70.3).
  for (const std::string type : {"Penalty", "Lagrange Multiplier", "Augmented Lagrange"}) {
    double N[2];
    int i = 0;
    for (int increments : {2, 20}) {
      auto p = input::buildProblem(pushedThrough(type, increments, 100.0), "push");
      const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "push");
      ASSERT_TRUE(r.report.completed) << type << ", " << increments << " increments: " << r.report.failure;
      const auto c = sums(p);
      EXPECT_EQ(c.active, 1) << type << ", " << increments << " increments";
      N[i++] = c.normal;
    }
    std::printf("%s: N = %.10f in 2 increments, %.10f in 20\n", type.c_str(), N[0], N[1]);
    EXPECT_GT(N[1], 1.0);
    EXPECT_NEAR(N[0], N[1], 1e-6 * N[1]) << type;
  }
}

TEST(PassThrough, DeepPenaltyPenetrationIsLegal) {
  // eps_N = 20: the equilibrium penetration exceeds r_A + r_B = 1 (the axes have crossed). Before it
  // was reported as "passed through each other". Penalty law: N = eps_N |g_N|.
  const double eps = 20.0;
  auto p = input::buildProblem(pushedThrough("Penalty", 20, eps), "deep");
  const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "deep");
  ASSERT_TRUE(r.report.completed) << r.report.failure;
  const auto c = sums(p);
  std::printf("deep penetration: N = %.9f, penetration %.9f (r_A + r_B = 1), eps_N penetration %.9f\n", c.normal,
              c.maxPenetration, eps * c.maxPenetration);
  EXPECT_EQ(c.active, 1);
  EXPECT_GT(c.maxPenetration, 1.0);
  EXPECT_NEAR(c.normal, eps * c.maxPenetration, 1e-9 * c.normal);
  // A legal state of the penalty law, but not contact: the run says so (more than 5 % of the
  // thinner section's inscribed radius).
  ASSERT_EQ(r.report.warnings.size(), 1u);
  EXPECT_NE(r.report.warnings[0].find("penetrated each other by up to"), std::string::npos) << r.report.warnings[0];
  EXPECT_NE(r.report.warnings[0].find("raise the Normal Penalty Parameter"), std::string::npos);
}

TEST(PassThrough, UnheldCrossingFailsTheIncrementAndIsNeverAResult) {
  // With the search margin at zero and the pair never found (a contact pair between beams far apart
  // at every iterate cannot cross unseen): here the check itself, on a state where "upper" lies
  // below "lower" with no contact point: the manager must refuse to accept it.
  auto p = input::buildProblem(pushedThrough("Penalty", 2, 100.0), "unheld");
  core::State s = p.model.initial;
  for (int n : p.beams->beams()[1].nodes) s.applyNodeIncrement(n, std::array<double, 6>{0, 0, -5.0, 0, 0, 0}.data());
  // The points as the search sees them from the initial state (none near): accepting must throw.
  EXPECT_THROW(p.contact->acceptSolution(s), std::runtime_error);
}

// Example 1, frictionless, in one increment with 60 Newton iterations allowed: beam 2's ends carried
// 40 along beam 1 and 20 down. Newton found the state with beam 2 below beam 1 (the motion's end, no
// contact), and the pass-through check compared only the element pairs where the axes' closest
// points lay at both ends of the increment: the crossing had moved from x = 50 to x = 90 along beam
// 1, and no element pair saw it; the run ended "complete" with no contact force. The check now
// follows the nodes' straight paths in steps of a quarter element, the increment is cut, and the
// run gives the contact force of 50 increments (Lagrange: 920.87 against 920.21, the frictionless
// problem's equilibria along the way; docs/contact.md).
TEST(PassThrough, Example1InOneIncrementIsCutWhereBeamTwoCrossedBeamOneAlongItsLength) {
  double N[2] = {0.0, 0.0};
  int i = 0;
  for (int increments : {1, 50}) {
    Deck d = example1("Lagrange Multiplier", "40.0, 0.0, -20.0", increments, 1e4, 400.0, 0.0);
    input::setAtPath(d, "Nonlinear Solver/Maximum Iterations", 60);
    auto p = input::buildProblem(d, "through");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "through");
    ASSERT_TRUE(r.report.completed) << increments << " increments: " << r.report.failure;
    const auto c = sums(p);
    EXPECT_EQ(c.active, 2) << increments << " increments";
    N[i++] = c.normal;
  }
  std::printf("Example 1 frictionless, Lagrange: N = %.6f in 1 increment, %.6f in 50\n", N[0], N[1]);
  EXPECT_NEAR(N[0], N[1], 2e-3 * N[1]);
}

// Example 1, frictionless, 20 elements per beam, Penalty on 5 increments: the first increment's
// Newton path carried beam 2 7.5 into beam 1 (three times its section's inscribed radius), where the
// points kept their normals and held it with a force of 6e5 (907 with 10 increments); "complete",
// warned. A point that acts and went deeper within an increment than the thinner section's
// inscribed radius now fails the increment, which is cut.
TEST(PassThrough, PenaltyCarriedDeepWithinAnIncrementIsCut) {
  double N[2] = {0.0, 0.0}, deepest[2] = {0.0, 0.0};
  int i = 0;
  for (int increments : {5, 10}) {
    Deck d = example1("Penalty", "40.0, 0.0, -20.0", increments, 1e4, 400.0, 0.0);
    for (const char* beam : {"Beams/beam 1/Elements", "Beams/beam 2/Elements"}) input::replaceAtPath(d, beam, 20);
    auto p = input::buildProblem(d, "deep");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "deep");
    ASSERT_TRUE(r.report.completed) << increments << " increments: " << r.report.failure;
    const auto c = sums(p);
    N[i] = c.normal;
    deepest[i++] = c.maxPenetration;
  }
  std::printf(
      "Example 1 frictionless, 20 elements, Penalty: N = %.6f (deepest %.3e) in 5 increments, %.6f (%.3e) in 10\n",
      N[0], deepest[0], N[1], deepest[1]);
  EXPECT_LT(deepest[0], 0.05 * 2.5);  // within the penetration warning's 5 % of beam 2's half width
  EXPECT_NEAR(N[0], N[1], 1e-2 * N[1]);
}

// Overlaps no contact point can see must never end "complete". The pushed-through deck with "upper"
// moved (a) parallel above "lower", with line contact switched off (Line Contact Angle 0; before:
// the run completed with the beams 13 inside each other and no force; with line contact every
// strategy sees it) and (b) short of "lower", its end 0.2 beside lower's axis, pushed down past it (the
// closest points of the two lines lie beyond upper's end: end contact, which completes). (a) stops
// with the cause; the same overlaps present at the start refuse the deck.
TEST(UnseenContact, ParallelBeamsAndBeamEndsStopTheRunWithTheCause) {
  using Array = Teuchos::Array<double>;
  struct Case {
    const char* name;
    std::vector<double> start, end;
    const char* cause;
    const char* strategy;
  };
  // Parallel circular beams are in line contact unless it is switched off (LineContact tests).
  const std::vector<Case> cases = {
      {"parallel", {0.0, 0.0, 3.0}, {100.0, 0.0, 3.0}, "nearly parallel", "Lagrange Multiplier"},
      {"end", {45.0, -50.0, 3.0}, {45.0, -0.2, 3.0}, "", "Lagrange Multiplier"}};
  for (const auto& c : cases) {
    auto deck = pushedThrough(c.strategy, 20, 100.0);
    input::replaceAtPath(deck, "Beams/upper/Start", Array(c.start));
    input::replaceAtPath(deck, "Beams/upper/End", Array(c.end));
    for (const char* support : {"Supports/c/Fixed", "Supports/d/Fixed"})
      input::replaceAtPath(deck, support, std::string("all"));
    input::setAtPath(deck, "Contact/Line Contact Angle", 0.0);
    input::setAtPath(deck, "Contact/Point Contact Angle", 15.0);
    auto p = input::buildProblem(deck, c.name);
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), c.name);
    std::printf("%s: completed %d, T reached %.4f: %s\n", c.name, r.report.completed, r.report.lastT,
                r.report.failure.c_str());
    const bool end = std::string(c.name) == "end";
    if (end) {
      // (b) is end contact now: upper's end face meets lower's top with its rim (0.2 short of lower's
      // axis), the contact's normal tilts it off lower, and it passes down beside lower without
      // overlapping it (the end point's gap, present while the end faces lower, not negative)
      EXPECT_TRUE(r.report.completed) << r.report.failure;
      int ends = 0;
      for (const auto& [key, pt] : p.contact->points())
        if (key.end()) {
          ++ends;
          EXPECT_GT(pt.gap, -1e-6);
        }
      std::printf("end: %d end points at the end\n", ends);
    } else {
      EXPECT_FALSE(r.report.completed) << c.name;
      EXPECT_NE(r.report.failure.find(c.cause), std::string::npos) << r.report.failure;
      // The beams touch when upper has come down by 2 of its 16: the last converged state is before that.
      EXPECT_LT(r.report.lastT, 2.0 / 16.0 + 1e-9) << c.name;
    }
    Array s(c.start), e(c.end);
    s[2] = e[2] = 0.5;
    input::replaceAtPath(deck, "Beams/upper/Start", s);
    input::replaceAtPath(deck, "Beams/upper/End", e);
    try {
      input::buildProblem(deck, c.name);
      ADD_FAILURE() << c.name << ": overlapping beams at the start were accepted";
    } catch (const core::InputError& error) {
      EXPECT_NE(std::string(error.what()).find(end ? "overlap at the start" : c.cause), std::string::npos)
          << error.what();
    }
  }
}

TEST(Nodes, CircularExample1CompletesWithEachStrategyAndLaw) {
  // The crossing of Example 1 with circular sections lies on a node of each beam (x = 50 on beam 1,
  // beam 2's centre node). Before: every strategy stopped at T = 0.025.
  for (const std::string law : {"Per Line", "Isotropic Coulomb"}) {
    std::map<std::string, std::array<double, 3>> got;
    for (const std::string type : {"Penalty", "Lagrange Multiplier", "Augmented Lagrange"}) {
      auto p = input::buildProblem(withLaw(circles(type, 0.0, 1e4, "40.0, 0.0, -20.0", 50, 0.5), law), "circ_e1");
      const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "circ_e1");
      ASSERT_TRUE(r.report.completed) << law << ", " << type << ": " << r.report.failure;
      const auto A = r.finalState.displacement(p.beams->beams()[0].nodes.back());
      const auto c = sums(p);
      std::printf("circular Example 1, %s, %s: A (%.6f, %.6f)  N %.4f  steps %d  Newton %d\n", law.c_str(),
                  type.c_str(), A[0], A[2], c.normal, r.report.steps, r.report.newtonIterations);
      got[type] = {A[0], A[2], c.normal};
    }
    // Augmented and plain Lagrange: 1e-6 apart with Per Line; 1.5e-4 in A's x with Isotropic Coulomb
    // (both within their stopping tests: augmentation stops at |g| <= 1e-6 with the slip direction
    // of the last pass, the complementarity rows settle it within Newton), asserted at 5e-4.
    const auto& l = got["Lagrange Multiplier"];
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(got["Augmented Lagrange"][k], l[k], (law == "Per Line" ? 1e-4 : 5e-4) * std::abs(l[k]))
          << law << " quantity " << k;
      EXPECT_NEAR(got["Penalty"][k], l[k], 0.01 * std::abs(l[k])) << law << " quantity " << k;  // eps_N = 1e4
    }
  }
}

TEST(Nodes, Example1WithTwentyElementsAndIsotropicFrictionCompletes) {
  // 20 elements per beam put beam 2's nodes at y = +-5, under beam 1's edges: all four points sit
  // on nodes. Before: the Lagrange active set cycled at T = 0.025. Lagrange and augmented Lagrange
  // must then agree (1e-4: the augmented gap tolerance is 1e-6).
  std::map<std::string, double> Auz;
  for (const std::string type : {"Lagrange Multiplier", "Augmented Lagrange"}) {
    Deck deck = withLaw(example1(type, "40.0, 0.0, -20.0", 200), "Isotropic Coulomb");
    for (const char* beam : {"Beams/beam 1/Elements", "Beams/beam 2/Elements"}) input::replaceAtPath(deck, beam, 20);
    auto p = input::buildProblem(deck, "e1_20");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "e1_20");
    ASSERT_TRUE(r.report.completed) << type << ": " << r.report.failure;
    Auz[type] = r.finalState.displacement(p.beams->beams()[0].nodes.back())[2];
    std::printf("Example 1, 20 elements, isotropic, %s: A uz %.6f, Newton %d\n", type.c_str(), Auz[type],
                r.report.newtonIterations);
  }
  EXPECT_NEAR(Auz["Augmented Lagrange"], Auz["Lagrange Multiplier"], 1e-4 * std::abs(Auz["Lagrange Multiplier"]));
}

// The contact search (bounding boxes hashed into a uniform grid) finds exactly the element pairs a
// brute-force test of every pair of elements finds: random straight fibres (10, 40, 120 of them, 3 to 6
// elements each, in a cube of side 10, All Pairs, Search Margin 0.3), at the start and after random
// nodal displacements of up to 0.5 (the boxes swept from the start to there). The brute force builds
// the same boxes: each element's nodes at both states, inflated by its radius and the margin.
TEST(Search, FindsTheElementPairsABruteForceSearchFinds) {
  std::mt19937 g(41);
  std::uniform_real_distribution<double> u(0.0, 10.0), d(-0.5, 0.5);
  std::uniform_int_distribution<int> elements(3, 6);
  for (int fibres : {10, 40, 120}) {
    Deck deck("BeamContact");
    for (int f = 0; f < fibres; ++f) {
      Teuchos::ParameterList& b = deck.sublist("Beams").sublist("fibre " + std::to_string(f));
      b.set("Start", Teuchos::Array<double>(std::vector<double>{u(g), u(g), u(g)}));
      b.set("End", Teuchos::Array<double>(std::vector<double>{u(g), u(g), u(g)}));
      b.set("Elements", elements(g));
      b.sublist("Section").set("Shape", std::string("Circle"));
      b.sublist("Section").set("Radius", 0.02);
      b.sublist("Material").set("Young's Modulus", 1e5);
      b.sublist("Material").set("Poisson's Ratio", 0.3);
      support(deck, "fibre " + std::to_string(f), 0, "all");
    }
    Teuchos::ParameterList& c = deck.sublist("Contact");
    c.set("All Pairs", true);
    c.set("Friction Coefficient", 0.0);
    c.set("Search Margin", 0.3);
    c.set("Allow Initial Penetration", true);
    c.sublist("Enforcement").set("Type", std::string("Penalty"));
    c.sublist("Enforcement").sublist("Penalty").set("Normal Penalty Parameter", 1e4);
    c.sublist("Enforcement").sublist("Penalty").set("Tangential Penalty Parameter", 1e3);
    const auto p = input::buildProblem(deck, "search");
    const core::State& start = p.model.initial;
    core::State moved = start;
    for (int n = 0; n < moved.numNodes(); ++n) {
      const double du[6] = {d(g), d(g), d(g), 0.0, 0.0, 0.0};
      moved.applyNodeIncrement(n, du);
    }
    const auto& elems = p.beams->elements();
    std::map<std::pair<int, int>, int> pairOf;
    for (std::size_t i = 0; i < p.contact->pairs().size(); ++i)
      pairOf[{p.contact->pairs()[i].beamA, p.contact->pairs()[i].beamB}] = static_cast<int>(i);
    for (const core::State* s : std::vector<const core::State*>{&start, &moved}) {
      const auto box = [&](int e, int k, bool high) {
        const auto& el = elems[e];
        const double reach = 0.02 + 0.3;
        const double values[4] = {s->position[el.node1][k], s->position[el.node2][k], start.position[el.node1][k],
                                  start.position[el.node2][k]};
        return high ? *std::max_element(values, values + 4) + reach : *std::min_element(values, values + 4) - reach;
      };
      std::vector<std::tuple<int, int, int>> brute;
      for (int a = 0; a < (int)elems.size(); ++a)
        for (int b = 0; b < (int)elems.size(); ++b) {
          const auto pi = pairOf.find({elems[a].beam, elems[b].beam});
          if (pi == pairOf.end()) continue;
          bool overlap = true;
          for (int k = 0; k < 3; ++k)
            overlap = overlap && box(a, k, false) <= box(b, k, true) && box(b, k, false) <= box(a, k, true);
          if (overlap) brute.emplace_back(pi->second, a, b);
        }
      std::sort(brute.begin(), brute.end());
      const auto found = p.contact->candidates(*s);
      std::printf("%3d fibres, %3zu elements, %s: %zu candidate element pairs, brute force %zu\n", fibres, elems.size(),
                  s == &start ? "at the start" : "moved", found.size(), brute.size());
      EXPECT_GT(brute.size(), 0u);
      EXPECT_EQ(found, brute);
    }
  }
}
