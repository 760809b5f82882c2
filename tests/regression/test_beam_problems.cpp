// Regression tests of the nonlinear beam solver against closed forms:
//  - linear cantilever (Euler-Bernoulli): tip deflection and rotation in both bending planes, axial
//    stretch and twist, loads small enough (tip deflection 1e-4 L) that geometric nonlinearity is
//    ~1e-8 relative; tolerance 1e-6 relative;
//  - end moment M = 2 pi E I / L rolls the cantilever into a full circle;
//  - quadratic convergence of Newton on a large-deflection tip-force case (order asserted);
//  - a tip force of 1e-200 (forces that underflow when squared) is solved, not taken for equilibrium;
//  - the small-strain check warns exactly when M h / (2 E I) or N / (E A) crosses 5 %;
//  - an increment at its round-off floor is accepted once the residual test holds, and a failure names
//    the test that failed.
#include <gtest/gtest.h>

#include <cmath>

#include "constraints/ContactManager.hpp"
#include "core/Compliance.hpp"
#include "elements/BeamSet.hpp"
#include "elements/CrossSection.hpp"
#include "elements/PinnedJoints.hpp"
#include "support/TestSupport.hpp"

using namespace bc;

namespace {

const double L = 100.0, b = 2.0, h = 4.0, E = 30000.0, nu = 0.25;

core::State solveTip(const std::string& force, const std::string& moment, const std::string& name) {
  auto p = test::problemFromXml(test::cantileverXml(L, b, h, E, nu, 10, force, moment, 1));
  const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), name);
  EXPECT_TRUE(r.report.completed) << r.report.failure;
  return r.finalState;
}

}  // namespace

namespace {
// A contribution that is not in the model: the compliance of everything.
struct Nothing : core::Contribution {
  std::string name() const override { return "nothing"; }
  void connectivity(const OwnsDof&, std::vector<std::vector<core::GlobalDof>>&) const override {}
  void evaluate(const core::State&, const OwnsDof&, core::AssemblySink&, bool) const override {}
};
}  // namespace

TEST(StructureCompliance, CantileverTipMatchesEulerBernoulliAndAFreeBeamIsSingular) {
  // v^T K^-1 v for unit tip loads (a force along Z, a moment about Z, a force along X): L^3 / (3 E Iy),
  // L / (E Iz), L / (E A); a force and a moment together: the sum plus twice their coupling L^2 / (2 E Iz).
  auto p = test::problemFromXml(test::cantileverXml(L, b, h, E, nu, 10, "0,0,0", "0,0,0", 1));
  const auto cs = elements::CrossSection::rectangle(b, h);
  const int tip = 10;
  auto load = [&](std::vector<std::pair<int, double>> entries) {
    core::SparseLoad v;
    for (const auto& [k, x] : entries) {
      v.dofs.push_back(core::GlobalDof(core::kDofsPerNode) * tip + k);
      v.values.push_back(x);
    }
    return v;
  };
  const auto c =
      core::structureCompliance(p.model, Nothing{}, p.model.initial,
                                {load({{2, 1.0}}), load({{5, 1.0}}), load({{0, 1.0}}), load({{1, 1.0}, {5, 1.0}})});
  const double EIy = E * cs.inertiaY(), EIz = E * cs.inertiaZ();
  const double expected[4] = {L * L * L / (3 * EIy), L / EIz, L / (E * cs.area()),
                              L * L * L / (3 * EIz) + L / EIz + L * L / EIz};
  for (int i = 0; i < 4; ++i) {
    std::printf("tip load %d: compliance %.9g, closed form %.9g\n", i, c[i], expected[i]);
    EXPECT_NEAR(c[i], expected[i], 1e-9 * expected[i]) << i;
  }
  p.model.supports.clear();
  try {
    core::structureCompliance(p.model, Nothing{}, p.model.initial, {load({{2, 1.0}})});
    ADD_FAILURE() << "a beam without supports has a compliance";
  } catch (const std::runtime_error& e) {
    std::printf("%s\n", e.what());
    EXPECT_NE(std::string(e.what()).find("singular"), std::string::npos) << e.what();
  }
}

TEST(LinearCantilever, TipValuesMatchEulerBernoulliClosedForms) {
  const auto cs = elements::CrossSection::rectangle(b, h);
  const double Iy = cs.inertiaY(), Iz = cs.inertiaZ(), A = cs.area(), J = cs.torsionConstant();
  const double G = E / (2 * (1 + nu));
  const int tip = 10;
  const double P = 1e-4 * 3 * E * Iz / (L * L);  // deflection 1e-4 L in the weaker plane
  {
    const auto s = solveTip("0,0," + test::num(P), "0,0,0", "bend_z");
    const double w = P * L * L * L / (3 * E * Iy), th = P * L * L / (2 * E * Iy);
    EXPECT_NEAR(s.displacement(tip)[2], w, 1e-6 * w);
    EXPECT_NEAR(s.rotationVector[tip][1], -th, 1e-6 * th);  // +z deflection turns the axis about -y
  }
  {
    const auto s = solveTip("0," + test::num(P) + ",0", "0,0,0", "bend_y");
    const double w = P * L * L * L / (3 * E * Iz), th = P * L * L / (2 * E * Iz);
    EXPECT_NEAR(s.displacement(tip)[1], w, 1e-6 * w);
    EXPECT_NEAR(s.rotationVector[tip][2], th, 1e-6 * th);
  }
  {
    const double N = 1e-4 * E * A;
    const auto s = solveTip(test::num(N) + ",0,0", "0,0,0", "axial");
    const double u = N * L / (E * A);
    EXPECT_NEAR(s.displacement(tip)[0], u, 1e-6 * u);
  }
  {
    const double T = 1e-4 * G * J / L;
    const auto s = solveTip("0,0,0", test::num(T) + ",0,0", "torsion");
    const double phi = T * L / (G * J);
    EXPECT_NEAR(s.rotationVector[tip][0], phi, 1e-6 * phi);
  }
}

TEST(LinearCantilever, ALoadWhoseForcesUnderflowWhenSquaredIsSolvedNotTakenForEquilibrium) {
  // A tip force of 1e-200: the residual's entries square to 1e-400, below the smallest double, so a
  // plain 2-norm of the first residual is 0 and every step passed for exact equilibrium at
  // iteration 0 (no solve, zero displacement). The tip deflection is P L^3 / (3 E Iy).
  const auto cs = elements::CrossSection::rectangle(b, h);
  const double P = 1e-200;
  auto p = test::problemFromXml(test::cantileverXml(L, b, h, E, nu, 10, "0,0," + test::num(P), "0,0,0", 1));
  const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "tiny_load");
  ASSERT_TRUE(r.report.completed) << r.report.failure;
  const double w = P * L * L * L / (3 * E * cs.inertiaY());
  std::printf("tip deflection %.9e, closed form %.9e, Newton iterations %d\n", r.finalState.displacement(10)[2], w,
              r.report.newtonIterations);
  EXPECT_GE(r.report.newtonIterations, 1);
  EXPECT_NEAR(r.finalState.displacement(10)[2], w, 1e-6 * w);
}

TEST(StrainCheck, EndMomentWarnsExactlyWhenTheBendingStrainCrossesFivePercent) {
  // An end moment M bends the cantilever to the uniform curvature M / (E Iy) (the roll-up below), so
  // its fibres at z = +-h/2 strain by M h / (2 E Iy); at load factor T by T times that. M5 is the
  // moment of 5 % (BeamSet::kStrainLimit). 0.95 M5 stays below at T = 1: no warning. 1.3 M5 in 20
  // increments first exceeds 5 % at the first T = k / 20 with 1.3 T > 1: T = 0.8 (0.75 gives 4.9 %).
  // The same for a tip force N along the axis: axial strain T N / (E A).
  const double Iy = elements::CrossSection::rectangle(b, h).inertiaY(), A = b * h;
  const double M5 = elements::BeamSet::kStrainLimit * 2 * E * Iy / h, N5 = elements::BeamSet::kStrainLimit * E * A;
  const int n = 20;
  double firstT = 0.0;
  for (int k = 1; k <= n; ++k)
    if (1.3 * k / double(n) > 1.0) {
      firstT = k / double(n);
      break;
    }
  struct Case {
    std::string name, force, moment, kind;
    bool warns;
  };
  const std::vector<Case> cases = {{"bending_below", "0,0,0", "0," + test::num(-0.95 * M5) + ",0", "bending", false},
                                   {"bending_above", "0,0,0", "0," + test::num(-1.3 * M5) + ",0", "bending", true},
                                   {"axial_below", test::num(0.95 * N5) + ",0,0", "0,0,0", "axial", false},
                                   {"axial_above", test::num(1.3 * N5) + ",0,0", "0,0,0", "axial", true}};
  for (const Case& c : cases) {
    auto p = test::problemFromXml(test::cantileverXml(L, b, h, E, nu, 10, c.force, c.moment, n));
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "strain_" + c.name);
    ASSERT_TRUE(r.report.completed) << c.name << ": " << r.report.failure;
    // The strain the check measures at T = 1, against the closed form.
    const auto& beams = dynamic_cast<const elements::BeamSet&>(*p.model.contributions[0]);
    double strain = 0.0;
    for (const auto& e : beams.elements()) {
      const auto s = elements::BeamSet::elementStrains(e, beams.beams()[0].section, r.finalState);
      strain = std::max(strain, c.kind == "axial" ? s.axial : s.bending);
    }
    const double expected = (c.warns ? 1.3 : 0.95) * elements::BeamSet::kStrainLimit;
    std::printf("%s: strain at T = 1 %.9f, closed form %.9f, %zu warnings\n", c.name.c_str(), strain, expected,
                r.report.warnings.size());
    for (const auto& w : r.report.warnings) std::printf("  %s\n", w.c_str());
    EXPECT_NEAR(strain, expected, 1e-6 * expected) << c.name;
    ASSERT_EQ(r.report.warnings.size(), c.warns ? 1u : 0u) << c.name;
    if (c.warns) {
      const std::string& w = r.report.warnings[0];
      char at[64];
      std::snprintf(at, sizeof at, "from T = %g (%s strain", firstT, c.kind.c_str());
      EXPECT_NE(w.find("beam \"b\""), std::string::npos) << w;
      EXPECT_NE(w.find(at), std::string::npos) << "expected \"" << at << "\" in: " << w;
    }
  }
}

TEST(RollUp, EndMomentRollsCantileverIntoFullCircle) {
  const double EI = E * 1.0 / 12.0;  // 1 x 1 section
  const double M = 2 * std::acos(-1.0) * EI / L;
  auto p = test::problemFromXml(test::cantileverXml(L, 1.0, 1.0, E, 0.3, 20, "0,0,0", "0," + test::num(-M) + ",0", 20,
                                                    R"XML(<ParameterList name="Nonlinear Solver">
      <Parameter name="Residual Tolerance" type="double" value="1e-13"/>
      <Parameter name="Increment Tolerance" type="double" value="1e-12"/></ParameterList>)XML"));
  const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "rollup");
  ASSERT_TRUE(r.report.completed) << r.report.failure;
  EXPECT_EQ(r.report.steps, 20);  // no step was cut
  int maxIt = 0;
  for (const auto& s : r.steps) {
    EXPECT_EQ(s.cutLevel, 0);
    maxIt = std::max(maxIt, s.iterations);
  }
  const auto& s = r.finalState;
  const int tip = 20;
  std::printf("tip displacement (%.3e, %.3e, %.3e), rotation about y %.12f (2 pi = %.12f), max Newton %d\n",
              s.displacement(tip)[0], s.displacement(tip)[1], s.displacement(tip)[2], s.rotationVector[tip][1],
              2 * std::acos(-1.0), maxIt);
  // Tip back at the clamp: the 20 equal chords of the deformed beam close a regular polygon exactly.
  EXPECT_NEAR(s.position[tip][0], 0.0, 1e-9 * L);
  EXPECT_NEAR(s.position[tip][1], 0.0, 1e-9 * L);
  EXPECT_NEAR(s.position[tip][2], 0.0, 1e-9 * L);
  EXPECT_NEAR(s.rotationVector[tip][1], -2 * std::acos(-1.0), 1e-9);
  // Mid node: across the polygon, diameter = chord / sin(pi / n).
  const double chord = L / 20;
  EXPECT_NEAR(s.position[10][2], chord / std::sin(std::acos(-1.0) / 20), 1e-9 * L);
}

// The increment test meets its round-off floor: the roll-up's moment held (a Load Curve rising by
// 1e-6 over T = 0.5 .. 1) with Increment Tolerance 1e-15, below what ||du|| can reach (measured: it
// stops falling at 1e-14 .. 5e-14 with the residual at its own floor). Before, each step of the held
// phase iterated to Maximum Iterations and was cut until the run stopped incomplete at T = 0.5; now an
// increment that stopped falling with the residual test met is at its floor. The answer is the one of
// the default tolerance (1e-8), to 1e-10 of L: both are the same equilibrium.
TEST(Newton, AnIncrementAtItsRoundOffFloorIsAcceptedOnceTheResidualTestHolds) {
  const double EI = E * 1.0 / 12.0;
  const double M = 2 * std::acos(-1.0) * EI / L;
  const auto solve = [&](double incrementTolerance, int maxIterations, const std::string& name) {
    auto deck = Teuchos::getParametersFromXmlString(
        test::cantileverXml(L, 1.0, 1.0, E, 0.3, 20, "0,0,0", "0," + test::num(-M) + ",0", 20));
    deck->sublist("Loads").sublist("tip").set(
        "Load Curve", Teuchos::Array<double>(std::vector<double>{0.0, 0.0, 0.5, 1.0, 1.0, 1.000001}));
    deck->sublist("Nonlinear Solver").set("Increment Tolerance", incrementTolerance);
    deck->sublist("Nonlinear Solver").set("Maximum Iterations", maxIterations);
    auto p = input::buildProblem(*deck, name);
    return test::runQuiet(p, Tpetra::getDefaultComm(), name);
  };
  const auto tight = solve(1e-15, 25, "floor_tight"), plain = solve(1e-8, 25, "floor_plain");
  ASSERT_TRUE(tight.report.completed) << tight.report.failure;
  ASSERT_TRUE(plain.report.completed) << plain.report.failure;
  for (const auto& s : tight.steps) EXPECT_EQ(s.cutLevel, 0) << "T = " << s.T;
  for (int n = 0; n <= 20; ++n)
    for (int d = 0; d < 3; ++d)
      EXPECT_NEAR(tight.finalState.position[n][d], plain.finalState.position[n][d], 1e-10 * L) << n << " " << d;
  // A failure names the test that failed with both norms: one Newton iteration cannot converge.
  const auto failed = solve(1e-8, 1, "floor_failed");
  ASSERT_FALSE(failed.report.completed);
  for (const char* part : {"Maximum Iterations", "the residual test fails", "Residual Tolerance x",
                           "the increment test fails", "Increment Tolerance x"})
    EXPECT_NE(failed.report.failure.find(part), std::string::npos) << part << " in: " << failed.report.failure;
  std::printf("failure message: %s\n", failed.report.failure.c_str());
}

TEST(Newton, ConvergesQuadraticallyNearTheSolution) {
  // Large deflection: tip force with P L^2 / (E I) = 5 (tip deflection ~0.7 L, rotations ~1 rad).
  const double EI = E * b * h * h * h / 12.0;
  const double P = 5.0 * EI / (L * L);
  auto p = test::problemFromXml(test::cantileverXml(L, b, h, E, nu, 10, "0,0," + test::num(P), "0,0,0", 5));
  auto comm = Tpetra::getDefaultComm();
  const auto r = test::runQuiet(p, comm, "quadratic");
  ASSERT_TRUE(r.report.completed) << r.report.failure;
  for (const auto& step : r.steps) {
    std::printf("load step %d residuals:", step.step);
    for (const auto& it : step.history) std::printf(" %.1e", it.residualNorm);
    std::printf("\n");
  }
  // Near the solution: from the converged state at T = 1, solve for T = 1.01 (a 1 % load change,
  // a perturbation along the soft bending mode). Measured: how the number of correct digits grows,
  // p = log(eps_k+1) / log(eps_k) with eps_k = ||du_k|| / ||du_0||, which is 2 for quadratic
  // convergence (digits double each iteration). Counted once eps_k < 1e-2 (the asymptotic range)
  // and while ||du_k+1|| > 1e-12 (round-off).
  auto linear = core::makeLinearSolver(p.linearSolver, {p.model.initial.numDofs(), 0, comm->getSize()});
  core::StaticSolver solver(comm, p.model, p.solver, *linear);
  core::State end;
  const auto trace = solver.iterateFrom(r.finalState, 1.0, 1.01, end);
  std::printf("near the solution: residuals");
  for (const auto& it : trace.history) std::printf(" %.2e", it.residualNorm);
  std::printf("\n                   increments");
  for (const auto& it : trace.history) std::printf(" %.2e", it.incrementNorm);
  std::printf("\n                   orders    ");
  int measured = 0;
  const double du0 = trace.history[0].incrementNorm;
  for (std::size_t k = 1; k + 1 < trace.history.size(); ++k) {
    const double ek = trace.history[k].incrementNorm / du0, next = trace.history[k + 1].incrementNorm;
    if (next < 1e-12) break;
    if (ek >= 1e-2) continue;
    const double order = std::log(next / du0) / std::log(ek);
    std::printf(" %.3f", order);
    EXPECT_GT(order, 1.8);
    ++measured;
  }
  std::printf("\n");
  EXPECT_GE(measured, 1);
}

namespace {
// An L-frame: arm 1 along X from the origin (clamped there) to (L1, 0, 0), arm 2 along Y from that
// point to (L1, L2, 0), the two beams given separately with a common end point (so joined there),
// 10 elements each; a tip force at arm 2's end. `extra` adds sublists (e.g. Contact).
std::string lFrame(double L1, double L2, const std::string& force, const std::string& extra = "") {
  const std::string section = R"X(<ParameterList name="Section"><Parameter name="Width" type="double" value=")X" +
                              test::num(b) + R"X("/><Parameter name="Height" type="double" value=")X" + test::num(h) +
                              R"X("/></ParameterList><ParameterList name="Material">)X"
                              R"X(<Parameter name="Young's Modulus" type="double" value=")X" +
                              test::num(E) + R"X("/><Parameter name="Poisson's Ratio" type="double" value=")X" +
                              test::num(nu) +
                              R"X("/></ParameterList><Parameter name="Elements" type="int" value="10"/>)X";
  return R"X(<ParameterList name="BeamContact"><ParameterList name="Beams">
    <ParameterList name="arm 1"><Parameter name="Start" type="Array(double)" value="{0, 0, 0}"/>
      <Parameter name="End" type="Array(double)" value="{)X" +
         test::num(L1) + R"X(, 0, 0}"/>)X" + section + R"X(</ParameterList>
    <ParameterList name="arm 2"><Parameter name="Start" type="Array(double)" value="{)X" +
         test::num(L1) + R"X(, 0, 0}"/>
      <Parameter name="End" type="Array(double)" value="{)X" +
         test::num(L1) + ", " + test::num(L2) + R"X(, 0}"/>)X" + section + R"X(</ParameterList></ParameterList>
  <ParameterList name="Supports"><ParameterList name="clamp"><Parameter name="Beam" type="string" value="arm 1"/>
    <Parameter name="Node" type="string" value="start"/></ParameterList></ParameterList>
  <ParameterList name="Loads"><ParameterList name="tip"><Parameter name="Beam" type="string" value="arm 2"/>
    <Parameter name="Node" type="string" value="end"/><Parameter name="Force" type="Array(double)" value="{)X" +
         force +
         R"X(}"/><Parameter name="Moment" type="Array(double)" value="{0, 0, 0}"/></ParameterList></ParameterList>
  <ParameterList name="Load Stepping"><Parameter name="Number of Increments" type="int" value="1"/></ParameterList>)X" +
         extra + R"X(</ParameterList>)X";
}
}  // namespace

// Linear closed forms of the L-frame (Euler-Bernoulli, Saint-Venant torsion). Loads are small
// (rotations about 1e-7): here geometric nonlinearity is first order in the rotation (arm 2 swings
// with arm 1's end, moving the load's line by theta L2), about 1e-4 at rotations of 1e-4.
//  - out of plane (P along Z): w = P L2^3 / (3 E Iy) + P L1^3 / (3 E Iy) + P L2^2 L1 / (G J)
//    (arm 2 bent; arm 1 bent by P and twisted by P L2, the twist carrying arm 2 round);
//  - in plane (P along Y, arm 2's axis): v = P L1^3 / (3 E Iz) + P L2 / (E A).
// Without the joint the arms would not be connected (arm 2 free: the deck would be refused).
TEST(Joints, LFrameOfTwoJoinedBeamsMatchesTheLinearClosedForms) {
  const auto cs = elements::CrossSection::rectangle(b, h);
  const double Iy = cs.inertiaY(), Iz = cs.inertiaZ(), A = cs.area(), J = cs.torsionConstant();
  const double G = E / (2 * (1 + nu)), L1 = 100.0, L2 = 60.0;
  {
    const double P = 1e-7 * 3 * E * Iy / (L2 * L2);
    auto p = test::problemFromXml(lFrame(L1, L2, "0, 0, " + test::num(P)), "lframe");
    EXPECT_EQ(p.model.initial.numNodes(), 21);  // 2 x 11 nodes, one shared
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "lframe_z");
    ASSERT_TRUE(r.report.completed) << r.report.failure;
    const int tip = p.beams->beams()[1].nodes.back();
    const double w =
        P * std::pow(L2, 3) / (3 * E * Iy) + P * std::pow(L1, 3) / (3 * E * Iy) + P * L2 * L2 * L1 / (G * J);
    std::printf("L-frame, out of plane: w = %.10e (closed form %.10e)\n", r.finalState.displacement(tip)[2], w);
    EXPECT_NEAR(r.finalState.displacement(tip)[2], w, 1e-6 * w);
  }
  {
    const double P = 1e-7 * 3 * E * Iz / (L1 * L1);
    auto p = test::problemFromXml(lFrame(L1, L2, "0, " + test::num(P) + ", 0"), "lframe");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "lframe_y");
    ASSERT_TRUE(r.report.completed) << r.report.failure;
    const int tip = p.beams->beams()[1].nodes.back();
    const double v = P * std::pow(L1, 3) / (3 * E * Iz) + P * L2 / (E * A);
    std::printf("L-frame, in plane: v = %.10e (closed form %.10e)\n", r.finalState.displacement(tip)[1], v);
    EXPECT_NEAR(r.finalState.displacement(tip)[1], v, 1e-6 * v);
  }
}

// The joined arms declared in contact with each other (All Pairs): the elements at the joint share
// a node and are no contact candidates, so the deck is not refused as overlapping at the start and
// the run completes with no contact point (before: "overlap at the start").
TEST(Joints, JoinedBeamsDoNotContactAtTheirJoint) {
  const std::string contact = R"X(<ParameterList name="Contact"><Parameter name="All Pairs" type="bool" value="true"/>
    <Parameter name="Friction Coefficient" type="double" value="0.0"/>
    <ParameterList name="Enforcement"><Parameter name="Type" type="string" value="Lagrange Multiplier"/></ParameterList>
    </ParameterList>)X";
  auto p = test::problemFromXml(lFrame(100.0, 60.0, "0, 0, 0.01", contact), "lframe_contact");
  const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "lframe_contact");
  ASSERT_TRUE(r.report.completed) << r.report.failure;
  int active = 0;
  for (const auto& [key, pt] : p.contact->points()) active += pt.result.active;
  EXPECT_EQ(active, 0);
}

// A beam joined to nothing that holds it is named with its structure: arm 2 attached to a free arm 1.
TEST(Joints, AnUnheldStructureIsNamedWithItsBeams) {
  Teuchos::ParameterList deck = input::parseParameterXml(lFrame(100.0, 60.0, "0, 0, 0.01"), "L-frame");
  input::setAtPath(deck, "Supports/clamp/Fixed", std::string("ux uy uz"));  // a pin: rotations free
  try {
    input::buildProblem(deck, "lframe_free");
    ADD_FAILURE() << "a structure free to rotate about the pinned end was accepted";
  } catch (const core::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("the beams joined to \"arm 1\" (2 beams sharing nodes) is not held"),
              std::string::npos)
        << e.what();
  }
}

namespace {
// The 45-degree bend (Bathe and Bolourchi 1979): a cantilever arc of radius 100 through 45 degrees in
// the x-z plane, x0(t) = R sin t e_x + R (1 - cos t) e_z, t in [0, pi/4], clamped at t = 0, unit
// square section, E = 1e7, nu = 0, J = 1/6 (GJ = EI = 8.333e5, as the benchmark states), tip force
// 600 along +y in 60 increments.
std::string bend45(int elements) {
  return R"X(<ParameterList name="BeamContact"><ParameterList name="Beams"><ParameterList name="bend">
    <ParameterList name="Arc"><Parameter name="Centre" type="Array(double)" value="{0, 0, 100}"/>
      <Parameter name="Radius" type="double" value="100"/><Parameter name="Normal" type="Array(double)" value="{0, -1, 0}"/>
      <Parameter name="Reference Direction" type="Array(double)" value="{0, 0, -1}"/>
      <Parameter name="Start Angle" type="double" value="0"/><Parameter name="End Angle" type="double" value="45"/></ParameterList>
    <Parameter name="Elements" type="int" value=")X" +
         std::to_string(elements) + R"X("/>
    <ParameterList name="Section"><Parameter name="Width" type="double" value="1"/><Parameter name="Height" type="double" value="1"/>
      <Parameter name="Torsion Constant" type="double" value="0.16666666666666666"/></ParameterList>
    <ParameterList name="Material"><Parameter name="Young's Modulus" type="double" value="1e7"/>
      <Parameter name="Poisson's Ratio" type="double" value="0"/></ParameterList></ParameterList></ParameterList>
  <ParameterList name="Supports"><ParameterList name="clamp"><Parameter name="Beam" type="string" value="bend"/>
    <Parameter name="Node" type="string" value="start"/></ParameterList></ParameterList>
  <ParameterList name="Loads"><ParameterList name="tip"><Parameter name="Beam" type="string" value="bend"/>
    <Parameter name="Node" type="string" value="end"/><Parameter name="Force" type="Array(double)" value="{0, 600, 0}"/>
    <Parameter name="Moment" type="Array(double)" value="{0, 0, 0}"/></ParameterList></ParameterList>
  <ParameterList name="Load Stepping"><Parameter name="Number of Increments" type="int" value="60"/></ParameterList>
</ParameterList>)X";
}
}  // namespace

// Published tip displacements (dx, dy, dz) at P = 600: Bathe and Bolourchi (1979, 8 elements)
// (-23.5, 53.4, -13.4) and Simo and Vu-Quoc (1986) (-23.48, 53.37, -13.50) (tip position
// (47.23, 15.79, 53.37) in their axes); as cited by the OpenFAST r-test BeamDyn case and the OpenSees
// gallery. The arc's geometry: the first node at the origin, the tip at (70.71, 0, 29.29). Asserted:
// convergence with elements (successive differences fall by at least 3; measured 4.1 and 4.0, second
// order), and the finest mesh within 1 % of Simo and Vu-Quoc in each component (measured 0.33 %,
// 0.19 %, 0.77 %; the published values differ by up to 0.8 % among themselves).
TEST(CurvedBeams, FortyFiveDegreeBendConvergesToThePublishedTipDisplacement) {
  std::vector<std::array<double, 3>> d;
  for (int n : {8, 16, 32, 64}) {
    auto p = test::problemFromXml(bend45(n), "bend45");
    const int tip = p.beams->beams()[0].nodes.back();
    EXPECT_NEAR(p.model.initial.reference[tip][0], 100 * std::sqrt(0.5), 1e-9);
    EXPECT_NEAR(p.model.initial.reference[tip][2], 100 * (1 - std::sqrt(0.5)), 1e-9);
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "bend45");
    ASSERT_TRUE(r.report.completed) << n << " elements: " << r.report.failure;
    const auto u = r.finalState.displacement(tip);
    d.push_back({u[0], u[1], u[2]});
    std::printf("45-degree bend, %2d elements: tip displacement (%.4f, %.4f, %.4f), %d Newton iterations\n", n, u[0],
                u[1], u[2], r.report.newtonIterations);
  }
  for (std::size_t k = 2; k < d.size(); ++k) {
    double before = 0, now = 0;
    for (int c = 0; c < 3; ++c) {
      before = std::max(before, std::abs(d[k - 1][c] - d[k - 2][c]));
      now = std::max(now, std::abs(d[k][c] - d[k - 1][c]));
    }
    std::printf("  refinement %zu: largest change %.3e (before %.3e, ratio %.2f)\n", k, now, before, before / now);
    EXPECT_GT(before / now, 3.0);
  }
  const auto& f = d.back();
  EXPECT_NEAR(f[0], -23.48, 0.01 * 23.48);
  EXPECT_NEAR(f[1], 53.37, 0.01 * 53.37);
  EXPECT_NEAR(f[2], -13.50, 0.01 * 13.50);
}

// Where the geometries put their nodes: a helix (radius 5, pitch 20, 1.5 turns about +x from the
// origin, first node towards +y), a polyline with a kink (its corner is a node), and the section
// orientation of a helix (its axis, across every element).
TEST(CurvedBeams, HelixAndPolylinePlaceTheirNodes) {
  const std::string tail = R"X(<ParameterList name="Section"><Parameter name="Width" type="double" value="1"/>
      <Parameter name="Height" type="double" value="1"/></ParameterList><ParameterList name="Material">
      <Parameter name="Young's Modulus" type="double" value="1e7"/><Parameter name="Poisson's Ratio" type="double" value="0.3"/>
      </ParameterList></ParameterList>)X";
  const std::string deck = R"X(<ParameterList name="BeamContact"><ParameterList name="Beams">
    <ParameterList name="wire"><ParameterList name="Helix"><Parameter name="Axis Point" type="Array(double)" value="{0, 0, 0}"/>
      <Parameter name="Axis Direction" type="Array(double)" value="{2, 0, 0}"/><Parameter name="Radius" type="double" value="5"/>
      <Parameter name="Pitch" type="double" value="20"/><Parameter name="Turns" type="double" value="1.5"/>
      <Parameter name="Reference Direction" type="Array(double)" value="{0, 1, 0}"/></ParameterList>
      <Parameter name="Elements" type="int" value="48"/>)X" +
                           tail + R"X(
    <ParameterList name="rod"><Parameter name="Points" type="Array(double)" value="{0, 20, 0, 10, 20, 0, 10, 30, 5}"/>
      <Parameter name="Elements" type="int" value="4"/>)X" +
                           tail + R"X(</ParameterList>
  <ParameterList name="Supports"><ParameterList name="w"><Parameter name="Beam" type="string" value="wire"/>
    <Parameter name="Node" type="string" value="start"/></ParameterList>
    <ParameterList name="r"><Parameter name="Beam" type="string" value="rod"/><Parameter name="Node" type="string" value="start"/>
    </ParameterList></ParameterList></ParameterList>)X";
  auto p = test::problemFromXml(deck, "geometries");
  const auto& X = p.model.initial.reference;
  const auto& wire = p.beams->beams()[0];
  ASSERT_EQ(wire.nodes.size(), 49u);
  // Node k at angle t = 3 pi k / 48: (20 t / (2 pi), 5 cos t, 5 sin t) (right hand about +x from +y).
  for (std::size_t k = 0; k < wire.nodes.size(); ++k) {
    const double t = 3.0 * std::acos(-1.0) * k / 48.0;
    EXPECT_NEAR(X[wire.nodes[k]][0], 20.0 * t / (2 * std::acos(-1.0)), 1e-12);
    EXPECT_NEAR(X[wire.nodes[k]][1], 5.0 * std::cos(t), 1e-12);
    EXPECT_NEAR(X[wire.nodes[k]][2], 5.0 * std::sin(t), 1e-12);
  }
  EXPECT_NEAR(wire.sectionY[0], 1.0, 1e-15);
  const auto& rod = p.beams->beams()[1];
  ASSERT_EQ(rod.nodes.size(), 9u);  // 4 elements on each of 2 segments
  EXPECT_NEAR(X[rod.nodes[4]][0], 10.0, 1e-12);
  EXPECT_NEAR(X[rod.nodes[4]][1], 20.0, 1e-12);
  EXPECT_NEAR(X[rod.nodes[8]][2], 5.0, 1e-12);
}

// A pinned joint passes force but no moment. The L-frame with arm 2 pinned to arm 1's tip, arm 2's far
// end held in translation and against spinning about its own axis (ux uy uz ry), a force P along -Z at
// arm 2's middle: arm 2 is a simply supported span on one rigid and one elastic support (arm 1's tip,
// compliance L1^3 / (3 E Iy)), statically determinate: each end carries P / 2, arm 1 no torsion, and
//   w_mid = P L2^3 / (48 E Iy) + (1/2) (P/2) L1^3 / (3 E Iy),   joint force P / 2.
// The same frame with a rigid joint is stiffer (arm 1's torsion and the joint moment help).
TEST(Joints, PinnedJointPassesForceButNoMoment) {
  const auto cs = elements::CrossSection::rectangle(b, h);
  const double Iy = cs.inertiaY(), L1 = 100.0, L2 = 60.0, P = 1e-7 * E * Iy / (L1 * L1);
  double w[3] = {0, 0, 0};
  // Variants: rigid joint, pinned joint, pinned joint with All Pairs contact (the elements meeting at
  // the pin are no contact candidates, as if they shared the node: same answer, no contact point).
  for (int variant = 0; variant < 3; ++variant) {
    const bool pinned = variant > 0;
    Teuchos::ParameterList deck = input::parseParameterXml(lFrame(L1, L2, "0, 0, 0"), "L-frame");
    input::replaceAtPath(deck, "Loads/tip/Node", std::string("middle"));
    input::replaceAtPath(deck, "Loads/tip/Force", Teuchos::Array<double>(std::vector<double>{0, 0, -P}));
    Teuchos::ParameterList& far = input::sublistAtPath(deck, "Supports/far");
    far.set("Beam", std::string("arm 2"));
    far.set("Node", std::string("end"));
    far.set("Fixed", std::string("ux uy uz ry"));
    Teuchos::ParameterList& joint = input::sublistAtPath(deck, "Joints/corner");
    joint.set("Beam A", std::string("arm 2"));
    joint.set("Node A", std::string("start"));
    joint.set("Beam B", std::string("arm 1"));
    joint.set("Node B", std::string("end"));
    joint.set("Type", std::string(pinned ? "Pinned" : "Rigid"));
    if (variant == 2) {
      Teuchos::ParameterList& contact = deck.sublist("Contact");
      contact.set("All Pairs", true);
      contact.set("Friction Coefficient", 0.0);
      contact.sublist("Enforcement").set("Type", std::string("Penalty"));
      contact.sublist("Enforcement").sublist("Penalty").set("Normal Penalty Parameter", 1e4);
      contact.sublist("Enforcement").sublist("Penalty").set("Tangential Penalty Parameter", 1e3);
    }
    auto p = input::buildProblem(deck, "lframe_pin");
    EXPECT_EQ(p.model.initial.numNodes(), pinned ? 22 : 21);
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "lframe_pin");
    ASSERT_TRUE(r.report.completed) << r.report.failure;
    const int mid = p.beams->beams()[1].nodes[5];
    w[variant] = -r.finalState.displacement(mid)[2];
    if (variant == 2) {
      ASSERT_TRUE(p.contact);
      EXPECT_TRUE(p.contact->points().empty()) << "the arms were found in contact at their pin";
      std::printf("pinned L-frame with All Pairs contact: w_mid = %.10e (without contact %.10e)\n", w[2], w[1]);
      EXPECT_NEAR(w[2], w[1], 1e-12 * w[1]);
    } else if (pinned) {
      const double expected = P * std::pow(L2, 3) / (48 * E * Iy) + 0.5 * (P / 2) * std::pow(L1, 3) / (3 * E * Iy);
      const auto& pins = dynamic_cast<const elements::PinnedJoints&>(*p.model.contributions[1]);
      const auto F = pins.force(r.finalState, 0);
      std::printf("pinned L-frame: w_mid = %.10e (closed form %.10e), joint force (%.3e, %.3e, %.10e) (P/2 = %.10e)\n",
                  w[1], expected, F[0], F[1], F[2], P / 2);
      EXPECT_NEAR(w[1], expected, 1e-6 * expected);
      EXPECT_NEAR(std::abs(F[2]), P / 2, 1e-6 * P);
      // No moment: arm 1's tip does not twist (rotation about X), though it bends.
      const int tip1 = p.beams->beams()[0].nodes.back();
      EXPECT_LT(std::abs(r.finalState.rotationVector[tip1][0]), 1e-6 * std::abs(r.finalState.rotationVector[tip1][1]));
    }
  }
  std::printf("rigid joint: w_mid = %.10e (pinned %.10e)\n", w[0], w[1]);
  EXPECT_LT(w[0], w[1]);
}

// A beam pinned to a held one, with no support of its own, can still turn about the pin: refused,
// naming the beam and the axis through the pin.
TEST(Joints, APinnedBeamMustHoldItsOwnRotation) {
  Teuchos::ParameterList deck = input::parseParameterXml(lFrame(100.0, 60.0, "0, 0, 0.001"), "L-frame");
  Teuchos::ParameterList& joint = input::sublistAtPath(deck, "Joints/corner");
  joint.set("Beam A", std::string("arm 2"));
  joint.set("Node A", std::string("start"));
  joint.set("Beam B", std::string("arm 1"));
  joint.set("Node B", std::string("end"));
  joint.set("Type", std::string("Pinned"));
  try {
    input::buildProblem(deck, "lframe_unheld_pin");
    ADD_FAILURE() << "a beam free to turn about its pin was accepted";
  } catch (const core::InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("beam \"arm 2\" is not held by its supports: it can rotate about the axis"), std::string::npos)
        << what;
    EXPECT_NE(what.find("through (100, 0, 0)"), std::string::npos) << what;
  }
}
