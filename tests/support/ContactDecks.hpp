// Decks and checks shared by the contact regression tests (tests/regression/test_contact_*.cpp,
// test_line_contact.cpp): the seed paper's Example 1 edited by parameter path, its circular and
// crossed-cantilever variants, parallel beams in line contact, the contact sums of a solved problem,
// and the contact tangent against central differences of the residual.
#pragma once
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "constraints/ContactManager.hpp"
#include "support/AssembledTangent.hpp"
#include "support/TestSupport.hpp"

#ifndef BC_SOURCE_DIR
#error "BC_SOURCE_DIR (the source tree, for the decks of input/) must be defined"
#endif

namespace bc::test {

// Decks are parameter lists, edited by parameter path (input::replaceAtPath fails on a misspelt
// path), never as text.
using Deck = Teuchos::ParameterList;

// "a, b, c" as an Array(double).
inline Teuchos::Array<double> vec(const std::string& text) {
  std::vector<double> v;
  std::stringstream ss(text);
  for (std::string x; std::getline(ss, x, ',');) v.push_back(std::stod(x));
  return Teuchos::Array<double>(v);
}

// A deck of input/ with its enforcement strategy set to `type`.
inline Deck inputDeck(const std::string& name, const std::string& type) {
  Deck d = input::readParameterXmlFile(std::string(BC_SOURCE_DIR) + "/input/" + name);
  input::replaceAtPath(d, "Contact/Enforcement/Type", type);
  return d;
}

// Example 1's deck with the strategy, the motion of beam 2's ends, the increments, the penalty
// parameters (of Penalty and Augmented Lagrange) and the friction coefficient replaced.
inline Deck example1(const std::string& type, const std::string& motion = "40.0, 0.0, -20.0", int increments = 50,
                     double epsN = 1e4, double epsT = 400.0, double mu = 0.5) {
  Deck d = inputDeck("example1.xml", type);
  for (const char* end : {"Supports/beam 2 start/Displacement", "Supports/beam 2 end/Displacement"})
    input::replaceAtPath(d, end, vec(motion));
  input::replaceAtPath(d, "Load Stepping/Number of Increments", increments);
  for (const std::string s : {"Penalty", "Augmented Lagrange"}) {
    input::replaceAtPath(d, "Contact/Enforcement/" + s + "/Normal Penalty Parameter", epsN);
    input::replaceAtPath(d, "Contact/Enforcement/" + s + "/Tangential Penalty Parameter", epsT);
  }
  input::replaceAtPath(d, "Contact/Pairs/crossing/Friction Coefficient", mu);
  return d;
}

// Beam 2 of Example 1 moved to run from `start` to `end`.
inline void moveBeam2(Deck& d, const std::string& start, const std::string& end) {
  input::replaceAtPath(d, "Beams/beam 2/Start", vec(start));
  input::replaceAtPath(d, "Beams/beam 2/End", vec(end));
}

struct ContactSums {
  double normal = 0.0, tangential1 = 0.0, maxPenetration = 0.0;
  int active = 0;
};

inline ContactSums sums(const input::Problem& p) {
  ContactSums c;
  for (const auto& [key, pt] : p.contact->points()) {
    if (!pt.result.active) continue;
    ++c.active;
    c.normal += -pt.result.lambdaN;
    c.tangential1 += pt.result.lambdaT[0];
    c.maxPenetration = std::max(c.maxPenetration, -pt.gap);
  }
  return c;
}

// Linear closed form of the pressing-only case (derived here): compliances of beam 1 at
// mid-span 1/600 and of beam 2 centre-to-ends 1/75, and here the penalty springs of the `points`
// contact points in parallel: N = (W - 0.5) / (1/600 + 1/75 + 1/(points eps_N)).
inline double pressingForce(double W, double epsN, int points) {
  const double spring = epsN > 0 ? 1.0 / (points * epsN) : 0.0;
  return (W - 0.5) / (1.0 / 600 + 1.0 / 75 + spring);
}

// The contact contribution alone, supports applied, at state `s`: max |K - central differences of
// the residual| (and max |K| in kmax).
inline double assembledContactTangentError(const input::Problem& p, const core::State& s, double& kmax) {
  auto comm = Tpetra::getDefaultComm();
  core::Model m;
  m.initial = p.model.initial;
  m.supports = p.model.supports;
  m.contributions = {p.contact};
  core::Assembler a(comm, m);
  const auto e = assembledTangentError(a, s, 0.3);
  kmax = e.largest;
  return e.error;
}

// `motion` of beam 2's ends at T = 1, solved to T = 0.3, then beam 2 moved by `dx` along X.
inline void checkContactTangent(const std::string& type, const Deck& deck, double dx, bool expectSlip, bool expectStick,
                                double mu) {
  auto comm = Tpetra::getDefaultComm();
  auto p = input::buildProblem(deck, "tangent_" + type);
  p.solver.loadFactors = {0.1, 0.2, 0.3};
  const auto run = test::runQuiet(p, comm, "contact_tangent");
  ASSERT_TRUE(run.report.completed) << run.report.failure;
  // Move beam 2 on along X from the converged state: the lines along beam 1 slide on, the lines
  // along beam 2 keep sticking.
  core::State s = run.finalState;
  for (int n : p.beams->beams()[1].nodes) s.applyNodeIncrement(n, std::array<double, 6>{dx, 0, 0, 0, 0, 0}.data());
  int slipping = 0, sticking = 0;
  for (const auto& [key, pt] : p.contact->points()) {
    const auto k = p.contact->kinematics(pt, s);
    if (!p.contact->enforcer().contributes(k.normal.value, *pt.state)) continue;
    std::vector<double> f(constraints::kPairDofs + 3, 0.0);
    const auto view = p.contact->strategyView(pt, k, s);
    ASSERT_EQ(view.friction, mu);
    const auto r = p.contact->enforcer().evaluate(view, *pt.state, f.data(), nullptr);
    for (int i = 0; i < 2; ++i) (r.slip[i] ? slipping : sticking)++;
  }
  if (expectSlip) {
    EXPECT_GT(slipping, 0);
  }
  if (expectStick) {
    EXPECT_GT(sticking, 0);
  }
  double kmax = 0.0;
  const double err = assembledContactTangentError(p, s, kmax);
  if (comm->getRank() == 0)
    std::printf(
        "%s: contact tangent vs central differences: max error / max |K| = %.2e (%d sliding, %d sticking lines)\n",
        type.c_str(), err / kmax, slipping, sticking);
  EXPECT_GT(kmax, 0.0);
  EXPECT_LT(err / kmax, 1e-6);
}

// Newton near a contact solution: from the converged state `s` at T = 1, a solve for T = 1.02 with the
// contact set unchanged. Orders p = log(eps_k+1) / log(eps_k), eps_k = ||du_k|| / ||du_0||, counted
// while eps_k < 1e-2 and ||du_k+1|| > 1e-12; each must exceed 1.8 (quadratic), and at least one is
// measured. Prints the increments and the orders after `what`.
inline void expectQuadraticNewton(input::Problem& p, const core::State& s, const std::string& what) {
  auto comm = Tpetra::getDefaultComm();
  auto linear = core::makeLinearSolver(p.linearSolver, {p.model.initial.numDofs(), 0, comm->getSize()});
  core::StaticSolver solver(comm, p.model, p.solver, *linear);
  core::State end;
  const auto trace = solver.iterateFrom(s, 1.0, 1.02, end);
  std::printf("%s: increments", what.c_str());
  for (const auto& it : trace.history) std::printf(" %.2e", it.incrementNorm);
  std::printf("\n  orders");
  const double du0 = trace.history[0].incrementNorm;
  int measured = 0;
  for (std::size_t k = 1; k + 1 < trace.history.size(); ++k) {
    const double ek = trace.history[k].incrementNorm / du0, next = trace.history[k + 1].incrementNorm;
    if (next < 1e-12 || next > trace.history[k].incrementNorm) break;
    if (ek >= 1e-2) continue;
    const double order = std::log(next / du0) / std::log(ek);
    std::printf(" %.3f", order);
    EXPECT_GT(order, 1.8) << what;
    ++measured;
  }
  std::printf("\n");
  EXPECT_GE(measured, 1) << what;
}

// Example 1's layout with circular sections (r = 5 and 2.5, gap 0.5), frictionless: the axes cross at x = 50 on
// beam 1 and at beam 2's centre node, both nodes, so the point load is nodal and Euler-Bernoulli
// gives the exact discrete answer: N = (W - 0.5) / (c1 + c2 + 1/eps_N), c1 = a^3 / (3 E I1) with
// a = 50 (cantilever), c2 = L^3 / (48 E I2) with L = 100 (beam 2 simply supported in bending), and
// A's deflection N a^2 (3 L1 - a) / (6 E I1).
inline Deck circles(const std::string& type, double W, double epsN, const std::string& motion = "", int increments = 4,
                    double mu = 0.0) {
  Deck d = example1(type, motion.empty() ? "0.0, 0.0, " + test::num(-W) : motion, increments, epsN, 400.0, mu);
  for (const auto& [beam, radius] : {std::make_pair("beam 1", 5.0), std::make_pair("beam 2", 2.5)}) {
    Deck& section = input::sublistAtPath(d, std::string("Beams/") + beam + "/Section", false);
    section.remove("Width");
    section.remove("Height");
    section.set("Shape", std::string("Circle"));
    section.set("Radius", radius);
  }
  return d;
}

// The closed form of circles(): N = (W - 0.5) / (c1 + c2 + 1 / eps_N) (eps_N 0: rigid contact).
inline double circlesForce(double W, double epsN) {
  const double pi = std::acos(-1.0), E = 30000.0;
  const double I1 = pi * std::pow(5.0, 4) / 4, I2 = pi * std::pow(2.5, 4) / 4;
  const double c1 = std::pow(50.0, 3) / (3 * E * I1), c2 = std::pow(100.0, 3) / (48 * E * I2);
  return (W - 0.5) / (c1 + c2 + (epsN > 0.0 ? 1.0 / epsN : 0.0));
}

// Crossed cantilevers (derived here): beam 2 (circle r = 2.5, length 100) clamped at
// y = -50, its tip moved down by Delta; beam 1 (circle r = 5) as in Example 1. Contact at a1 = 50
// on beam 1 and a2 = 50 from beam 2's clamp, both nodes, so Euler-Bernoulli is exact:
// N = (c Delta - g0) / (f11 + f22), c = a2^2 (3 L2 - a2) / (2 L2^3), f11 = a1^3 / (3 E I1),
// f22 = a2^3 / (3 E I2) - a2^4 (3 L2 - a2)^2 / (12 E I2 L2^3).
// Initial gap 0.01 and a press of 0.01: the axes (7.5 apart) tilt with the beams' slopes theta and
// the gap between the surfaces shrinks by about 7.5 theta^2 / 2 beyond the linear theory, a second
// order effect that stays below 1e-3 of the press only while the deflections are this small.
inline Deck crossedCantilevers(const std::string& type, double delta) {
  Deck d = circles(type, 0.0, 1e4);
  moveBeam2(d, "50.0, -50.0, 7.51", "50.0, 50.0, 7.51");  // initial gap 0.01
  // Beam 2 clamped at its start, its tip pushed down by delta.
  Deck& supports = input::sublistAtPath(d, "Supports", false);
  for (const char* old : {"beam 2 start", "beam 2 end", "symmetry at B"}) supports.remove(old);
  Deck& clamp = supports.sublist("beam 2 clamp");
  clamp.set("Beam", std::string("beam 2"));
  clamp.set("Node", std::string("start"));
  Deck& tip = supports.sublist("beam 2 tip");
  tip.set("Beam", std::string("beam 2"));
  tip.set("Node", std::string("end"));
  tip.set("Fixed", std::string("uz"));
  tip.set("Displacement", vec("0, 0, " + test::num(-delta)));
  return d;
}

// The closed form of the crossed cantilevers above: the compliances f11 (beam 1) and f22 (beam 2,
// tip held) at the contact point, c (the point's deflection per unit tip motion of beam 2), the
// initial gap g0 and the tip motion delta that closes it and presses by 0.01.
struct CrossedCantileverForm {
  double c, f11, f22, g0, delta;
};
inline CrossedCantileverForm crossedCantileverForm() {
  const double pi = std::acos(-1.0), E = 30000.0, g0 = 0.01, L2 = 100.0, a1 = 50.0, a2 = 50.0;
  const double I1 = pi * std::pow(5.0, 4) / 4, I2 = pi * std::pow(2.5, 4) / 4;
  const double c = a2 * a2 * (3 * L2 - a2) / (2 * L2 * L2 * L2);
  const double f11 = std::pow(a1, 3) / (3 * E * I1);
  const double f22 =
      std::pow(a2, 3) / (3 * E * I2) - std::pow(a2, 4) * std::pow(3 * L2 - a2, 2) / (12 * E * I2 * std::pow(L2, 3));
  return {c, f11, f22, g0, (g0 + 0.01) / c};
}

// The deck with its friction law set (the paper decks select "Per Line").
inline Deck withLaw(Deck deck, const std::string& law) {
  input::replaceAtPath(deck, "Contact/Friction Law", law);
  return deck;
}

// Press, then slide by load curves (docs/input.md): Example 1's layout with circular sections and
// friction `mu` (Isotropic Coulomb); beam 2's ends are pressed down by 0.6 while T goes from 0 to 0.5
// (load curve 0, 0, 0.5, 1, 1, 1; supports "beam 2 start" and "beam 2 end" fixing uz ry) and, with
// `drag`, moved by 1.0 along X while T goes to 1 by a second support on each end node ("beam 2 start
// drag", "beam 2 end drag" fixing ux; load curve 0, 0, 0.5, 0, 1, 1), in 20 increments. Without
// `drag` the press alone in 10 increments to T = 1, the ends held in ux.
inline Deck pressThenSlide(const std::string& type, double mu, bool drag) {
  Deck d = withLaw(circles(type, 0.6, 1e4, "", drag ? 20 : 10, mu), "Isotropic Coulomb");
  const Teuchos::Array<double> press = vec("0, 0, 0.5, 1, 1, 1"), slide = vec("0, 0, 0.5, 0, 1, 1");
  for (const std::string node : {"start", "end"}) {
    const std::string s = "Supports/beam 2 " + node;
    input::replaceAtPath(d, s + "/Fixed", std::string(drag ? "uz ry" : "ux uz ry"));
    input::replaceAtPath(d, s + "/Displacement", vec("0, 0, -0.6"));
    if (!drag) continue;
    input::setAtPath(d, s + "/Load Curve", press);
    Deck& move = input::sublistAtPath(d, s + " drag");
    move.set("Beam", std::string("beam 2"));
    move.set("Node", node);
    move.set("Fixed", std::string("ux"));
    move.set("Displacement", vec("1.0, 0, 0"));
    move.set("Load Curve", slide);
  }
  return d;
}

// The last step's row of a run's reactions.csv (the forces the supports exert on the beams), by column.
inline std::map<std::string, double> lastReactions(const std::string& directory) {
  std::ifstream csv(directory + "/reactions.csv");
  std::string header, line, last;
  std::getline(csv, header);
  while (std::getline(csv, line)) last = line;
  std::map<std::string, double> row;
  std::stringstream hs(header), ls(last);
  for (std::string h, v; std::getline(hs, h, ',') && std::getline(ls, v, ',');) row[h] = std::stod(v);
  return row;
}

// Two parallel circular beams along X (r = 0.5, E = `E`), "ground" from 0 to 100 at z = 0 and "rod"
// from `shift` to 100 + shift touching it (axis 1 above), with `ground` and `rod` elements, in line
// contact (ground is beam A); no supports or loads yet.
// `degrees` turns the rod about its centre in the XY plane (all-angle tests); `lift` raises it.
inline Teuchos::ParameterList parallelBeams(const std::string& type, int ground, int rod, double shift, double E,
                                            int gauss, double degrees = 0.0, double lift = 0.0) {
  Teuchos::ParameterList deck("BeamContact");
  auto beam = [&](const std::string& name, double x0, double z, int n) {
    Teuchos::ParameterList& b = deck.sublist("Beams").sublist(name);
    const double a = name == "rod" ? degrees * std::acos(-1.0) / 180.0 : 0.0;
    const double cx = x0 + 50.0, dx = 50.0 * std::cos(a), dy = 50.0 * std::sin(a);
    b.set("Start", Teuchos::Array<double>(std::vector<double>{cx - dx, -dy, z}));
    b.set("End", Teuchos::Array<double>(std::vector<double>{cx + dx, dy, z}));
    b.set("Elements", n);
    b.sublist("Section").set("Shape", std::string("Circle"));
    b.sublist("Section").set("Radius", 0.5);
    b.sublist("Material").set("Young's Modulus", E);
    b.sublist("Material").set("Poisson's Ratio", 0.3);
  };
  beam("ground", 0.0, 0.0, ground);
  beam("rod", shift, 1.0 + lift, rod);
  Teuchos::ParameterList& c = deck.sublist("Contact");
  Teuchos::ParameterList& pair = c.sublist("Pairs").sublist("line");
  pair.set("Beam A", std::string("ground"));
  pair.set("Beam B", std::string("rod"));
  pair.set("Friction Coefficient", 0.0);
  c.set("Line Gauss Points", gauss);
  c.sublist("Enforcement").set("Type", type);
  for (const char* s : {"Penalty", "Augmented Lagrange"}) {
    c.sublist("Enforcement").sublist(s).set("Normal Penalty Parameter", 1e4);
    c.sublist("Enforcement").sublist(s).set("Tangential Penalty Parameter", 1e3);
  }
  deck.sublist("Load Stepping").set("Number of Increments", 1);
  deck.sublist("Output").set("Write VTK", false);
  return deck;
}

inline void support(Teuchos::ParameterList& deck, const std::string& beam, int node, const std::string& fixed,
                    double uz = 0.0) {
  Teuchos::ParameterList& s = deck.sublist("Supports").sublist(beam + " " + std::to_string(node));
  s.set("Beam", beam);
  s.set("Node", std::to_string(node));
  s.set("Fixed", fixed);
  s.set("Displacement", Teuchos::Array<double>(std::vector<double>{0.0, 0.0, uz}));
}

// A parallelBeams deck with rectangular sections (width 2 along y, the rod's `rodWidth`, height 1
// along z).
inline Teuchos::ParameterList toRectangles(Teuchos::ParameterList deck, double rodWidth = 2.0) {
  for (const char* beam : {"ground", "rod"}) {
    Teuchos::ParameterList& sec = deck.sublist("Beams").sublist(beam).sublist("Section");
    sec.remove("Radius");
    sec.set("Shape", std::string("Rectangle"));
    sec.set("Width", std::string(beam) == "rod" ? rodWidth : 2.0);
    sec.set("Height", 1.0);
  }
  return deck;
}

// The named beams' sections made squares of the given sides.
inline void squareSections(Deck& deck, std::initializer_list<std::pair<const char*, double>> sides) {
  for (const auto& [beam, side] : sides) {
    Deck& sec = deck.sublist("Beams").sublist(beam).sublist("Section");
    sec.remove("Radius");
    sec.set("Shape", std::string("Rectangle"));
    sec.set("Width", side);
    sec.set("Height", side);
  }
}

// input/columns_end_to_end.xml slid with friction 0.3: the lower column stiffened (E = 1e5), the upper
// one starting 0.001 above it, its top driven by (0.3, 0.2, -0.0105) in 8 increments (32 for
// Augmented Lagrange, whose stick state depends on the step: docs/contact.md, "End-to-end contact"),
// penalties 1e3 / 1e2;
// rectangles: the lower column 1.2 x 1.2, the upper 1 x 1.
inline Deck endToEndSlide(const std::string& type, bool rectangles) {
  Deck d = inputDeck("columns_end_to_end.xml", type);
  if (rectangles) squareSections(d, {{"lower", 1.2}, {"upper", 1.0}});
  input::replaceAtPath(d, "Contact/Pairs/end to end/Friction Coefficient", 0.3);
  input::replaceAtPath(d, "Beams/lower/Material/Young's Modulus", 1e5);
  input::replaceAtPath(d, "Beams/upper/Start", vec("0.0, 0.0, 20.001"));
  input::replaceAtPath(d, "Beams/upper/End", vec("0.0, 0.0, 10.001"));
  input::replaceAtPath(d, "Supports/upper top/Displacement", vec("0.3, 0.2, -0.0105"));
  input::replaceAtPath(d, "Load Stepping/Number of Increments", type == "Augmented Lagrange" ? 32 : 8);
  for (const std::string law : {"Penalty", "Augmented Lagrange"}) {
    input::replaceAtPath(d, "Contact/Enforcement/" + law + "/Normal Penalty Parameter", 1e3);
    input::replaceAtPath(d, "Contact/Enforcement/" + law + "/Tangential Penalty Parameter", 1e2);
  }
  return d;
}

}  // namespace bc::test
