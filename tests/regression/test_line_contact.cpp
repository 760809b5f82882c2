// Line contact of parallel and nearly parallel beams: penalty tractions per unit length, the
// elastic-foundation closed form, the Lagrange multiplier field, friction along the axes, rectangular
// sections face to face and at small angles.
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

namespace {
// A uniform load of q per length in -z on a straight beam of n elements along x (length 100):
// its consistent nodal loads, forces q h (half at the ends) and, at the two ends, the moments of the
// cubic shape functions, M_y = +q h^2 / 12 at the start and -q h^2 / 12 at the end (interior ones
// cancel). Line contact's axes are the beams' cubic curves, so the contact traction also acts on the
// nodal rotations; with lumped forces alone the two beams of a stacked pair are loaded differently
// at the ends.
void uniformLoad(Teuchos::ParameterList& deck, const std::string& beam, int n, double q) {
  const double h = 100.0 / n;
  for (int i = 0; i <= n; ++i) {
    Teuchos::ParameterList& load = deck.sublist("Loads").sublist(beam + " q " + std::to_string(i));
    load.set("Beam", beam);
    load.set("Node", std::to_string(i));
    const double P = q * h * (i == 0 || i == n ? 0.5 : 1.0);
    const double M = i == 0 ? q * h * h / 12 : (i == n ? -q * h * h / 12 : 0.0);
    load.set("Force", Teuchos::Array<double>(std::vector<double>{0.0, 0.0, -P}));
    load.set("Moment", Teuchos::Array<double>(std::vector<double>{0.0, M, 0.0}));
  }
}

// Two parallel rods lying on each other (parallelBeams: circles r 0.5, n elements each, 6 Gauss
// points) with friction mu, the rod or the ground as A, Penalty's and Augmented Lagrange's eps_T.
Teuchos::ParameterList rodsWithFriction(const std::string& type, int n, double E, double mu, bool rodIsA, double epsT) {
  auto deck = parallelBeams(type, n, n, 0.0, E, 6);
  if (rodIsA) {
    input::replaceAtPath(deck, "Contact/Pairs/line/Beam A", std::string("rod"));
    input::replaceAtPath(deck, "Contact/Pairs/line/Beam B", std::string("ground"));
  }
  input::replaceAtPath(deck, "Contact/Pairs/line/Friction Coefficient", mu);
  for (const char* s : {"Penalty", "Augmented Lagrange"})
    input::replaceAtPath(deck, std::string("Contact/Enforcement/") + s + "/Tangential Penalty Parameter", epsT);
  return deck;
}

// Two cantilevers stacked (parallelBeams: circles r 0.5, E 1e5, n elements each, `gauss` Gauss points),
// both clamped at x = 0, the rod's tip pressed down by P, 4 increments.
Teuchos::ParameterList stackedCantilevers(const std::string& type, int n, int gauss, double P) {
  auto deck = parallelBeams(type, n, n, 0.0, 1e5, gauss);
  support(deck, "ground", 0, "all");
  support(deck, "rod", 0, "all");
  Teuchos::ParameterList& load = deck.sublist("Loads").sublist("tip");
  load.set("Beam", std::string("rod"));
  load.set("Node", std::string("end"));
  load.set("Force", Teuchos::Array<double>(std::vector<double>{0.0, 0.0, -P}));
  input::replaceAtPath(deck, "Load Stepping/Number of Increments", 4);
  return deck;
}

struct LineSums {
  int points = 0, active = 0;
  double total = 0.0, gapMin = 1e300, gapMax = -1e300;
  double friction = 0.0;  // x components of the active points' tangential forces on beam B
  int slipping = 0;  // active points slipping along the axes
};
LineSums lineSums(const input::Problem& p) {
  LineSums s;
  for (const auto& [key, q] : p.contact->points()) {
    if (q.node()) continue;  // (a line node of a multiplier field)
    EXPECT_TRUE(q.line()) << "a point contact between parallel circular beams";
    ++s.points;
    if (!q.result.active) continue;
    ++s.active;
    s.total += -q.result.lambdaN;
    s.gapMin = std::min(s.gapMin, q.gap);
    s.gapMax = std::max(s.gapMax, q.gap);
    s.friction += q.tangentialForce[0];
    s.slipping += q.result.slip[1];
  }
  return s;
}
}  // namespace

// A rigid punch: every node of both beams held, the rod's moved down by d = 1e-4. Every Gauss point
// penetrates by d, the traction is eps_N d per unit length (the penalty acts per unit length of line
// A), and on matching meshes the forces sum to eps_N d L = 100 exactly. With the rod shifted by 3 and
// 7 elements, the ground's elements are cut into segments at the rod's nodes and at its end, so the
// Gauss points integrate the constant traction over the overlap exactly: eps_N d 97 with any rule
// (without segments, Gauss points whose projection fell beyond the rod's end dropped out, and the
// sum only approached 97 as the rule was refined).
TEST(LineContact, RigidPunchGivesThePenaltyTractionPerUnitLength) {
  auto deck = parallelBeams("Penalty", 10, 10, 0.0, 1e5, 6);
  for (int i = 0; i <= 10; ++i) {
    support(deck, "ground", i, "all");
    support(deck, "rod", i, "all", -1e-4);
  }
  // With friction on the pair (circles: along and across the axes; no warning).
  input::replaceAtPath(deck, "Contact/Pairs/line/Friction Coefficient", 0.3);
  auto p = input::buildProblem(deck, "punch");
  const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "punch");
  ASSERT_TRUE(r.report.completed) << r.report.failure;
  EXPECT_TRUE(r.report.warnings.empty()) << r.report.warnings[0];
  const auto s = lineSums(p);
  std::printf("matching meshes: %d Gauss points active of %d, total %.12f (eps_N d L = 100), gaps %.12e .. %.12e\n",
              s.active, s.points, s.total, s.gapMin, s.gapMax);
  EXPECT_EQ(s.active, 60);
  EXPECT_NEAR(s.total, 100.0, 1e-9 * 100.0);
  // contact_points.csv: each Gauss point's line traction is eps_N d = 1 per unit length, its segment
  // (element_A, element_B) the matching elements, and its normal_penalty the deck's eps_N.
  const auto split = [](const std::string& line) {
    std::vector<std::string> cells;
    std::stringstream in(line);
    for (std::string cell; std::getline(in, cell, ',');) cells.push_back(cell);
    return cells;
  };
  const auto names = split(p.contact->tableHeader());
  const auto column = [&](const std::string& name) {
    const auto it = std::find(names.begin(), names.end(), name);
    EXPECT_NE(it, names.end()) << name;
    return static_cast<std::size_t>(it - names.begin());
  };
  const std::size_t traction = column("line_traction"), eA = column("element_A"), eB = column("element_B"),
                    penalty = column("normal_penalty");
  for (const auto& row : p.contact->tableRows()) {
    const auto cells = split(row);
    ASSERT_EQ(cells.size(), names.size()) << row;
    EXPECT_NEAR(std::stod(cells[traction]), 1.0, 1e-9) << row;
    EXPECT_EQ(cells[eA], cells[eB]) << row;
    EXPECT_EQ(std::stod(cells[penalty]),
              input::sublistAtPath(deck, "Contact/Enforcement/Penalty").get<double>("Normal Penalty Parameter"))
        << row;
  }
  // A line point keeps its side: the rod moved on down by 1.2 has its axis 0.2 below the ground's,
  // and every point's gap is -(0.2 + 1e-4) - (r_A + r_B) = -1.2001 (not +0.2001 - 1 = -0.7999), in
  // the kinematics (whose side comes from the double-precision geometry).
  {
    core::State moved = r.finalState;
    for (int n : p.beams->beams()[1].nodes)
      moved.applyNodeIncrement(n, std::array<double, 6>{0, 0, -1.2, 0, 0, 0}.data());
    for (const auto& [key, q] : p.contact->points()) {
      if (!q.line()) continue;
      const auto k = p.contact->kinematics(q, moved);
      EXPECT_NEAR(k.normal.value, -1.2001, 1e-9);
      // Raising the rod opens it: d g / d u_z of B's two nodes sum to +1 (the shape functions' sum).
      EXPECT_NEAR(k.normal.R[12 + 2] + k.normal.R[18 + 2], 1.0, 1e-9);
    }
  }
  EXPECT_NEAR(s.gapMin, -1e-4, 1e-9 * 1e-4);
  EXPECT_NEAR(s.gapMax, -1e-4, 1e-9 * 1e-4);
  for (int gauss : {2, 6, 16}) {
    auto shifted = parallelBeams("Penalty", 10, 7, 3.0, 1e5, gauss);
    for (int i = 0; i <= 10; ++i) support(shifted, "ground", i, "all");
    for (int i = 0; i <= 7; ++i) support(shifted, "rod", i, "all", -1e-4);
    auto q = input::buildProblem(shifted, "punch_shifted");
    const auto rq = test::runQuiet(q, Tpetra::getDefaultComm(), "punch_shifted");
    ASSERT_TRUE(rq.report.completed) << rq.report.failure;
    const double total = lineSums(q).total, error = std::abs(total - 97.0) / 97.0;
    std::printf("rod shifted by 3, %2d Gauss points per element: total %.9f (eps_N d 97 = 97), error %.2e\n", gauss,
                total, error);
    EXPECT_LT(error, 1e-10);
  }
}

// Two identical pinned beams (E = 1e9, so rotations stay near 1e-4) in contact along their length,
// the rod loaded by q = 0.01 per length (consistent nodal loads, uniformLoad; small, because the closed
// form is linear: with q = 1 the geometric nonlinearity, e.g. the vertical offset of two tilted
// axes, moves the result by 2e-4 of it). The penetration
// d = w_rod - w_ground obeys EI d'''' + 2 eps_N d = q with d = d'' = 0 at the pinned ends (the sum of
// the two deflections carries q like one beam; Hetenyi's beam on an elastic foundation of modulus
// 2 eps_N): from the centre, d = q / k + A cosh(b x) cos(b x) + B sinh(b x) sin(b x), k = 2 eps_N,
// b = (k / (4 EI))^(1/4), B = A sh s / (ch c), A = -(q / k) ch c / (ch^2 c^2 + sh^2 s^2) at x = l = 50,
// and the contact force eps_N int d = eps_N [2 l q / k + A (sh c + ch s) / b + B (ch s - sh c) / b].
// The penalty result converges to it with elements (about fourth order: 3.8e-4, 2.6e-5, 3.3e-7 with 10,
// 20, 40 elements; with 80 it stays at 2e-6, the geometric nonlinearity at this load).
TEST(LineContact, ParallelPinnedBeamsMatchTheElasticFoundationClosedForm) {
  const double E = 1e9, eps = 1e4, q = 0.01, l = 50.0, pi = std::acos(-1.0);
  const double EI = E * pi * std::pow(0.5, 4) / 4, k = 2 * eps, b = std::pow(k / (4 * EI), 0.25);
  const double ch = std::cosh(b * l), sh = std::sinh(b * l), c = std::cos(b * l), sn = std::sin(b * l);
  const double A = -(q / k) * ch * c / (ch * ch * c * c + sh * sh * sn * sn), B = A * sh * sn / (ch * c);
  const double exact = eps * (2 * l * q / k + A * (sh * c + ch * sn) / b + B * (ch * sn - sh * c) / b);
  auto pinnedDeck = [&](const std::string& type, int n) {
    auto deck = parallelBeams(type, n, n, 0.0, E, 6);
    for (const char* beam : {"ground", "rod"}) {
      support(deck, beam, 0, "ux uy uz rx");
      support(deck, beam, n, "uy uz rx");
    }
    uniformLoad(deck, "rod", n, q);
    return deck;
  };
  double previous = 1e300;
  for (int n : {10, 20, 40}) {
    auto p = input::buildProblem(pinnedDeck("Penalty", n), "foundation");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "foundation");
    ASSERT_TRUE(r.report.completed) << n << ": " << r.report.failure;
    const double total = lineSums(p).total, error = std::abs(total - exact) / exact;
    std::printf("penalty, %2d elements: contact force %.9f, closed form %.9f, relative error %.2e\n", n, total, exact,
                error);
    EXPECT_LT(error, previous);
    previous = error;
  }
  EXPECT_LT(previous, 1e-5);
  // Augmented Lagrange's multipliers on lines are Lagrange's field regularized by their estimates,
  // augmented until the field's weighted gaps are within Gap Tolerance: it converges to Lagrange's
  // solution, which carries more than the penalty's softer contact. How close: a weighted gap g left
  // over moves the force by about the beams' stiffness to the smooth mode, (pi / L)^4 EI / 2 per
  // unit length and gap (the two beams in series), times L: with Gap Tolerance 1e-8, 2.4e-5 (4.8e-5
  // of the total). The passes do not grow with the mesh (each contracts every mode by the Normal
  // Target Error, 1e-3: 3 to 6 passes).
  double penaltyTotal = 0.0, lagrangeTotal = 0.0;
  const double tolerance = 1e-8, smooth = std::pow(pi / (2 * l), 4) * EI / 2 * (2 * l) * tolerance;
  for (const std::string type : {"Penalty", "Lagrange Multiplier", "Augmented Lagrange"}) {
    auto deck = pinnedDeck(type, 40);
    input::setAtPath(deck, "Contact/Enforcement/Augmented Lagrange/Gap Tolerance", tolerance);
    auto p = input::buildProblem(deck, "foundation_al");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "foundation_al");
    ASSERT_TRUE(r.report.completed) << r.report.failure;
    const auto s = lineSums(p);
    std::printf("%s, 40 elements: contact force %.9f, gaps %.2e .. %.2e, %d Newton iterations\n", type.c_str(), s.total,
                s.gapMin, s.gapMax, r.report.newtonIterations);
    if (type == "Penalty") {
      penaltyTotal = s.total;
      continue;
    }
    EXPECT_GT(s.total, penaltyTotal);
    if (type == "Lagrange Multiplier") {
      lagrangeTotal = s.total;
      continue;
    }
    EXPECT_NEAR(s.total, lagrangeTotal, smooth);
  }
}

// Penalty with its springs on the line's nodes (Line Springs = Nodes): node a's traction is
// Lambda_a = eps_N g_a, g_a the gap weighted by its hat over what B covers of its elements (the row
// int N_a (g_N - Lambda_a / eps_N) ds = 0, the compliance lumped on the node). A rigid punch (every
// node held, the rod's moved down by d = 1e-4) penetrates by d everywhere: every node's traction is
// eps_N d = 1 per unit length, the forces sum to eps_N d L = 100, and each Gauss point's gap is -d.
// On the pinned beams of the elastic foundation above, the springs on the nodes are a foundation of
// modulus eps_N lumped on the nodes: the contact force converges to the closed form at second order
// as the elements are refined (measured 1.63e-2, 5.45e-3, 1.55e-3; springs at every Gauss point
// converge faster here, at fourth order). The contact tangent (the nodes' rows among them) against
// central differences of the residual on a rod shifted along the ground, frictionless and sticking.
TEST(LineContact, PenaltySpringsOnTheLineNodesGiveThePenaltyTractionAndTheFoundation) {
  {
    auto deck = parallelBeams("Penalty", 10, 10, 0.0, 1e5, 6);
    input::setAtPath(deck, "Contact/Enforcement/Penalty/Line Springs", std::string("Nodes"));
    for (int i = 0; i <= 10; ++i) {
      support(deck, "ground", i, "all");
      support(deck, "rod", i, "all", -1e-4);
    }
    auto p = input::buildProblem(deck, "punch_nodes");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "punch_nodes");
    ASSERT_TRUE(r.report.completed) << r.report.failure;
    EXPECT_TRUE(r.report.warnings.empty()) << r.report.warnings.front();
    const auto s = lineSums(p);
    int nodes = 0;
    double lowest = 1e300, highest = -1e300;
    for (const auto& [key, q] : p.contact->points()) {
      if (!q.node()) continue;
      ++nodes;
      lowest = std::min(lowest, -q.result.lambdaN);
      highest = std::max(highest, -q.result.lambdaN);
    }
    std::printf(
        "punch, springs on the nodes: %d nodes, tractions %.12f .. %.12f (eps_N d = 1), total %.12f (100), "
        "gaps %.12e .. %.12e\n",
        nodes, lowest, highest, s.total, s.gapMin, s.gapMax);
    EXPECT_EQ(nodes, 11);  // (the ends keep their nodes where the supports hold both beams)
    EXPECT_NEAR(lowest, 1.0, 1e-9);
    EXPECT_NEAR(highest, 1.0, 1e-9);
    EXPECT_NEAR(s.total, 100.0, 1e-9 * 100.0);
    EXPECT_NEAR(s.gapMin, -1e-4, 1e-9 * 1e-4);
    EXPECT_NEAR(s.gapMax, -1e-4, 1e-9 * 1e-4);
  }
  const double E = 1e9, eps = 1e4, q = 0.01, l = 50.0, pi = std::acos(-1.0);
  const double EI = E * pi * std::pow(0.5, 4) / 4, k = 2 * eps, b = std::pow(k / (4 * EI), 0.25);
  const double ch = std::cosh(b * l), sh = std::sinh(b * l), c = std::cos(b * l), sn = std::sin(b * l);
  const double A = -(q / k) * ch * c / (ch * ch * c * c + sh * sh * sn * sn), B = A * sh * sn / (ch * c);
  const double exact = eps * (2 * l * q / k + A * (sh * c + ch * sn) / b + B * (ch * sn - sh * c) / b);
  double previous = 1e300;
  for (int n : {10, 20, 40}) {
    auto deck = parallelBeams("Penalty", n, n, 0.0, E, 6);
    input::setAtPath(deck, "Contact/Enforcement/Penalty/Line Springs", std::string("Nodes"));
    for (const char* beam : {"ground", "rod"}) {
      support(deck, beam, 0, "ux uy uz rx");
      support(deck, beam, n, "uy uz rx");
    }
    uniformLoad(deck, "rod", n, q);
    auto p = input::buildProblem(deck, "foundation_nodes");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "foundation_nodes");
    ASSERT_TRUE(r.report.completed) << n << ": " << r.report.failure;
    const double total = lineSums(p).total, error = std::abs(total - exact) / exact;
    std::printf(
        "springs on the nodes, %2d elements: contact force %.9f, closed form %.9f, relative error %.2e, %d "
        "Newton iterations\n",
        n, total, exact, error, r.report.newtonIterations);
    EXPECT_LT(error, previous / 2.5);
    previous = error;
  }
  EXPECT_LT(previous, 2e-3);
  // The tangent: the rod (7 elements) shifted by 3 along the ground (10), so that its ends lie inside
  // the ground's elements (where both beams' ends meet, the segment's bounds switch between them
  // under a perturbation: no derivative there, for any strategy), each pinned at its ends, the rod
  // under q.
  // Frictionless, and with a friction coefficient of 10: every node sticks (the tangential springs' rows
  // int N_a (g_T - (Lambda_T - Lambda_T,n) / eps_T) ds), its trial force well inside the cone. (With
  // 0.3 a stick-slip front crosses the field, where the cone's projection has no derivative; slipping
  // nodes are checked in LineCone's drag.) The Per Line law is refused with springs on the nodes (its
  // nodes' rigid stick and slip kept them at the cone: 50 times the friction of the springs).
  for (const std::string law : {"", "Isotropic Coulomb", "Per Line"}) {
    auto deck = parallelBeams("Penalty", 10, 7, 3.0, E, 6);
    input::setAtPath(deck, "Contact/Enforcement/Penalty/Line Springs", std::string("Nodes"));
    if (!law.empty()) {
      input::replaceAtPath(deck, "Contact/Pairs/line/Friction Coefficient", 10.0);
      input::setAtPath(deck, "Contact/Friction Law", law);
    }
    support(deck, "ground", 0, "ux uy uz rx");
    support(deck, "ground", 10, "uy uz rx");
    support(deck, "rod", 0, "ux uy uz rx");
    support(deck, "rod", 7, "uy uz rx");
    uniformLoad(deck, "rod", 7, q);
    if (law == "Per Line") {
      // Refused with the pair declared, and with All Pairs (the friction given for every pair).
      auto allPairs = deck;
      allPairs.sublist("Contact").remove("Pairs");
      allPairs.sublist("Contact").set("All Pairs", true);
      allPairs.sublist("Contact").set("Friction Coefficient", 10.0);
      for (const auto& d : {deck, allPairs}) {
        try {
          input::buildProblem(d, "foundation_nodes_shifted");
          ADD_FAILURE() << "Per Line friction with springs on the nodes was not refused";
        } catch (const core::InputError& e) {
          std::printf("Per Line: %s\n", e.what());
          EXPECT_NE(std::string(e.what()).find("Isotropic Coulomb"), std::string::npos) << e.what();
        }
      }
      continue;
    }
    auto p = input::buildProblem(deck, "foundation_nodes_shifted");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "foundation_nodes_shifted");
    ASSERT_TRUE(r.report.completed) << r.report.failure;
    int sticking = 0, active = 0;
    double friction = 0.0;
    for (const auto& [key, pt] : p.contact->points())
      if (pt.node() && pt.result.active) {
        ++active;
        sticking += !pt.result.slip[0];
        friction = std::max(friction, std::abs(pt.result.lambdaT[0]) + std::abs(pt.result.lambdaT[1]));
      }
    double kmax = 0.0;
    const double err = assembledContactTangentError(p, r.finalState, kmax);
    std::printf(
        "rod shifted by 3%s%s: contact force %.9f, %d of %d nodes sticking, largest friction multiplier "
        "%.3e; contact tangent vs central differences: max error / max |K| = %.2e\n",
        law.empty() ? "" : ", friction 10, ", law.c_str(), lineSums(p).total, sticking, active, friction, err / kmax);
    EXPECT_GT(kmax, 0.0);
    EXPECT_LT(err / kmax, 1e-6);
    if (!law.empty()) {
      EXPECT_EQ(sticking, active);
      EXPECT_GT(friction, 0.0);
    }
  }
}

// The stacked cantilevers of PenaltySpringsOverConstrainingStackedCantileversSayWhatHelps (clamped at
// x = 0, the rod's tip pressed by P = 0.05, 6 Gauss points, where springs at every Gauss point stop)
// with the springs on the nodes: complete. The beams lie on each other and the force gathers at the
// tips, which a linear traction over the end element holds at its two-thirds point (x = 96.7 on 10
// elements): the total is above Lagrange's tip force (exact constraints, which hold the tip's force
// at a point of the end) by an error that halves with the element (first order: the force's place),
// and the penetration the field leaves at the tip is warned (unresolved zone) while it exceeds 1e-3 of
// the radius.
TEST(LineContact, PenaltySpringsOnTheLineNodesCarryStackedCantileversAsTheyAreRefined) {
  const double P = 0.05;
  const auto run = [&](const std::string& type, int n, std::vector<std::string>& warnings) {
    auto deck = stackedCantilevers(type, n, 6, P);
    if (type == "Penalty") input::setAtPath(deck, "Contact/Enforcement/Penalty/Line Springs", std::string("Nodes"));
    auto p = input::buildProblem(deck, "stacked_nodes");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "stacked_nodes");
    EXPECT_TRUE(r.report.completed) << type << " " << n << ": " << r.report.failure;
    warnings = r.report.warnings;
    // Newton near the solution, with the springs on the nodes (expectQuadraticNewton).
    if (type == "Penalty" && n == 10 && r.report.completed)
      expectQuadraticNewton(p, r.finalState, "springs on the nodes, Newton from T = 1 to 1.02");
    return lineSums(p).total;
  };
  std::vector<std::string> warnings;
  const double lagrange = run("Lagrange Multiplier", 10, warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  double previous = 1e300;
  for (int n : {10, 20}) {
    const double total = run("Penalty", n, warnings), error = total / lagrange - 1.0;
    std::printf("springs on the nodes, %d elements: total %.9f, Lagrange Multiplier %.9f (%+.2e), %zu warnings\n", n,
                total, lagrange, error, warnings.size());
    EXPECT_GT(error, 0.0);
    EXPECT_LT(error, 0.6 * previous);
    previous = error;
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("Line Springs = Gauss Points"), std::string::npos) << warnings[0];
  }
}

// Two identical rods pinned at the same x, the upper loaded by q: each carries q / 2 and both end
// slopes are theta = (q / 2) L^3 / (24 E I). The slope turns the contact normal, so the supports hold
// the gap at the ends at -2 r (1 - cos theta) = -r theta^2 (to O(theta^4)), a penetration a rigid line
// constraint cannot remove: closing it within an element of length h takes tractions of about
// E I r theta^2 / h^4, a share of q that grows as h^-4 (measured: the total force +0.07, +0.55, +3.5 %
// with 10, 20, 40 elements at q = 1, and 0.04 % with 40 at q = 0.01, linear in q as the estimate
// says). Lagrange Multiplier warns where that share exceeds 1 % of the field's mean traction, with
// the gap; not at 10 elements, not at q = 0.01, and Penalty (which takes the gap as eps_N |g|, 1e-3
// of q) never.
TEST(LineContact, AGapThatSupportsHoldAtBothBeamsEndsIsReportedWhenRigidContactCannotCloseIt) {
  const double E = 1e9, L = 100.0, r = 0.5, pi = std::acos(-1.0), EI = E * pi * std::pow(r, 4) / 4;
  auto run = [&](const std::string& type, int n, double q, std::string& warning) {
    auto deck = parallelBeams(type, n, n, 0.0, E, 6);
    for (const char* beam : {"ground", "rod"}) {
      support(deck, beam, 0, "ux uy uz rx");
      support(deck, beam, n, "uy uz rx");
    }
    uniformLoad(deck, "rod", n, q);
    input::replaceAtPath(deck, "Load Stepping/Number of Increments", 2);
    auto p = input::buildProblem(deck, "held_ends");
    const auto result = test::runQuiet(p, Tpetra::getDefaultComm(), "held_ends");
    EXPECT_TRUE(result.report.completed) << result.report.failure;
    warning.clear();
    int held = 0;
    for (const auto& w : result.report.warnings)
      if (w.find("supports hold both beams") != std::string::npos) {
        warning = w;
        ++held;
      }
    EXPECT_LE(held, 1);
    const double total = lineSums(p).total;
    std::printf("%s, %d elements, q = %g: total %.6f (q L / 2 %+.3f %%)%s\n", type.c_str(), n, q, total,
                100 * (total / (0.5 * q * L) - 1), held ? ", held-end warning" : "");
  };
  std::string w;
  run("Lagrange Multiplier", 10, 1.0, w);
  EXPECT_TRUE(w.empty()) << w;
  run("Lagrange Multiplier", 40, 0.01, w);
  EXPECT_TRUE(w.empty()) << w;
  run("Penalty", 40, 1.0, w);
  EXPECT_TRUE(w.empty()) << w;
  run("Lagrange Multiplier", 40, 1.0, w);
  ASSERT_FALSE(w.empty());
  EXPECT_NE(w.find("contact pair \"line\""), std::string::npos) << w;
  EXPECT_NE(w.find("hold only one of the two beams there, or use Penalty"), std::string::npos) << w;
  const double theta = 0.5 * L * L * L / (24 * EI), expected = -r * theta * theta;
  const auto at = w.find("the gap they hold there is ");
  ASSERT_NE(at, std::string::npos) << w;
  const double gap = std::stod(w.substr(at + std::string("the gap they hold there is ").size()));
  std::printf("held gap %.4e, closed form -r theta^2 = %.4e\n", gap, expected);
  EXPECT_NEAR(gap, expected, 0.02 * std::abs(expected));
}

// The same held ends with soft beams (E = 1e5, q = 0.01, 10 elements: end slopes of 0.04 for circles),
// where the held gap's force is not small: it goes from one beam's supports into the other's, and the
// contact force is the strategy's and the mesh's, not the beams' (whose exact share is q L / 2, each
// beam carrying q / 2). Every strategy that completes warns, naming the force on A's end element
// beyond the line's mean traction:
// - circles, Penalty (eps_N 1e4): the total was 5.5 q L / 2, "complete" without a word;
// - 2 x 1 rectangles with the rod turned by 0.08 degrees (point contact and end contact at the
//   rectangles' corners share the held ends with the line), Penalty: 4.3 times q L / 2; Lagrange
//   multipliers: the end points carried 1771 times the load q L. An end point within line contact's
//   angles now gives way to the multiplier field (docs/contact.md, "End contact"): the total is
//   q L / 2 within 5 % (measured +2.1 %: the held gaps' force), and the warning stays (the held gap's
//   force on the end element grows as h^-4 with refinement). The rod's twist is free at its far end
//   there: along these crossing edges the bounding line passes from one beam's edge to the other's
//   near mid-span on each side, each a multiplier field of its own, and with both beams' twists held
//   at both ends the two fields' rows over-constrain the relative twist: the run stops on a singular
//   matrix naming dependent constraints (tested; before, no line carried about a third of each side
//   and the run completed resting on one line there).
TEST(LineContact, HeldEndsWarnWithEveryStrategyWhereTheirForceGoesIntoTheSupports) {
  const double q = 0.01, L = 100.0;
  struct Case {
    std::string type;
    bool rectangles;
    double degrees;
    bool excess;  // the held ends' force makes the total more than q L
  };
  for (const Case& c : {Case{"Penalty", false, 0.0, true}, Case{"Lagrange Multiplier", true, 0.08, false},
                        Case{"Penalty", true, 0.08, true}}) {
    auto deck = parallelBeams(c.type, 10, 10, 0.0, 1e5, 6, c.degrees);
    if (c.rectangles) deck = toRectangles(deck);
    const bool twistFree = c.type == "Lagrange Multiplier";
    for (const char* beam : {"ground", "rod"}) {
      support(deck, beam, 0, "ux uy uz rx");
      support(deck, beam, 10, twistFree && std::string(beam) == "rod" ? "uy uz" : "uy uz rx");
    }
    uniformLoad(deck, "rod", 10, q);
    input::replaceAtPath(deck, "Load Stepping/Number of Increments", 10);
    if (twistFree) {
      auto held = deck;
      support(held, "rod", 10, "uy uz rx");
      input::setAtPath(held, "Load Stepping/Maximum Step Cuts", 0);  // (singular at every step size)
      auto p = input::buildProblem(held, "held_twists");
      const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "held_twists");
      EXPECT_FALSE(r.report.completed);
      EXPECT_NE(r.report.failure.find("dependent constraints"), std::string::npos) << r.report.failure;
    }
    auto p = input::buildProblem(deck, "held_soft_ends");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "held_soft_ends");
    ASSERT_TRUE(r.report.completed) << c.type << ": " << r.report.failure;
    double total = 0.0;
    for (const auto& [key, pt] : p.contact->points())
      if (!pt.node() && pt.result.active) total += std::abs(pt.result.lambdaN);
    std::string warning;
    for (const auto& w : r.report.warnings)
      if (w.find("supports hold both beams") != std::string::npos) warning = w;
    std::printf("%s, %s at %g degrees: total contact force %.6g (q L / 2 = %g)\n  %s\n", c.type.c_str(),
                c.rectangles ? "rectangles" : "circles", c.degrees, total, 0.5 * q * L, warning.c_str());
    if (c.excess) EXPECT_GT(total, 2.0 * 0.5 * q * L) << c.type;  // the held ends' force, why the warning is needed
    else EXPECT_NEAR(total, 0.5 * q * L, 0.05 * 0.5 * q * L) << c.type;
    EXPECT_NE(warning.find("end element there carry"), std::string::npos) << c.type << ": " << warning;
    EXPECT_NE(warning.find("hold only one of the two beams there"), std::string::npos) << warning;
  }
}

// Lagrange multipliers on a line (a mortar field on the nodes of line A, linear between them,
// constant on the end elements). Two identical cantilevers (E = 1e9, clamped at x = 0), the rod
// lying on the ground and loaded by q per length: with the contact exact, both deflect alike, so
// each carries q / 2 and the traction is q / 2 everywhere (total q L / 2; the rod's load consistent,
// with end moments). The field holds it on matching meshes, and on non-matching ones without growing
// oscillation as the mesh is refined. At q = 0.01 the geometric nonlinearity is small (the traction's
// deviation from q / 2 scales with q); at q = 1 it shows at the clamp (printed). A penalty of 1e8
// acting per Gauss point (as stiff as the exact constraint, but one constraint per Gauss point: more
// than the beams' dofs there) oscillates along the whole line (printed for comparison).
TEST(LineContact, LagrangeMultiplierFieldCarriesHalfTheLoadOfStackedCantilevers) {
  auto cantilevers = [&](const std::string& type, int nGround, int nRod, double q) {
    auto deck = parallelBeams(type, nGround, nRod, 0.0, 1e9, 6);
    support(deck, "ground", 0, "all");
    support(deck, "rod", 0, "all");
    uniformLoad(deck, "rod", nRod, q);
    input::replaceAtPath(deck, "Load Stepping/Number of Increments", 2);
    return deck;
  };
  // The traction at each active Gauss point (its force over the length it stands for) against q / 2.
  // The points at the free tips (A's end nodes keep their multipliers there: no supports) are point
  // forces, in the total but not among the tractions; exact contact puts none there.
  struct Traction {
    double total = 0.0, worst = 0.0, tip = 0.0;
    int active = 0;
  };
  auto traction = [](const input::Problem& p, double q) {
    Traction t;
    for (const auto& [key, pt] : p.contact->points()) {
      if (!pt.line() || !pt.result.active) continue;
      t.total += -pt.result.lambdaN;
      if (constraints::LineContact::endPoint(pt)) {
        t.tip = std::max(t.tip, std::abs(pt.result.lambdaN));
        continue;
      }
      ++t.active;
      t.worst = std::max(t.worst, std::abs(-pt.result.lambdaN / pt.length - 0.5 * q) / (0.5 * q));
    }
    return t;
  };
  // Refinement sequences: matching meshes, the rod coarser (7 : 10), the rod finer (13 : 10).
  const std::vector<std::vector<std::pair<int, int>>> sequences = {
      {{10, 10}, {20, 20}, {40, 40}}, {{10, 7}, {20, 14}, {40, 28}}, {{10, 13}, {20, 26}}};
  for (const auto& sequence : sequences) {
    double previousError = 1e300, firstWorst = 0.0, previousTip = 1e300;
    for (const auto& [nGround, nRod] : sequence) {
      const double q = 0.01;
      auto p = input::buildProblem(cantilevers("Lagrange Multiplier", nGround, nRod, q), "lm_line");
      const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "lm_line");
      ASSERT_TRUE(r.report.completed) << r.report.failure;
      const Traction t = traction(p, q);
      const double error = std::abs(t.total - 50 * q) / (50 * q);
      std::printf(
          "Lagrange, ground %d / rod %d elements, q = %g: total %.9f (q L / 2 = %.3f, error %.1e), traction "
          "within %.1e of q / 2 at %d Gauss points, tip's point force %.1e\n",
          nGround, nRod, q, t.total, 50 * q, error, t.worst, t.active, t.tip);
      // Six Gauss points on each segment: the rod's elements cut by the planes of the ground's
      // nodes. Where the two meshes' nodes line up in the reference, the planes (normal to the
      // ground's turned axis) cut the rod's axis, 2 r above, 2 r theta beside its node: every
      // interior node of the ground makes a segment.
      EXPECT_EQ(t.active, 6 * (nGround + nRod - 1));
      if (nGround == nRod) {
        // The same interpolation on both beams: the uniform traction is the discrete solution.
        EXPECT_LT(error, 1e-5);
        EXPECT_LT(t.worst, 1e-4);
        EXPECT_LT(t.tip, 1e-9);
        continue;
      }
      // Different meshes interpolate the same deflection differently by O(q h^4 / EI); the exact
      // constraint turns that into a traction perturbation of fixed relative size near the clamp
      // (where the curvature is largest), decaying along the beam. It must not grow with refinement
      // (an unstable multiplier field would), and the total converges (first order: the clamp's
      // element).
      if (firstWorst == 0.0) firstWorst = t.worst;
      EXPECT_LT(t.worst, 1.05 * firstWorst);
      EXPECT_LT(t.worst, 0.1);
      EXPECT_LT(error, 0.6 * previousError);
      previousError = error;
      // (The tip's point force, 0 in exact contact, falls with the element length.)
      EXPECT_LE(t.tip, 0.6 * previousTip);
      previousTip = t.tip;
    }
  }
  for (int n : {10, 20, 40}) {
    auto p = input::buildProblem(cantilevers("Lagrange Multiplier", n, n, 1.0), "lm_line_q1");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "lm_line_q1");
    ASSERT_TRUE(r.report.completed) << r.report.failure;
    const Traction t = traction(p, 1.0);
    std::printf(
        "Lagrange, %d elements, q = 1: total %.6f, largest deviation of the traction from q / 2: %.1e (at the "
        "clamp)\n",
        n, t.total, t.worst);
    EXPECT_NEAR(t.total, 50.0, 1e-3 * 50.0);
    EXPECT_LT(t.worst, 1e-2);
  }
  {
    auto deck = cantilevers("Penalty", 40, 40, 0.01);
    input::replaceAtPath(deck, "Contact/Enforcement/Penalty/Normal Penalty Parameter", 1e8);
    auto p = input::buildProblem(deck, "stiff_penalty_line");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "stiff_penalty_line");
    ASSERT_TRUE(r.report.completed) << r.report.failure;
    const Traction t = traction(p, 0.01);
    std::printf(
        "Penalty 1e8 per Gauss point, 40 elements, q = 0.01: total %.6f, largest deviation of the traction "
        "from q / 2: %.1e\n",
        t.total, t.worst);
  }
}

// Friction along the axes of a line contact: a rigid punch that slides. Both beams are held at every
// node, the rod pressed 1e-4 into the ground (eps_N 1e4 per unit length: N = 1 per length, 100 in
// total) and slid along the axes by delta, pair friction mu = 0.3, eps_T = 1e3 per unit length. Sliding
// by 0.01 (beyond the elastic slip mu N' / eps_T = 3e-4) the friction force is mu N = 30, with each
// friction law; sliding by 1e-5 the rod sticks and the force is eps_T delta L = 1. (A prescribed
// penetration is a penalty's case: Augmented Lagrange cannot close it. Its line friction is the same
// law at each Gauss point, checked by the tangent test below.)
TEST(LineContact, FrictionAlongTheAxesReachesMuN) {
  for (const std::string law : {"Per Line", "Isotropic Coulomb"})
    for (const std::string type : {"Penalty"})
      for (const double delta : {0.01, 1e-5}) {
        auto deck = parallelBeams(type, 10, 10, 0.0, 1e5, 6);
        input::setAtPath(deck, "Contact/Friction Law", law);
        input::replaceAtPath(deck, "Contact/Pairs/line/Friction Coefficient", 0.3);
        input::replaceAtPath(deck, "Load Stepping/Number of Increments", 2);
        for (int i = 0; i <= 10; ++i) {
          support(deck, "ground", i, "all");
          Teuchos::ParameterList& s = deck.sublist("Supports").sublist("slide " + std::to_string(i));
          s.set("Beam", std::string("rod"));
          s.set("Node", std::to_string(i));
          s.set("Fixed", std::string("all"));
          s.set("Displacement", Teuchos::Array<double>(std::vector<double>{delta, 0.0, -1e-4}));
        }
        auto p = input::buildProblem(deck, "line_friction");
        const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "line_friction");
        ASSERT_TRUE(r.report.completed) << r.report.failure;
        const LineSums sums = lineSums(p);
        const double normal = sums.total, friction = sums.friction;
        const int slipping = sums.slipping, active = sums.active;
        std::printf("%s, %s, slide %g: N = %.9f, friction force %.9f (mu N = %.9f), %d of %d points slipping\n",
                    type.c_str(), law.c_str(), delta, normal, friction, 0.3 * normal, slipping, active);
        // The rod slid by delta overlaps the ground on 100 - delta (the segments end at its end).
        const double length = 100.0 - delta;
        EXPECT_NEAR(normal, length, 1e-9 * 100.0);
        if (delta > 1e-3) {
          EXPECT_EQ(slipping, active);
          EXPECT_NEAR(std::abs(friction), 0.3 * normal, 1e-9 * normal);
        } else {
          EXPECT_EQ(slipping, 0);
          EXPECT_NEAR(std::abs(friction), 1e3 * delta * length, 1e-9);
        }
        // The rod slides in +x: the ground pulls it back, so the force on the rod points in -x.
        EXPECT_LT(friction, 0.0);
      }
}

// Friction along the axes with every strategy: a rod lying on a held ground, loaded by q = 0.01 per
// length, its clamped ends slid along the axes by 0.05 (far beyond the elastic slip mu q / eps_T =
// 3e-6 of a penalty), pair friction 0.3: every line point slides, and the friction force on the rod
// is mu times its normal force (1e-8), with each friction law; Lagrange multipliers through the
// field's friction rows. (The rod starts touching, so Penalty's first Newton step, without contact
// stiffness, drops it 0.5 through the ground. Before the line gap kept its side, the points then saw
// the rod beyond the ground's axis as a positive gap growing again, and the run ended "complete"
// with N = 1956 instead of 0.93.)
TEST(LineContact, FrictionAlongTheAxesWithEveryStrategy) {
  for (const std::string law : {"Per Line", "Isotropic Coulomb"})
    for (const std::string type : {"Penalty", "Augmented Lagrange", "Lagrange Multiplier"}) {
      auto deck = parallelBeams(type, 10, 10, 0.0, 1e5, 6);
      input::setAtPath(deck, "Contact/Friction Law", law);
      input::replaceAtPath(deck, "Contact/Pairs/line/Friction Coefficient", 0.3);
      input::replaceAtPath(deck, "Load Stepping/Number of Increments", 2);
      if (type != "Lagrange Multiplier")
        input::setAtPath(deck, "Contact/Enforcement/" + type + "/Regularization Gap", 1e-6);
      for (int i = 0; i <= 10; ++i) support(deck, "ground", i, "all");
      for (int i = 0; i <= 10; ++i) {
        Teuchos::ParameterList& s = deck.sublist("Supports").sublist("rod " + std::to_string(i));
        s.set("Beam", std::string("rod"));
        s.set("Node", std::to_string(i));
        s.set("Fixed", std::string(i == 0 || i == 10 ? "all" : "uy"));
        s.set("Displacement", Teuchos::Array<double>(std::vector<double>{i == 0 || i == 10 ? 0.05 : 0.0, 0.0, 0.0}));
      }
      uniformLoad(deck, "rod", 10, 0.01);
      auto p = input::buildProblem(deck, "line_friction_all");
      const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "line_friction_all");
      ASSERT_TRUE(r.report.completed) << type << ", " << law << ": " << r.report.failure;
      const LineSums sums = lineSums(p);
      const double normal = sums.total, friction = sums.friction;
      const int slipping = sums.slipping, active = sums.active;
      std::printf("%s, %s: N = %.9f, friction force %.9f (mu N = %.9f), %d of %d points slipping\n", type.c_str(),
                  law.c_str(), normal, friction, 0.3 * normal, slipping, active);
      EXPECT_GT(active, 30);
      EXPECT_EQ(slipping, active);
      EXPECT_NEAR(-friction, 0.3 * normal, 1e-8 * normal);
    }
}

namespace {
// The crossing of the angle sweep on parallelBeams (ground 20 elements, rod 12, lifted 0.1): both
// clamped at their ends, the rod's ends pressed down by 0.12 (closure 0.02) in 10 increments, every
// inner node held sideways (two beams at a small angle pressed together otherwise roll apart).
void pressCrossing(Teuchos::ParameterList& deck) {
  input::replaceAtPath(deck, "Load Stepping/Number of Increments", 10);
  support(deck, "ground", 0, "all");
  support(deck, "ground", 20, "all");
  support(deck, "rod", 0, "all", -0.12);
  support(deck, "rod", 12, "all", -0.12);
  for (int i = 1; i < 20; ++i) support(deck, "ground", i, "uy");
  for (int i = 1; i < 12; ++i) support(deck, "rod", i, "uy");
}

Teuchos::ParameterList parallelRectangles(const std::string& type, int ground, int rod, double E, int gauss,
                                          double lift) {
  return toRectangles(parallelBeams(type, ground, rod, 0.0, E, gauss, 0.0, lift));
}
}  // namespace

// Line contact sees the gap at its Gauss points only. Two clamped beams crossing at 8 degrees, line
// contact forced (Line Contact Angle 9, Point Contact Angle 10), pressed together by a closure of
// 0.02: with 2 Gauss points per element the contact zone around the crossing falls between them
// (force 53 % low in bench_line_contact), and the run must say so; with 8 (error 1e-3) it must not.
TEST(LineContact, OverlapBetweenGaussPointsIsReported) {
  for (const int gauss : {2, 8}) {
    auto deck = parallelBeams("Penalty", 20, 12, 0.0, 1e5, gauss, 8.0, 0.1);
    input::setAtPath(deck, "Contact/Line Contact Angle", 9.0);
    input::setAtPath(deck, "Contact/Point Contact Angle", 10.0);
    input::setAtPath(deck, "Contact/Enforcement/Penalty/Regularization Gap", 1e-3);
    pressCrossing(deck);
    auto p = input::buildProblem(deck, "between_gauss");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "between_gauss");
    ASSERT_TRUE(r.report.completed) << r.report.failure;
    const bool warned = std::any_of(r.report.warnings.begin(), r.report.warnings.end(), [](const std::string& w) {
      return w.find("between the Gauss points of line contact") != std::string::npos;
    });
    std::printf("%d Gauss points: %s\n", gauss, warned ? "overlap between them reported" : "no warning");
    EXPECT_EQ(warned, gauss == 2);
  }
}

// Rectangular sections crossing at small angles: point contact of their edges down to Parallel Line
// Tolerance, face contact (line contact) only below it. The beams of the test above, with 2 x 1
// sections, crossing at 12, 8 and 4 degrees, pressed together, Penalty: every crossing completes with
// point contact. (At 1 degree the rod's held ends lie on the ground's: the next test.) (With the circles' blend angles,
// 5 and 15 degrees, the crossings at 4 .. 12 degrees failed at first contact when the face contact saw A's edges on B's
// face only, not B's edges on A's face. Exactly parallel, this loading still fails at first contact, T = 0.85:
// docs/contact.md.)
TEST(LineContact, RectanglesCrossingAtSmallAnglesComplete) {
  for (const double degrees : {12.0, 8.0, 4.0}) {
    auto deck = toRectangles(parallelBeams("Penalty", 20, 12, 0.0, 1e5, 6, degrees, 0.1));
    pressCrossing(deck);
    auto p = input::buildProblem(deck, "rectangles_crossing");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "rectangles_crossing");
    ASSERT_TRUE(r.report.completed) << degrees << " degrees: " << r.report.failure;
    int points = 0, lines = 0;
    double total = 0.0;
    for (const auto& [key, q] : p.contact->points()) {
      if (q.node() || !q.result.active) continue;
      (q.line() ? lines : points)++;
      total += -q.result.lambdaN;
    }
    std::printf("rectangles crossing at %4.1f degrees: %d point contacts, %d line points, normal force %.6f\n", degrees,
                points, lines, total);
    EXPECT_GT(total, 0.0);
    EXPECT_EQ(lines, 0);
    EXPECT_GT(points, 0);
  }
}

// Rectangles crossing at 1 degree are in point contact (above Parallel Line Tolerance), whose points
// sit where the edges cross; faces lying on each other along the beams elsewhere are not seen, and a
// run must not end "complete" with them overlapping:
// - the crossing above, pressed at the rod's clamped ends, which at 1 degree lie on the ground's
//   clamped ends (held together and pressed into each other by 0.02): the run stops naming the faces'
//   overlap (it ended "complete" with the rod's ends in the ground);
// - two pinned 2 x 1 beams at 1 degree, the upper under q = 0.01 (consistent loads), Lagrange: in
//   point contact the run stops the same way (it ended "complete" with 0.3195, 37 % below the line
//   contact it is); forced into line contact (Parallel Line Tolerance sin 2 degrees) it completes with
//   a total within 1 % of q L / 2, the closed form at 0 degrees (two identical pinned beams deflect
//   alike, each carrying q / 2; measured 0.4 % below at 1 degree), and at 2 degrees it completes
//   (the faces in contact chosen as those the sections' separating axes give: the direction between
//   the axes picked the side faces there and refused the deck for an overlap at the start).
TEST(LineContact, RectanglesFaceOnFaceAtOneDegreeAreSeenOrStopTheRun) {
  const auto facesOverlap = [](const std::string& failure) {
    return failure.find("whose faces overlap by") != std::string::npos;
  };
  {
    auto deck = toRectangles(parallelBeams("Penalty", 20, 12, 0.0, 1e5, 6, 1.0, 0.1));
    pressCrossing(deck);
    auto p = input::buildProblem(deck, "rectangles_one_degree");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "rectangles_one_degree");
    EXPECT_FALSE(r.report.completed);
    EXPECT_TRUE(facesOverlap(r.report.failure)) << r.report.failure;
  }
  const double q = 0.01;
  const auto pinned = [&](double degrees, double parallel) {
    auto deck = toRectangles(parallelBeams("Lagrange Multiplier", 10, 10, 0.0, 1e5, 6, degrees));
    for (const char* beam : {"ground", "rod"}) {
      support(deck, beam, 0, "ux uy uz rx");
      support(deck, beam, 10, "uy uz rx");
    }
    uniformLoad(deck, "rod", 10, q);
    input::replaceAtPath(deck, "Load Stepping/Number of Increments", 10);
    if (parallel > 0.0) input::setAtPath(deck, "Contact/Parallel Line Tolerance", parallel);
    auto p = input::buildProblem(deck, "pinned_rectangles");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "pinned_rectangles");
    double total = 0.0;
    for (const auto& [key, pt] : p.contact->points())
      if (!pt.node() && pt.result.active) total += -pt.result.lambdaN;
    return std::make_pair(r, total);
  };
  const auto [point, unused] = pinned(1.0, 0.0);
  (void)unused;
  EXPECT_FALSE(point.report.completed);
  EXPECT_TRUE(facesOverlap(point.report.failure)) << point.report.failure;
  const double lines = std::sin(2.0 * std::acos(-1.0) / 180.0);
  const auto [one, total] = pinned(1.0, lines);
  ASSERT_TRUE(one.report.completed) << one.report.failure;
  std::printf("pinned rectangles at 1 degree in line contact: total %.6f (q L / 2 = %.6f at 0 degrees)\n", total,
              q * 50.0);
  EXPECT_NEAR(total, q * 50.0, 0.01 * q * 50.0);
  const auto [two, totalTwo] = pinned(2.0, lines);
  EXPECT_TRUE(two.report.completed) << two.report.failure;
  std::printf("pinned rectangles at 2 degrees in line contact: total %.6f\n", totalTwo);
  // Stiff beams (E = 1e9, q = 1: 3.9e-3 deflection at mid-span), Penalty (eps_N 1e9) with 20 elements, at 0.5 and
  // 1 degree: the faces come 2e-4 inside each other at the quarter points, so the run must stop (it
  // ended "complete" with 5 q L / 16, the single central point's answer, 37 % below q L / 2, while the
  // test took overlaps below 1e-3 of the inscribed radius for none).
  for (const double degrees : {0.5, 1.0}) {
    auto deck = toRectangles(parallelBeams("Penalty", 20, 20, 0.0, 1e9, 6, degrees));
    input::setAtPath(deck, "Contact/Enforcement/Penalty/Normal Penalty Parameter", 1e9);
    for (const char* beam : {"ground", "rod"}) {
      support(deck, beam, 0, "ux uy uz rx");
      support(deck, beam, 20, "uy uz rx");
    }
    uniformLoad(deck, "rod", 20, 1.0);
    input::replaceAtPath(deck, "Load Stepping/Number of Increments", 2);
    auto p = input::buildProblem(deck, "stiff_rectangles");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "stiff_rectangles");
    EXPECT_FALSE(r.report.completed) << degrees << " degrees";
    EXPECT_TRUE(facesOverlap(r.report.failure)) << degrees << " degrees: " << r.report.failure;
  }
}

// Rectangular sections lying face to face are in line contact on the two edges of A's upper face
// against B's lower face. The ground (20 elements) pinned at its ends, the rod (16 elements) on it,
// pushed down by 0.01 at its middle node (held there, the rest of it free: a double cantilever that
// bends onto the ground from 0.002 above it), both held against sideways motion; their twist is held
// by the ground's end supports, the rod's middle one and the contact of the two edges. Every
// strategy: the contact forces sum to the rod's support reaction (equilibrium, 1e-6) and the two
// edges carry equal shares (the section is symmetric, 1e-6).
TEST(LineContact, RectanglesFaceToFaceCarryTheLoadOnBothEdges) {
  for (const std::string type : {"Penalty", "Lagrange Multiplier", "Augmented Lagrange"}) {
    auto deck = parallelRectangles(type, 20, 16, 1e5, 6, 0.002);
    // (The faces come down on each other along a length at once: the penalty laws' C1 onset.)
    if (type != "Lagrange Multiplier")
      input::setAtPath(deck, "Contact/Enforcement/" + type + "/Regularization Gap", 1e-4);
    input::replaceAtPath(deck, "Load Stepping/Number of Increments", 2);
    support(deck, "ground", 0, "ux uy uz rx");
    support(deck, "ground", 20, "uy uz rx");
    for (int i = 1; i < 20; ++i) support(deck, "ground", i, "uy rz");
    for (int i = 0; i <= 16; ++i) support(deck, "rod", i, i == 8 ? "all" : "uy rz", i == 8 ? -0.01 : 0.0);
    auto p = input::buildProblem(deck, "rectangles");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "rectangles");
    ASSERT_TRUE(r.report.completed) << type << ": " << r.report.failure;
    double edge[4] = {0, 0, 0, 0}, total = 0.0;
    int active = 0;
    for (const auto& [key, q] : p.contact->points()) {
      if (!q.result.active || q.node()) continue;
      ASSERT_TRUE(q.line()) << "a point contact between parallel rectangles";
      ++active;
      edge[q.edge()] += -q.result.lambdaN;
      total += -q.result.lambdaN;
    }
    // The force the rod's middle support exerts on it (z; reactions.csv, last step): the rod is
    // held by it and the contact alone, so the contact forces on the rod sum to minus it.
    const double rz = -lastReactions(test::scratchDirectory("rectangles_np1")).at("rod 8_Fz");
    std::printf("%s: %d line points active, edges %.9f + %.9f = %.9f, rod's reaction %.9f\n", type.c_str(), active,
                edge[0], edge[1], total, rz);
    EXPECT_GT(active, 8);
    EXPECT_NEAR(total, rz, 1e-6 * std::abs(rz));
    EXPECT_NEAR(edge[0], edge[1], 1e-6 * total);
    EXPECT_EQ(edge[2] + edge[3], 0.0);  // only the upper face's edges (0, 1) of the ground
  }
}

namespace {
// A narrow 5 x 5 beam on a wide 10 x 10 one (length 100, E 1e5, `n` elements each, 2 Gauss points),
// both along X: "wide" with its axis at z = 0, "narrow" on it (axis at z = 7.5, shifted across by
// `shift` along Y) or, with `degrees`, turned about Z at its centre. Beam A of the pair is the narrow
// one if `narrowIsA`, else the wide one; frictionless.
Teuchos::ParameterList narrowOnWide(const std::string& type, bool narrowIsA, int n, double shift = 0.0,
                                    double degrees = 0.0, double lift = 0.0) {
  auto deck = parallelBeams(type, n, n, 0.0, 1e5, 2, degrees, 0.0);
  for (const auto& [beam, size] : {std::make_pair("ground", 10.0), std::make_pair("rod", 5.0)}) {
    Teuchos::ParameterList& sec = deck.sublist("Beams").sublist(beam).sublist("Section");
    sec.remove("Radius");
    sec.set("Shape", std::string("Rectangle"));
    sec.set("Width", size);
    sec.set("Height", size);
  }
  for (const char* end : {"Start", "End"}) {
    auto x = deck.sublist("Beams").sublist("rod").get<Teuchos::Array<double>>(end);
    x[1] += shift;
    x[2] = 7.5 + lift;
    deck.sublist("Beams").sublist("rod").set(end, x);
  }
  if (narrowIsA) {
    input::replaceAtPath(deck, "Contact/Pairs/line/Beam A", std::string("rod"));
    input::replaceAtPath(deck, "Contact/Pairs/line/Beam B", std::string("ground"));
  }
  return deck;
}

// The z force of the active line points on the narrow beam (the rod) and on each bounding line
// ((roles swapped, edge) -> force); the active points with A's roles and with swapped ones.
struct NarrowSums {
  double onRod = 0.0, deepest = 0.0;
  std::map<std::pair<bool, int>, double> lines;
  int asA = 0, swapped = 0;
  double offEdge = 0.0;  // the largest distance of a reported position across from the narrow beam's edge (shift 0)
};
NarrowSums narrowSums(const input::Problem& p, bool narrowIsA) {
  NarrowSums s;
  const auto& elems = p.beams->elements();
  const int beamA = p.contact->pairs()[0].beamA;
  for (const auto& [key, q] : p.contact->points()) {
    if (q.node() || !q.result.active) continue;
    EXPECT_TRUE(q.line()) << "a point contact between parallel rectangles";
    const bool swapped = elems[q.elementA].beam != beamA;
    (swapped ? s.swapped : s.asA)++;
    // normalForce + tangentialForce: the force on the pair's beam B.
    const double fz = q.normalForce[2] + q.tangentialForce[2];
    s.onRod += narrowIsA ? -fz : fz;
    s.lines[{swapped, q.edge()}] += -q.result.lambdaN;
    s.deepest = std::max(s.deepest, -q.gap);
    s.offEdge = std::max(s.offEdge, std::abs(std::abs(q.position[1]) - 2.5));
  }
  return s;
}
}  // namespace

// Rectangles of different widths face to face (issue 32): the lines bounding the overlap of the two
// faces carry the contact, each an edge of A on B's face or an edge of B on A's face (roles
// swapped). Two cantilevers clamped at x = 0, the narrow 5 x 5 one lying on the wide 10 x 10 one and
// loaded by q = 0.01 (consistent loads). Centred, with exact contact both deflect alike, w'''' =
// (q - p) / EI_n = p / EI_w, and both clamped at the same place: the traction is uniform,
// p = q I_w / (I_w + I_n) = 16 q / 17 (I_w / I_n = (10 / 5)^4), total 16 q L / 17 on the narrow beam's
// two edges, half on each by symmetry. Penalty (eps_N per unit length of each line) gives the same
// uniform traction when the narrow beam's clamp is lowered by the penetration p / (2 eps_N) it
// causes. Lagrange and Augmented Lagrange (its field converges to Lagrange's) give p. With A the narrow
// beam its edges are A's, with A the wide one they are B's (swapped): the same Gauss points on the
// same segments, so the two runs agree to round-off. Offset by 5 across, the overlap runs from the
// narrow beam's edge (y = 2.5, inside the wide face) to the wide beam's edge (y = 5, inside the
// narrow face): one bounding line of each beam, either way round; the contact forces balance the
// narrow beam's load and clamp reaction (1e-8). Before, A wide on B narrow passed through with no
// force, and A narrow on B wide, offset, stopped.
TEST(LineContact, NarrowOnWideRectanglesCarryTheLoadEitherWayRound) {
  const int n = 5;
  const double q = 0.01, L = 100.0, p = 16.0 * q / 17.0, eps = 100.0;
  for (const double shift : {0.0, 5.0}) {
    for (const std::string type : {"Penalty", "Lagrange Multiplier", "Augmented Lagrange"}) {
      std::map<bool, std::pair<double, double>> results;  // narrowIsA -> (force on the rod, its tip deflection)
      for (const bool narrowIsA : {true, false}) {
        auto deck = narrowOnWide(type, narrowIsA, n, shift);
        input::setAtPath(deck, "Contact/Enforcement/Penalty/Normal Penalty Parameter", eps);
        // (Augmented Lagrange stops when the field's weighted gaps are within Gap Tolerance; near the
        // common clamp the beams are stiff, and gaps below 1e-8 there still leave 3.1e-5 of the force
        // off Lagrange's, 2.4e-8 below 1e-10.)
        if (type == "Augmented Lagrange")
          input::setAtPath(deck, "Contact/Enforcement/Augmented Lagrange/Gap Tolerance", 1e-10);
        support(deck, "ground", 0, "all");
        support(deck, "rod", 0, "all", type == "Penalty" && shift == 0.0 ? -p / (2 * eps) : 0.0);
        uniformLoad(deck, "rod", n, q);
        auto problem = input::buildProblem(deck, "narrow_on_wide");
        const auto r = test::runQuiet(problem, Tpetra::getDefaultComm(), "narrow_on_wide");
        ASSERT_TRUE(r.report.completed) << type << ", shift " << shift << ": " << r.report.failure;
        const NarrowSums s = narrowSums(problem, narrowIsA);
        const double reaction = lastReactions(test::scratchDirectory("narrow_on_wide_np1")).at("rod 0_Fz");
        const double tip = r.finalState.position[problem.beams->beams()[1].nodes.back()][2] - 7.5;
        results[narrowIsA] = {s.onRod, tip};
        std::printf(
            "%s, shift %g, A %s: %d points as A, %d swapped, force on the narrow beam %.10f (16 q L / 17 = %.10f), "
            "its clamp %.10f, deepest %.2e, tip %.9f\n",
            type.c_str(), shift, narrowIsA ? "narrow" : "wide", s.asA, s.swapped, s.onRod, p * L, reaction, s.deepest,
            tip);
        // Equilibrium of the narrow beam: load q L down, contact and clamp up.
        EXPECT_NEAR(s.onRod + reaction, q * L, 1e-8 * q * L);
        ASSERT_EQ(s.lines.size(), 2u);  // two bounding lines
        if (shift == 0.0) {
          // Both bounding lines are the narrow beam's edges: A's, or B's with the roles swapped.
          EXPECT_EQ(s.swapped > 0, !narrowIsA);
          EXPECT_EQ(s.asA > 0, narrowIsA);
          EXPECT_NEAR(s.lines.begin()->second, s.lines.rbegin()->second, 1e-6 * s.onRod);
          EXPECT_NEAR(s.onRod, p * L, 1e-6 * p * L);
          // Reported where they touch: on the narrow beam's edges, y = +-2.5 (the beams bend in z only).
          // Before, midway between the edge and the face's centre line: y = +-1.25.
          EXPECT_LT(s.offEdge, 1e-9) << type;
        } else {
          EXPECT_GT(s.swapped, 0);  // one line of each
          EXPECT_GT(s.asA, 0);
        }
      }
      EXPECT_NEAR(results[true].first, results[false].first, 1e-8 * std::abs(results[true].first));
      EXPECT_NEAR(results[true].second, results[false].second, 1e-8 * std::abs(results[true].second));
    }
  }
}

// Equal rectangles offset across (issue 32): two 5 x 5 cantilevers clamped at x = 0, one on the other,
// the upper one shifted across by `shift` and loaded by q = 0.01. On each side of the strip where the
// faces overlap, one beam's edge bounds it, inside the other's face by the shift: an edge of A on B's
// face or of B on A's (roles swapped). Both lines touch, so with the two beams alike the twist and the
// line forces are alike: the lines carry equal forces (the torques on the two beams, about their own
// axes, are equal only so). Aligned, the traction is q / 2 (total q L / 2, the narrow-on-wide closed
// form with I_w = I_n; measured -5e-5, the geometric nonlinearity, 10 times less at q / 10). Offset by
// s, the upper beam's face lies s phi lower than the lower's at the same twist phi, which couples
// bending to torsion over a length of about s (EI / 4 GJ)^(1/2) = 0.31 s at the clamp: measured
// +1.1e-4 and +3.3e-4 of q L / 2 at s = 0.025 and 0.075 with Lagrange multipliers (+5e-4, +1.5e-3 with
// Penalty). Before, an offset between 1e-3 and 5 % of the half width (0.0025 .. 0.125 here) left the
// side where A's edge lies beyond B's face and B's edge inside A's with no line at all: the upper beam
// lay on one line and twisted, "complete".
TEST(LineContact, EqualRectanglesOffsetAcrossCarryTheLoadOnBothBoundingLines) {
  const int n = 10;
  const double q = 0.01, L = 100.0, eps = 1e4, lift = 0.01;
  for (const double shift : {0.0, 0.025, 0.075})
    for (const std::string type : {"Lagrange Multiplier", "Augmented Lagrange", "Penalty"}) {
      std::map<bool, double> force;  // upper beam is A -> the force on it
      for (const bool upperIsA : {true, false}) {
        auto deck = narrowOnWide(type, upperIsA, n, shift);
        input::replaceAtPath(deck, "Beams/ground/Section/Width", 5.0);
        input::replaceAtPath(deck, "Beams/ground/Section/Height", 5.0);
        for (const char* end : {"Start", "End"}) {
          auto x = deck.sublist("Beams").sublist("rod").get<Teuchos::Array<double>>(end);
          x[2] = 5.0 + lift;
          deck.sublist("Beams").sublist("rod").set(end, x);
        }
        input::setAtPath(deck, "Contact/Enforcement/Penalty/Normal Penalty Parameter", eps);
        if (type == "Augmented Lagrange")
          input::setAtPath(deck, "Contact/Enforcement/Augmented Lagrange/Gap Tolerance", 1e-10);
        support(deck, "ground", 0, "all");
        // (The upper beam starts 0.01 above the lower one and its clamp is lowered onto it as the load
        // comes on; Penalty: by the penetration q / 4 / eps_N of each line more, as above.)
        support(deck, "rod", 0, "all", -lift - (type == "Penalty" ? q / (4 * eps) : 0.0));
        uniformLoad(deck, "rod", n, q);
        auto problem = input::buildProblem(deck, "offset_rectangles");
        const auto r = test::runQuiet(problem, Tpetra::getDefaultComm(), "offset_rectangles");
        ASSERT_TRUE(r.report.completed) << type << ", shift " << shift << ": " << r.report.failure;
        const NarrowSums s = narrowSums(problem, upperIsA);
        const double reaction = lastReactions(test::scratchDirectory("offset_rectangles_np1")).at("rod 0_Fz");
        std::printf("%s, shift %g, A the %s beam: %d points as A, %d swapped, lines", type.c_str(), shift,
                    upperIsA ? "upper" : "lower", s.asA, s.swapped);
        for (const auto& [line, f] : s.lines) std::printf(" %.9f", f);
        std::printf(", force on the upper beam %.10f (q L / 2 = %.10f), deepest %.2e\n", s.onRod, 0.5 * q * L,
                    s.deepest);
        force[upperIsA] = s.onRod;
        EXPECT_NEAR(s.onRod + reaction, q * L, 1e-8 * q * L);  // the upper beam's equilibrium
        ASSERT_EQ(s.lines.size(), 2u) << type << ", shift " << shift << ": both bounding lines carry";
        EXPECT_NEAR(s.lines.begin()->second, s.lines.rbegin()->second, 1e-6 * s.onRod) << type << ", shift " << shift;
        EXPECT_NEAR(s.onRod, 0.5 * q * L, (type == "Penalty" ? 2e-3 : 5e-4) * 0.5 * q * L)
            << type << ", shift " << shift;
        EXPECT_LT(s.deepest, 1e-6) << type << ", shift " << shift;
      }
      // (Offset, each way round has the same two lines: equal to round-off. Aligned, both lines are A's
      // edges, on the upper or the lower beam's segments: 8e-8 apart, measured.)
      EXPECT_NEAR(force[true], force[false], (shift > 0.0 ? 1e-9 : 1e-6) * q * L)
          << type << ", shift " << shift << ": either way round";
    }
}

// A 2 x 1 rod turned by 1 degree about its axis falling onto a held 2 x 1 ground (issue 32): the rod's
// ends held 0.1 above contact (uz, uy, rx; ux at its start), 10 elements each, loaded by q = 0.01, its
// lowest edge coming down on the ground's face. Where it lies on the ground its curvature is zero;
// each end part of length a is a beam with the end held g above the ground and clamped-like at the
// touchdown, so a = (24 E I g / q)^(1/4) and the contact carries q (L - a) (the ends q a / 2 each), I
// the rod's second moment about the horizontal, 1 / (sin^2 theta / I_z + cos^2 theta / I_y). The
// rod's lowest edge lies 0.9 % of the half width inside the ground's face, the ground's edge as far
// beyond the rod's face: with the ground as A no line carried before, and every strategy stopped at
// first contact naming the overlap. Now each completes within 1 % of q (L - a) (measured +0.007 to
// +0.12 %, 2 Gauss points), the same either way round (1e-4: Lagrange multipliers, each way; the others with the
// ground as A, whose lines the band missed). On 10 increments too (ground as A, every strategy): the
// increment to T = 0.9 cycles between active sets and is cut, and the retry lowered the field's
// refinement cap below the converged field's level, dropped its refined elements' points and force
// (first residual 0.55, the increment's load gives 0.07) and stopped with the rod through the ground
// near its held end (Lagrange multipliers and Augmented Lagrange); the retry now starts from the
// converged field (LineContact::clearLevels). On 20 elements and 5 increments (Lagrange multipliers,
// Augmented Lagrange) the next step's field dropped refined elements whose interior nodes carried
// force: the increment after T = 0.8 started with a residual of 0.41 (its load gives 0.044) and the
// run stopped there; such elements now keep their refinement (LineContact::resumeLevels). The rod
// lying flat on 10 elements and 10 increments (Lagrange multipliers): a retry capped at the converged
// field's level in an earlier step made the next step's first failure drop that level; that memory is
// now per step.
TEST(LineContact, RectangularRodTurnedAboutItsAxisFallsOnTheGroundEitherWayRound) {
  const double q = 0.01, L = 100.0, g = 0.1, E = 1e5;
  for (const std::string type : {"Lagrange Multiplier", "Augmented Lagrange", "Penalty"}) {
    std::map<bool, double> totals;
    // (elements, increments, turn in degrees)
    for (const auto& [n, increments, degrees] :
         {std::tuple{10, 4, 1.0}, std::tuple{10, 10, 1.0}, std::tuple{20, 5, 1.0}, std::tuple{10, 10, 0.0}})
      for (const bool groundIsA : {true, false}) {
        if (!groundIsA && (type != "Lagrange Multiplier" || increments != 4)) continue;
        if ((n == 20 || degrees == 0.0) && type == "Penalty") continue;
        if (degrees == 0.0 && type != "Lagrange Multiplier") continue;
        const double th = degrees * std::acos(-1.0) / 180.0, cs = std::cos(th), sn = std::sin(th);
        const double Iy = 2.0 / 12.0, Iz = 8.0 / 12.0, I = 1.0 / (sn * sn / Iz + cs * cs / Iy);
        const double a = std::pow(24.0 * E * I * g / q, 0.25), exact = q * (L - a);
        auto deck = toRectangles(parallelBeams(type, n, n, 0.0, E, 2));
        for (const char* end : {"Start", "End"}) {
          auto x = deck.sublist("Beams").sublist("rod").get<Teuchos::Array<double>>(end);
          x[2] = 0.5 + sn + 0.5 * cs + g;  // the lowest edge g above the ground's face
          deck.sublist("Beams").sublist("rod").set(end, x);
        }
        deck.sublist("Beams").sublist("rod").set("Section Orientation",
                                                 Teuchos::Array<double>(std::vector<double>{0.0, cs, sn}));
        if (!groundIsA) {
          input::replaceAtPath(deck, "Contact/Pairs/line/Beam A", std::string("rod"));
          input::replaceAtPath(deck, "Contact/Pairs/line/Beam B", std::string("ground"));
        }
        input::replaceAtPath(deck, "Load Stepping/Number of Increments", increments);
        for (int i = 0; i <= n; ++i) support(deck, "ground", i, "all");
        support(deck, "rod", 0, "ux uy uz rx");
        support(deck, "rod", n, "uy uz rx");
        uniformLoad(deck, "rod", n, q);
        auto problem = input::buildProblem(deck, "turned_rod");
        const auto r = test::runQuiet(problem, Tpetra::getDefaultComm(), "turned_rod");
        ASSERT_TRUE(r.report.completed) << type << (groundIsA ? ", ground as A: " : ", rod as A: ") << increments
                                        << " increments: " << r.report.failure;
        double total = 0.0, deepest = 0.0;
        for (const auto& [key, pt] : problem.contact->points()) {
          if (pt.node() || !pt.result.active) continue;
          total += -pt.result.lambdaN;
          deepest = std::max(deepest, -pt.gap);
        }
        std::printf(
            "%s, %s as A, %d elements, %d increments, %g degrees: %d steps, total %.6f (q (L - a) = %.6f, %+.3f %%), "
            "deepest "
            "%.2e\n",
            type.c_str(), groundIsA ? "ground" : "rod", n, increments, degrees, r.report.steps, total, exact,
            100.0 * (total / exact - 1.0), deepest);
        EXPECT_NEAR(total, exact, 0.01 * exact) << type;
        EXPECT_LT(deepest, 1e-4) << type;
        if (increments == 4) totals[groundIsA] = total;
      }
    if (totals.size() == 2) {
      EXPECT_NEAR(totals[true], totals[false], 1e-4 * totals[true]) << type << ": either way round";
    }
  }
}

// A flat plate on a tall beam in one increment: two cantilevers clamped at x = 0, the ground 1 wide
// and 5 tall, the rod a 10 x 1 plate lying on it, loaded by q = 0.01 (consistent loads; alone its
// tip would go 1.5 down, through the ground). With exact contact both deflect alike: the traction is
// uniform, p = q I_g / (I_g + I_r) = q 125 / 135 (I_g = 125 / 12, I_r = 10 / 12), total p L on the
// ground's two edges (Penalty: the rod's clamp lowered by p / (2 eps_N), as above). Every strategy,
// either beam as A, in one increment: complete, the total within 1e-4 of p L (measured 2.3e-5
// Penalty, 4.3e-5 Lagrange and Augmented Lagrange: below), the same either way round (1e-8).
// Before, Lagrange and Augmented Lagrange ended "complete" with no force and the plate 1.5 inside
// the ground: the axes (2.5 apart) were further apart than the inscribed radii sum (1), which the
// unseen-overlap test took for apart; it now tests the sections' overlap (separating axes) and cuts
// the increment.
TEST(LineContact, FlatPlateOnATallBeamInOneIncrementCarriesTheClosedFormTraction) {
  const int n = 10;
  const double q = 0.01, L = 100.0, p = q * 125.0 / 135.0, eps = 100.0;
  double onePlate = 0.0;  // the force with the tall beam as A
  for (const std::string type : {"Penalty", "Lagrange Multiplier", "Augmented Lagrange"})
    for (const bool plateIsA : {false, true}) {
      auto deck = narrowOnWide(type, plateIsA, n);
      for (const auto& [beam, width, height] :
           {std::make_tuple("ground", 1.0, 5.0), std::make_tuple("rod", 10.0, 1.0)}) {
        input::replaceAtPath(deck, std::string("Beams/") + beam + "/Section/Width", width);
        input::replaceAtPath(deck, std::string("Beams/") + beam + "/Section/Height", height);
      }
      for (const char* end : {"Start", "End"}) {
        auto x = deck.sublist("Beams").sublist("rod").get<Teuchos::Array<double>>(end);
        x[2] = 3.0;
        deck.sublist("Beams").sublist("rod").set(end, x);
      }
      input::setAtPath(deck, "Contact/Enforcement/Penalty/Normal Penalty Parameter", eps);
      if (type == "Augmented Lagrange")
        input::setAtPath(deck, "Contact/Enforcement/Augmented Lagrange/Gap Tolerance", 1e-10);
      support(deck, "ground", 0, "all");
      support(deck, "rod", 0, "all", type == "Penalty" ? -p / (2 * eps) : 0.0);
      uniformLoad(deck, "rod", n, q);
      auto problem = input::buildProblem(deck, "plate_on_tall");
      const auto r = test::runQuiet(problem, Tpetra::getDefaultComm(), "plate_on_tall");
      ASSERT_TRUE(r.report.completed) << type << ": " << r.report.failure;
      const NarrowSums s = narrowSums(problem, plateIsA);
      std::printf("%s, A the %s: %d steps, force on the plate %.10f (p L = %.10f), deepest %.2e\n", type.c_str(),
                  plateIsA ? "plate" : "tall beam", r.report.steps, s.onRod, p * L, s.deepest);
      // (The closed form is linear: the faces lie 2.5 above the ground's axis and 0.5 below the
      // plate's, so the nodes' turns theta (up to 1.5e-3) change their gap by 3 theta^2 / 2 on a
      // deflection of 0.11, about 3e-5 of it: 1e-4.)
      EXPECT_NEAR(s.onRod, p * L, 1e-4 * p * L) << type;
      if (plateIsA) {
        EXPECT_NEAR(s.onRod, onePlate, 1e-8 * p * L) << type << ": either way round";
      }
      onePlate = s.onRod;
    }
}

// The narrow-on-wide cantilevers with the narrow one lifted 0.2 and loaded by q = 1 in one increment
// (Penalty, eps_N 1e4, 10 elements): its first Newton step turns the narrow beam's elements by about
// 2 degrees against the wide one's, beyond the rectangles' blend (twice Parallel Line Tolerance), so
// its line points carry nothing there, and no edges cross for point contact. They counted as seeing
// the overlap, and the run ended "complete" with the narrow beam 2.1 inside the other and no force;
// now the increment is cut. Must: complete, the force on the narrow beam balance its load and clamp
// (1e-8), and equal the answer of 20 increments (1e-8; measured equal to 10 digits, 35.7416).
TEST(LineContact, LiftedNarrowBeamPressedInOneIncrementEqualsTwentyIncrements) {
  const int n = 10;
  const double q = 1.0, L = 100.0;
  std::map<int, double> force;
  for (const int increments : {1, 20}) {
    auto deck = narrowOnWide("Penalty", false, n, 0.0, 0.0, 0.2);
    input::setAtPath(deck, "Contact/Enforcement/Penalty/Normal Penalty Parameter", 1e4);
    input::replaceAtPath(deck, "Load Stepping/Number of Increments", increments);
    support(deck, "ground", 0, "all");
    support(deck, "rod", 0, "all");
    uniformLoad(deck, "rod", n, q);
    auto problem = input::buildProblem(deck, "lifted_narrow");
    const auto r = test::runQuiet(problem, Tpetra::getDefaultComm(), "lifted_narrow");
    ASSERT_TRUE(r.report.completed) << increments << " increments: " << r.report.failure;
    const NarrowSums s = narrowSums(problem, false);
    const double reaction = lastReactions(test::scratchDirectory("lifted_narrow_np1")).at("rod 0_Fz");
    std::printf("lifted narrow beam, %2d increments: %d steps, force on it %.10f, its clamp %.10f\n", increments,
                r.report.steps, s.onRod, reaction);
    EXPECT_NEAR(s.onRod + reaction, q * L, 1e-8 * q * L);
    EXPECT_GT(s.onRod, 0.0);
    force[increments] = s.onRod;
  }
  EXPECT_NEAR(force[1], force[20], 1e-8 * force[20]);
}

// Narrow on wide rectangles crossing at 2 degrees, forced into line contact (Parallel Line
// Tolerance sin 3 degrees): the wide beam from x = 20 to 80, the narrow one (length 100) turned about
// (50, 0) and lifted by 0.1, both clamped at their ends, the narrow one's ends (beyond the wide beam)
// pressed down by 0.12 (closure 0.02), their inner nodes held sideways. Either way round, each
// strategy: complete, no penetration deeper than the warnings' 5 % of the thinner inscribed radius,
// the contact forces on the narrow beam equal minus its support reactions (1e-8), and the two ways
// agree: the narrow beam's edges stay on the wide face (1.05 across at x = 20 and 80), so its edges
// carry the contact either way, as A's or with swapped roles (1e-8).
TEST(LineContact, NarrowOnWideRectanglesCrossingAtASmallAngle) {
  const int n = 8;
  for (const std::string type : {"Penalty", "Lagrange Multiplier", "Augmented Lagrange"}) {
    std::map<bool, double> total;
    for (const bool narrowIsA : {true, false}) {
      auto deck = narrowOnWide(type, narrowIsA, n, 0.0, 2.0, 0.1);
      input::replaceAtPath(deck, "Beams/ground/Start", vec("20, 0, 0"));
      input::replaceAtPath(deck, "Beams/ground/End", vec("80, 0, 0"));
      input::setAtPath(deck, "Contact/Parallel Line Tolerance", std::sin(3.0 * std::acos(-1.0) / 180.0));
      if (type != "Lagrange Multiplier") {
        input::setAtPath(deck, "Contact/Enforcement/" + type + "/Normal Penalty Parameter", 1e5);
        input::setAtPath(deck, "Contact/Enforcement/" + type + "/Regularization Gap", 1e-4);
      }
      input::replaceAtPath(deck, "Load Stepping/Number of Increments", 5);
      support(deck, "ground", 0, "all");
      support(deck, "ground", n, "all");
      support(deck, "rod", 0, "all", -0.12);
      support(deck, "rod", n, "all", -0.12);
      for (int i = 1; i < n; ++i) support(deck, "ground", i, "uy");
      for (int i = 1; i < n; ++i) support(deck, "rod", i, "uy");
      auto problem = input::buildProblem(deck, "narrow_crossing");
      const auto r = test::runQuiet(problem, Tpetra::getDefaultComm(), "narrow_crossing");
      ASSERT_TRUE(r.report.completed) << type << ", A " << (narrowIsA ? "narrow" : "wide") << ": " << r.report.failure;
      const NarrowSums s = narrowSums(problem, narrowIsA);
      const auto reactions = lastReactions(test::scratchDirectory("narrow_crossing_np1"));
      const double rod = reactions.at("rod 0_Fz") + reactions.at("rod " + std::to_string(n) + "_Fz");
      total[narrowIsA] = s.onRod;
      std::printf(
          "%s, 2 degrees, A %s: %d points as A, %d swapped, force on the narrow beam %.9f, its supports %.9f, "
          "deepest %.2e, %zu warnings\n",
          type.c_str(), narrowIsA ? "narrow" : "wide", s.asA, s.swapped, s.onRod, rod, s.deepest,
          r.report.warnings.size());
      EXPECT_GT(s.onRod, 0.0);
      EXPECT_NEAR(s.onRod, -rod, 1e-8 * s.onRod);
      EXPECT_LT(s.deepest, 0.05 * 2.5);
      EXPECT_EQ(s.swapped > 0, !narrowIsA);
      EXPECT_EQ(s.asA > 0, narrowIsA);
    }
    EXPECT_NEAR(total[true], total[false], 1e-8 * total[true]);
  }
}

// The angle sweep: a rod (60 long, from x = 20 to 80 when parallel) above a ground beam (100 long,
// pinned at its ends), turned by 0, 0.5, 1, 2, 3, 4, 5, 10 degrees about their common centre, its ends
// pinned, pushed down by 0.2 into the ground's middle and dragged along x by 0.05, friction 0.3;
// circular (r = 0.5) and rectangular (2 x 1) sections; each strategy. Every run must complete, and then:
// - the rod is in equilibrium: the contact forces on it (the force each point applies on beam B,
//   contact_points' normal and tangential vectors) balance its support reactions to 1e-8 of them;
// - the Coulomb cone holds for the force each point applies (|F_T| <= mu |F_N| (1 + 1e-9));
// - no overlap beyond 5 % of the thinner section's inscribed radius unless the run warns of it; the
//   multiplier fields of Lagrange and Augmented Lagrange on circles refine where the contact zone is
//   shorter than an element, with friction too: no warning, and no overlap beyond 1e-3 of the radius
//   (the unresolved-zone warning's threshold; measured at most 8.6e-5 of it, at 2 degrees; at 5
//   degrees the refined field's first attempt at the last step stalls, its retry with a cut step
//   converges refined; before, the retry went on unrefined: 30 % of the force missing, warned);
// - the strategies agree on the total normal force (below).
// At 3 degrees the rectangular rod's ends lie over the ground's face with one lower corner each, and
// no edges cross there: every strategy stopped at first contact (an overlap no point sees) until
// those corners became points of their own ("End corners"). At 4 degrees Lagrange multipliers and
// Augmented Lagrange on circles ended "complete" with the rod 7.7 % of the radius into the ground
// (warned): see the next test.
// At 0 and 0.5 degrees the rod, pressed at its pinned ends, bows up and touches the ground near its
// ends only, its middle at a gap near 0: Penalty's points there joined and left the active set at
// every Newton iterate, and with friction its retries stayed in Newton's own active set: it stopped
// at the first increment (circles). Now the retries from the run's second such failure fix the points
// that act for each Newton solve. Not yet: Lagrange multipliers on the rectangles at 0 degrees (equal
// widths, the edges on each other; the field's active set cycles and the matrix turns singular:
// docs/contact.md, "Not there yet"). Penalty there stalled at T = 0.25 on 4 increments (||r|| 0.92,
// steps of 1e-4); it now completes by way of its retries (7 steps, 186 Newton iterations, 0.456644),
// and with Line Springs = Nodes in 4 steps (84 iterations, 0.457043; Augmented Lagrange 0.457096).
// Penalty with Line Springs = Nodes ("Penalty Nodes") runs every angle and section with the same
// checks, within 0.43 % of the multipliers' total.
namespace {
// The angle sweep's deck (below): the rod turned by `degrees`, the ground of `ground` elements.
Teuchos::ParameterList sweepDeck(const std::string& type, double degrees, bool rectangles, double mu, int ground = 10) {
  auto deck = parallelBeams(type, ground, 10, 0.0, 1e5, 6, degrees, 0.0);
  const double a = degrees * std::acos(-1.0) / 180.0, c = 30.0 * std::cos(a), s = 30.0 * std::sin(a);
  input::replaceAtPath(deck, "Beams/rod/Start", Teuchos::Array<double>(std::vector<double>{50 - c, -s, 1.0}));
  input::replaceAtPath(deck, "Beams/rod/End", Teuchos::Array<double>(std::vector<double>{50 + c, s, 1.0}));
  if (rectangles) deck = toRectangles(deck);
  input::replaceAtPath(deck, "Contact/Pairs/line/Friction Coefficient", mu);
  support(deck, "ground", 0, "ux uy uz rx");
  support(deck, "ground", ground, "uy uz rx");
  for (int end : {0, 10}) {
    support(deck, "rod", end, "ux uy uz rx", -0.2);
    input::replaceAtPath(deck, "Supports/rod " + std::to_string(end) + "/Displacement",
                         Teuchos::Array<double>(std::vector<double>{0.05, 0.0, -0.2}));
  }
  input::replaceAtPath(deck, "Load Stepping/Number of Increments", 4);
  return deck;
}
}  // namespace

TEST(LineContact, AngleSweepEveryStrategyBothSectionsCompletesInEquilibriumWithinTheCone) {
  const double mu = 0.3;
  for (const bool rectangles : {false, true})
    for (const double degrees : {0.0, 0.5, 1.0, 2.0, 3.0, 4.0, 5.0, 10.0}) {
      std::map<std::string, double> normal;  // each strategy's total normal force
      for (const std::string type : {"Penalty", "Penalty Nodes", "Lagrange Multiplier", "Augmented Lagrange"}) {
        if (rectangles && degrees == 0.0 && type == "Lagrange Multiplier") continue;  // not yet (above)
        // ("Penalty Nodes": Penalty with Line Springs = Nodes.)
        const bool penalty = type.rfind("Penalty", 0) == 0;
        auto deck = sweepDeck(penalty ? "Penalty" : type, degrees, rectangles, mu);
        if (type == "Penalty Nodes")
          input::setAtPath(deck, "Contact/Enforcement/Penalty/Line Springs", std::string("Nodes"));
        const std::string name = "sweep";
        auto p = input::buildProblem(deck, name);
        const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), name);
        const std::string what =
            std::string(rectangles ? "rectangles" : "circles") + ", " + test::num(degrees) + " degrees, " + type;
        EXPECT_TRUE(r.report.completed) << what << ": " << r.report.failure;
        if (!r.report.completed) continue;
        // Equilibrium of the rod (beam B of the pair).
        core::Vec3d force{};
        double worstCone = 0.0, deepest = 0.0;
        int active = 0;
        for (const auto& [key, q] : p.contact->points()) {
          if (q.node() || !q.result.active) continue;
          ++active;
          force = force + q.normalForce + q.tangentialForce;
          normal[type] += math::norm(q.normalForce);
          const double n = math::norm(q.normalForce), t = math::norm(q.tangentialForce);
          if (n > 0.0) worstCone = std::max(worstCone, t / (mu * n));
          deepest = std::max(deepest, -q.gap);
        }
        const auto reactions = lastReactions(test::scratchDirectory(name + "_np1"));
        core::Vec3d held{};
        double scale = 0.0;
        for (int end : {0, 10})
          for (int d = 0; d < 3; ++d) {
            const double v = reactions.at("rod " + std::to_string(end) + "_F" + std::string(1, "xyz"[d]));
            held[d] += v;
            scale = std::max(scale, std::abs(v));
          }
        const double imbalance = math::norm(force + held);
        const double inscribed = 0.5;  // the circle's radius, and the 2 x 1 rectangle's inscribed radius
        bool warned = false;
        for (const auto& w : r.report.warnings) warned = warned || w.find("penetrat") != std::string::npos;
        std::printf(
            "%-11s %4.1f deg %-20s: %d active, N %.6g, imbalance %.1e, |F_T| / (mu N) max %.12f, overlap %.2e%s\n",
            rectangles ? "rectangles" : "circles", degrees, type.c_str(), active, math::norm(force), imbalance / scale,
            worstCone, deepest, warned ? " (warned)" : "");
        EXPECT_GT(active, 0) << what;
        EXPECT_LT(imbalance, 1e-8 * scale) << what;
        EXPECT_LE(worstCone, 1.0 + 1e-9) << what;
        if (!warned) {
          EXPECT_LT(deepest, 0.05 * inscribed) << what;
        }
        if (!rectangles && !penalty) {
          EXPECT_FALSE(warned) << what;
          EXPECT_LT(deepest, 1e-3 * inscribed) << what;
        }
      }
      // The strategies on one equilibrium: Penalty's total normal force within 1.5 % of the multipliers'
      // (its compliance, and at 0 and 0.5 degrees its Gauss points' spacing at the rod's pressed ends:
      // measured -0.92 % on circles at 0 degrees, -0.35 % and -0.22 % with 12 and 24 Gauss points),
      // Augmented Lagrange on Lagrange's to 1e-3 (its sticking points' tangential penalty against
      // Lagrange's exact stick: measured up to 2.1e-4 on the rectangles' end points, the same with a Gap
      // Tolerance of 1e-9; 2e-6 on circles, but 7.3e-4 at 1 degree: Lagrange's refined field fails
      // its attempt at the last step, and the retry's field, capped a level coarser for the rest of
      // the run, passes the resolution check (5.4e-6 deep) with 24 active points against 36; with 8
      // increments Lagrange lands on Augmented Lagrange's 0.038912 to 1e-6).
      const double reference =
          normal.count("Lagrange Multiplier") ? normal["Lagrange Multiplier"] : normal["Augmented Lagrange"];
      for (const auto& [type, value] : normal) {
        std::printf("    %-20s total normal force %.6f (%+.2e)\n", type.c_str(), value, value / reference - 1.0);
        EXPECT_NEAR(value, reference, (type.rfind("Penalty", 0) == 0 ? 1.5e-2 : 1e-3) * reference)
            << (rectangles ? "rectangles, " : "circles, ") << degrees << " degrees, " << type;
      }
    }
}

// A contact zone nearly as long as a field element, inside it. The sweep's circles at 4 and 4.5
// degrees, frictionless, the crossing inside a ground element (11 elements, 9.1 long; the zone about
// 9 long). Two things let the rod through:
// - the element's Gauss points all penetrated and its neighbours' were open, so no element both
//   penetrated and opened: no refinement, and the nodes' hats, weighing the open neighbours, were
//   open: Augmented Lagrange's first step ended with the rod 10 % of its radius into the ground and no
//   active point. Now an element that penetrates counts its neighbours' open gaps as its own.
// - where the refined field's attempt at a step failed twice (at its sixth level, a singular matrix),
//   the pair went on unrefined for the rest of the run: Lagrange multipliers passed 17 % of the radius
//   into the ground with no force for half the run and ended "complete" 34 % (4 degrees) and 46 %
//   (4.5) low (warned). Now each failed attempt caps the pair's refinement one level below what it
//   reached.
// The total force within 1 % of Penalty's (eps_N 1e4, whose Gauss points hold their own gaps; 10
// elements, the crossing at a node) and no line point deeper than 2 % of the radius (Lagrange's
// unresolved-zone warning may stay: measured 5.0e-4 and 6.4e-4 deep, 0.13 % and 0.18 % low).
TEST(LineContact, ZoneNearlyAsLongAsAFieldElementIsHeld) {
  for (const double degrees : {4.0, 4.5}) {
    double reference = 0.0;
    for (const std::string type : {"Penalty", "Lagrange Multiplier", "Augmented Lagrange"}) {
      auto deck = sweepDeck(type, degrees, false, 0.0, type == "Penalty" ? 10 : 11);
      auto p = input::buildProblem(deck, "refine_retry");
      const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "refine_retry");
      ASSERT_TRUE(r.report.completed) << degrees << " degrees, " << type << ": " << r.report.failure;
      double force = 0.0, deepest = 0.0;
      for (const auto& [key, q] : p.contact->points()) {
        if (q.node() || !q.result.active) continue;
        force += math::norm(q.normalForce);
        deepest = std::max(deepest, -q.gap);
      }
      if (type == "Penalty") reference = force;
      std::printf("%.1f degrees %-20s: N %.6f (%+.2e of Penalty's), deepest line point %.2e\n", degrees, type.c_str(),
                  force, force / reference - 1.0, deepest);
      EXPECT_NEAR(force, reference, 0.01 * reference) << degrees << " degrees, " << type;
      EXPECT_LT(deepest, 0.02 * 0.5) << degrees << " degrees, " << type;
    }
  }
}

// Two circular cantilevers stacked (radius 0.5, E = 1e5, 10 elements, clamped at x = 0), the upper
// one's tip pressed down by P = 0.05, Penalty with eps_N = 1e4: a penalty's bending wavelength,
// (4 EI / eps_N)^(1/4) = 1.2, is far below the elements' length (10). With 6 Gauss points per element
// the springs over-constrain the elements' relative bending, every point lies within 1e-6 of zero
// gap, and which of them act cycles: the run stops, and its message must say why and what helps
// (before, it named only the cycling). With 3 Gauss points per element it completes without a
// warning: the force sits at the outermost Gauss point, at x = a, and the compatibility of the two
// cantilevers there gives F = P (3 L - a) / (4 a) (P / 2 at the tip; measured -3.5e-4 from it: the
// large deflection's part). (With 2 the tip's last 2.1 lie beyond the outer point: 1.1e-3 of overlap
// there, warned.)
TEST(LineContact, PenaltySpringsOverConstrainingStackedCantileversSayWhatHelps) {
  const double P = 0.05, L = 100.0;
  for (const int gauss : {6, 3}) {
    auto deck = stackedCantilevers("Penalty", 10, gauss, P);
    input::setAtPath(deck, "Load Stepping/Maximum Step Cuts", 1);
    auto p = input::buildProblem(deck, "stacked_penalty");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "stacked_penalty");
    if (gauss == 6) {
      std::printf("6 Gauss points: %s\n", r.report.failure.c_str());
      ASSERT_FALSE(r.report.completed);
      EXPECT_NE(r.report.failure.find("over-constrains"), std::string::npos) << r.report.failure;
      EXPECT_NE(r.report.failure.find("Line Springs = Nodes"), std::string::npos) << r.report.failure;
      EXPECT_NE(r.report.failure.find("Line Gauss Points"), std::string::npos) << r.report.failure;
      EXPECT_NE(r.report.failure.find("Lagrange Multiplier"), std::string::npos) << r.report.failure;
      continue;
    }
    ASSERT_TRUE(r.report.completed) << r.report.failure;
    EXPECT_TRUE(r.report.warnings.empty()) << r.report.warnings.front();
    double total = 0.0, moment = 0.0, onRod = 0.0;  // onRod: the force's vertical part on the rod (beam B)
    for (const auto& [key, q] : p.contact->points()) {
      if (q.node() || !q.result.active) continue;
      total += math::norm(q.normalForce);
      moment += q.position[0] * math::norm(q.normalForce);
      onRod += q.normalForce[2];
    }
    const double a = moment / total, exact = P * (3.0 * L - a) / (4.0 * a);
    const auto reactions = lastReactions(test::scratchDirectory("stacked_penalty_np1"));
    std::printf(
        "3 Gauss points: total normal force %.9f at x = %.6f, closed form %.9f (%+.2e), ground's reaction %.9f\n",
        total, a, exact, total / exact - 1.0, reactions.at("ground 0_Fz"));
    EXPECT_NEAR(total, exact, 1e-3 * exact);
    EXPECT_NEAR(reactions.at("ground 0_Fz"), onRod, 1e-8 * P);  // the ground's clamp takes what it carries
  }
}

// A pass after the first solves at least once. A rod (E = 1e9, r = 0.5) from x = -10 to 110, pinned at
// its ends off the ground (0 to 100, held at every node and loaded there by 1e6, which its supports
// take), starts 1e-5 into the ground (Allow Initial Penetration). The first pass, without contact,
// is in equilibrium at once; the next activates the line nodes, whose rows (gaps of 1e-5 times their
// lengths, about 1e-4) lie below a residual measured against the load of 1e6 (1e-9 of it). Accepted
// unsolved, their multipliers stayed 0 and the run ended "complete" with no contact force and the rod
// still 1e-5 in. Solved: the contact pushes the rod out (a force, balanced by the rod's pins to 1e-9
// of it) and every active line node's weighted gap is closed (Lagrange: to 1e-9 of delta; Augmented
// Lagrange: within its Gap Tolerance).
TEST(LineContact, APassAfterAnActiveSetChangeSolvesItsNewRows) {
  const double E = 1e9, delta = 1e-5, a = 10.0;
  for (const std::string type : {"Lagrange Multiplier", "Augmented Lagrange"}) {
    auto deck = parallelBeams(type, 10, 12, 0.0, E, 6, 0.0, -delta);
    input::replaceAtPath(deck, "Beams/rod/Start", Teuchos::Array<double>(std::vector<double>{-a, 0.0, 1.0 - delta}));
    input::replaceAtPath(deck, "Beams/rod/End", Teuchos::Array<double>(std::vector<double>{100 + a, 0.0, 1.0 - delta}));
    input::setAtPath(deck, "Contact/Allow Initial Penetration", true);
    for (int i = 0; i <= 10; ++i) support(deck, "ground", i, "all");
    support(deck, "rod", 0, "ux uy uz rx");
    support(deck, "rod", 12, "uy uz rx");
    Teuchos::ParameterList& load = deck.sublist("Loads").sublist("held");
    load.set("Beam", std::string("ground"));
    load.set("Node", std::string("5"));
    load.set("Force", Teuchos::Array<double>(std::vector<double>{0.0, 0.0, -1e6}));
    auto p = input::buildProblem(deck, "pass_solves");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "pass_solves");
    ASSERT_TRUE(r.report.completed) << type << ": " << r.report.failure;
    const auto s = lineSums(p);
    double nodeGap = 0.0;
    int nodes = 0;
    for (const auto& [key, q] : p.contact->points())
      if (q.node() && q.extraCount > 0) {
        ++nodes;
        nodeGap = std::max(nodeGap, std::abs(q.gap));
      }
    const auto reactions = lastReactions(test::scratchDirectory("pass_solves_np1"));
    const double pins = -(reactions.at("rod 0_Fz") + reactions.at("rod 12_Fz"));
    std::printf("%s: contact force %.9e, the rod's pins %.9e, %d active line nodes, weighted gaps within %.1e\n",
                type.c_str(), s.total, pins, nodes, nodeGap);
    EXPECT_GT(s.total, 0.0) << type;
    EXPECT_NEAR(s.total, pins, 1e-9 * 1e6) << type;
    EXPECT_GT(nodes, 0) << type;
    EXPECT_LT(nodeGap, type == "Lagrange Multiplier" ? 1e-9 * delta : 1e-6) << type;
  }
}

// Two rectangular cantilevers stacked face to face (2 x 1 and a rod 2 or 1.5 wide on top, 10
// elements each, clamped at x = 0), the upper one's tip pressed down by P = 0.05. They bend alike,
// so every interior line point lies at a gap near 0 and the contact force sits at the tip: for point
// loads on Euler-Bernoulli cantilevers, compatibility of the tips gives the lower one
// P I_lower / (I_upper + I_lower) (P / 2 for equal sections). Near x = 10 the beams' axes stood
// 0.08 degrees apart while the active set settled; the common normal of an edge of A and an edge of
// B was then horizontal, across the faces' normal, and an edge against the far edge of the other
// beam, 2 apart across the width, was a point contact 2 deep (blend weight up to 0.27): Lagrange
// multipliers stopped at T = 0.75 (the active set cycling), Augmented Lagrange at 0.73. Now no point
// lies across the faces. Either way round, Lagrange multipliers and Augmented Lagrange: complete,
// the total normal force within 5e-4 of the closed form (measured +1.89e-4 to +1.91e-4, +2.1e-4 with
// 20 elements: the large-deflection part, +1.75e-5 with a tenth of the load), the contact forces on
// the ground equal to minus its clamp's reaction (1e-8), no line point deeper than 1e-6.
TEST(LineContact, StackedCantileversBentAlikeCarryTheTipForceOfTheClosedForm) {
  struct Case {
    std::string type;
    double rodWidth;
    bool rodIsA;
  };
  for (const Case& c : {Case{"Lagrange Multiplier", 2.0, false}, Case{"Lagrange Multiplier", 1.5, true},
                        Case{"Augmented Lagrange", 2.0, false}}) {
    auto deck = toRectangles(parallelBeams(c.type, 10, 10, 0.0, 1e5, 6), c.rodWidth);
    if (c.rodIsA) {
      input::replaceAtPath(deck, "Contact/Pairs/line/Beam A", std::string("rod"));
      input::replaceAtPath(deck, "Contact/Pairs/line/Beam B", std::string("ground"));
    }
    support(deck, "ground", 0, "all");
    support(deck, "rod", 0, "all");
    Teuchos::ParameterList& load = deck.sublist("Loads").sublist("tip");
    load.set("Beam", std::string("rod"));
    load.set("Node", std::string("end"));
    const double P = 0.05;
    load.set("Force", Teuchos::Array<double>(std::vector<double>{0.0, 0.0, -P}));
    input::replaceAtPath(deck, "Load Stepping/Number of Increments", 4);
    auto p = input::buildProblem(deck, "stacked");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "stacked");
    const std::string what =
        c.type + ", rod " + test::num(c.rodWidth) + " wide, " + (c.rodIsA ? "rod" : "ground") + " as A";
    ASSERT_TRUE(r.report.completed) << what << ": " << r.report.failure;
    double total = 0.0, deepest = 0.0;
    core::Vec3d onB{};  // the force the points apply on beam B
    for (const auto& [key, q] : p.contact->points()) {
      if (q.node() || !q.result.active) continue;
      total += math::norm(q.normalForce);
      onB = onB + q.normalForce + q.tangentialForce;
      deepest = std::max(deepest, -q.gap);
    }
    // The ground's equilibrium: its clamp's reaction and the contact's force on it cancel (the ground
    // is B with the rod as A, else A, which carries minus B's force).
    const auto reactions = lastReactions(test::scratchDirectory("stacked_np1"));
    const double onGround = c.rodIsA ? onB[2] : -onB[2];
    EXPECT_NEAR(reactions.at("ground 0_Fz"), -onGround, 1e-8 * P) << what;
    // Second moments about the width axis are proportional to the widths (equal heights).
    const double exact = P * 2.0 / (2.0 + c.rodWidth);
    std::printf("%s: total normal force %.9f, closed form %.9f (%+.2e), ground's reaction %.9f, deepest %.2e\n",
                what.c_str(), total, exact, total / exact - 1.0, reactions.at("ground 0_Fz"), deepest);
    EXPECT_NEAR(total, exact, 5e-4 * exact) << what;
    EXPECT_LT(deepest, 1e-6) << what;
  }
}

// Two equal circular rods stacked (r = 0.5, E = 1e9, L = 100), each supported in y and z at both ends
// and held along x at mid-span (the symmetry plane), the upper rod loaded by q = 1 per length, with
// friction: a layered beam. Where the interface sticks, the rods bend as one section (full
// interaction): I_c = 2 (pi r^4 / 4) + 2 (pi r^2) r^2 = 2.5 pi r^4, mid-span deflection
// 5 q L^4 / (384 E I_c), 5 times stiffer than the rods apart. The interface's shear flow is
// f = V S / I_c (S = pi r^2 r, the first moment of one rod about the pair's centroid), largest at the
// supports, V = q L / 2: f = 40; the line pressure is q / 2 along the whole line (each rod takes the
// same curvature and the same moment r f per length from the shear flow), so the interface sticks
// everywhere for mu >= 80 and slips near the supports below.
// The slip is that of the surfaces (LinePairInput::turnSlip): with A's axis point's slip alone a
// friction force put the moment r_A f of A's section on B, the pressure was q / 2 -+ r f', and the
// answer depended on which rod was A (mu = 50: one order stuck everywhere, the other did not converge).
TEST(LineContact, StackedRodsWithFrictionBendAsOneSectionWhereTheyStick) {
  const double E = 1e9, r = 0.5, L = 100.0, q = 1.0, pi = std::acos(-1.0);
  const double composite = 5 * q * std::pow(L, 4) / (384 * E * 2.5 * pi * std::pow(r, 4));
  const double apart = 5 * (q / 2) * std::pow(L, 4) / (384 * E * pi * std::pow(r, 4) / 4);
  auto layered = [&](const std::string& type, int n, double mu, bool rodIsA) {
    auto deck = rodsWithFriction(type, n, E, mu, rodIsA, 1e8);
    for (const char* beam : {"ground", "rod"}) {
      support(deck, beam, 0, "uy uz rx");
      support(deck, beam, n / 2, "ux");
      support(deck, beam, n, "uy uz rx");
    }
    uniformLoad(deck, "rod", n, q);
    input::replaceAtPath(deck, "Load Stepping/Number of Increments", 2);
    auto p = input::buildProblem(deck, "layered");
    const auto run = test::runQuiet(p, Tpetra::getDefaultComm(), "layered");
    EXPECT_TRUE(run.report.completed) << type << ", " << n << " elements, mu " << mu << ": " << run.report.failure;
    const int mid = p.beams->beams()[1].nodes[n / 2];
    return -(run.finalState.position[mid][2] - 1.0);
  };
  // Sticking everywhere (Lagrange multipliers): the composite section, at second order in the mesh.
  double previous = 0.0;
  for (int n : {10, 20, 40}) {
    const double w = layered("Lagrange Multiplier", n, 100.0, false), error = std::abs(w / composite - 1.0);
    std::printf("mu 100, %2d elements: mid-span deflection %.9f, composite %.9f (%.2e), rods apart %.9f\n", n, w,
                composite, error, apart);
    if (previous > 0.0) {
      EXPECT_GT(previous / error, 3.5) << n;
    }
    previous = error;
  }
  EXPECT_LT(previous, 3e-4);
  // Either rod as A, each strategy: the same answer; sticking from mu = 80 on (the same as mu 1000),
  // slipping near the supports at 70.
  const int n = 20;
  const double stuck = layered("Lagrange Multiplier", n, 1000.0, false);
  for (const double mu : {85.0, 70.0, 5.0}) {
    const double w = layered("Lagrange Multiplier", n, mu, false),
                 swapped = layered("Lagrange Multiplier", n, mu, true);
    std::printf("Lagrange multipliers, mu %g: %.9f, rod as A %.9f\n", mu, w, swapped);
    EXPECT_NEAR(swapped, w, 1e-6 * w) << mu;
    if (mu > 80.0) {
      EXPECT_NEAR(w, stuck, 1e-9 * stuck);
    } else {
      EXPECT_GT(w, stuck * (1.0 + 1e-4)) << mu;
    }
    EXPECT_LT(w, apart) << mu;
  }
  for (const std::string type : {"Penalty", "Augmented Lagrange"}) {
    const double w = layered(type, n, 50.0, false), swapped = layered(type, n, 50.0, true);
    std::printf("%s, mu 50: %.9f, rod as A %.9f\n", type.c_str(), w, swapped);
    EXPECT_NEAR(swapped, w, 1e-4 * w) << type;
  }
}

// Friction across the axes of circles (the surfaces' slip across, g_T1): a rod (r 0.5, E 1e7, L 100)
// lying on a held rod of the same section, pressed by q = 1 per length, then twisted at its free end
// by T. The rod is held across (uy) at every node and clamped against twist at x = 0 only, so its
// twist phi(x) is resisted by the friction moment per length, at most mu q r. Where T < mu q r L it
// slips over the length l = T / (mu q r) from its end and sticks beyond (no twist there): phi(L) =
// T^2 / (2 G J mu q r), phi(L - l + s) = mu q r s^2 / (2 G J). Above it slips everywhere and the
// clamp takes the rest: phi(L) = (T L - mu q r L^2 / 2) / (G J). The normal load comes first (T 0
// to 0.5), then the torque (0.5 to 1), so that the interface is pressed before it is twisted.
TEST(LineContact, RodTwistedOnAHeldRodSlipsWhereItsTorqueExceedsTheFriction) {
  const double E = 1e7, r = 0.5, L = 100.0, q = 1.0, mu = 0.3, pi = std::acos(-1.0);
  const double GJ = E / 2.6 * pi * std::pow(r, 4) / 2, m = mu * q * r;
  struct Twist {
    bool completed = false;
    double end = 0.0, mid = 0.0;
  };
  const auto twisted = [&](const std::string& type, int n, double T, bool rodIsA) {
    auto deck = rodsWithFriction(type, n, E, mu, rodIsA, 1e7);
    for (int i = 0; i <= n; ++i) {
      support(deck, "ground", i, "all");
      support(deck, "rod", i, i == 0 ? "ux uy uz rx ry" : "uy");
    }
    uniformLoad(deck, "rod", n, q);
    for (int i = 0; i <= n; ++i)
      deck.sublist("Loads").sublist("rod q " + std::to_string(i)).set("Load Curve", vec("0, 0, 0.5, 1, 1, 1"));
    Teuchos::ParameterList& torque = deck.sublist("Loads").sublist("torque");
    torque.set("Beam", std::string("rod"));
    torque.set("Node", std::string("end"));
    torque.set("Moment", Teuchos::Array<double>(std::vector<double>{T, 0.0, 0.0}));
    torque.set("Load Curve", vec("0, 0, 0.5, 0, 1, 1"));
    input::replaceAtPath(deck, "Load Stepping/Number of Increments", 10);
    auto p = input::buildProblem(deck, "twisted");
    const auto run = test::runQuiet(p, Tpetra::getDefaultComm(), "twisted");
    EXPECT_TRUE(run.report.completed) << type << ", " << n << " elements, T " << T << ": " << run.report.failure;
    const auto& rod = p.beams->beams()[1].nodes;
    const auto angle = [&](int node) {
      const auto& R = run.finalState.rotation[node];
      return std::atan2(R(2, 1), R(1, 1));
    };
    return Twist{run.report.completed, angle(rod[n]), angle(rod[n / 2])};
  };
  // Slipping over 60 of the 100 (T = 9), Lagrange multipliers: the error falls with the mesh.
  const double T = 9.0, l = T / m, end = T * T / (2 * GJ * m), mid = m * std::pow(L / 2 - (L - l), 2) / (2 * GJ);
  double previous = 1.0;
  for (int n : {10, 20, 40}) {
    const Twist t = twisted("Lagrange Multiplier", n, T, true);
    const double error = std::abs(t.end / end - 1.0);
    std::printf("T %g, %2d elements: twist at the end %.9e (closed form %.9e, %.2e), at mid-span %.9e (%.9e)\n", T, n,
                t.end, end, error, t.mid, mid);
    EXPECT_LT(error, 0.7 * previous) << n;
    EXPECT_LT(error, 1.5e-3) << n;
    previous = error;
    EXPECT_NEAR(t.mid, mid, 0.1 * mid) << n;
  }
  EXPECT_LT(previous, 3e-4);
  // Every strategy, either rod as A (Lagrange multipliers on the held rod's nodes: not yet, see
  // docs/contact.md, "Friction across the axes"). Penalty (eps_T 1e7 per length) twists further by
  // its springs' stretch, mu q / eps_T over the radius at the slip zone's end, 6e-8 (1e-4).
  for (const std::string type : {"Penalty", "Augmented Lagrange", "Lagrange Multiplier"})
    for (const bool rodIsA : {false, true}) {
      if (type == "Lagrange Multiplier" && !rodIsA) continue;
      const Twist t = twisted(type, 20, T, rodIsA);
      std::printf("%s, %s as A: twist at the end %.9e (%.2e from the closed form)\n", type.c_str(),
                  rodIsA ? "rod" : "held rod", t.end, t.end / end - 1.0);
      EXPECT_NEAR(t.end, end, 1.5e-3 * end) << type << rodIsA;
    }
  // Slipping everywhere (T = 20 > mu q r L = 15): the friction moment is mu r times the normal
  // force everywhere.
  const double all = 20.0, endAll = (all * L - m * L * L / 2) / GJ;
  const Twist t = twisted("Lagrange Multiplier", 20, all, true);
  std::printf("T %g: twist at the end %.9e (closed form %.9e, %.2e)\n", all, t.end, endAll, t.end / endAll - 1.0);
  EXPECT_NEAR(t.end, endAll, 1e-5 * endAll);
}
