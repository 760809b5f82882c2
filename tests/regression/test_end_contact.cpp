// End contact: a column's free end face pressed onto a beam's side (the force from the two
// stiffnesses in series) and slid along it with friction (mu N), its tangent against central
// differences, an end driven through in one increment; end-to-end contact: two coaxial columns
// pressed end to end (their axial stiffnesses in series) and one slid across the other with
// friction. Each strategy, circular and rectangular sections, either beam as the pair's A.
#include <gtest/gtest.h>

#include <cmath>

#include "support/ContactDecks.hpp"

using namespace bc;
using namespace bc::test;

namespace {

// input/column_on_beam.xml with the strategy, 20 elements on the beam (the column at x = 45 stands
// on a node: the beam's cubic elements are exact there), circular or rectangular sections (beam 2 x 2,
// column 1 x 1), the pair's roles swapped if asked.
Deck columnDeck(const std::string& type, bool rectangles, bool swapped) {
  Deck d = inputDeck("column_on_beam.xml", type);
  input::replaceAtPath(d, "Beams/beam/Elements", 20);
  if (rectangles) squareSections(d, {{"beam", 2.0}, {"column", 1.0}});
  if (swapped) {
    input::replaceAtPath(d, "Contact/Pairs/end on beam/Beam A", std::string("column"));
    input::replaceAtPath(d, "Contact/Pairs/end on beam/Beam B", std::string("beam"));
  }
  return d;
}

// The closed form: the closing 0.01 over the column's L / (E A) and the beam's a^3 b^3 / (3 E I L^3)
// (clamped at both ends for bending, load at a = 45 of L = 100), and with Penalty the penalty's 1 / eps_N.
double columnForce(bool rectangles, double epsN) {
  const double area = rectangles ? 1.0 : M_PI * 0.25, inertia = rectangles ? 16.0 / 12.0 : M_PI / 4.0;
  const double column = 10.0 / (1e3 * area);
  const double beam = std::pow(45.0 * 55.0, 3) / (3.0 * 1e5 * inertia * 1e6);
  return 0.01 / (column + beam + (epsN > 0.0 ? 1.0 / epsN : 0.0));
}

struct EndForces {
  double normal = 0.0, tangential = 0.0;
  int active = 0, slipping = 0;
};
// The active end points' forces (end-to-end points if asked, end points on a beam's side otherwise).
EndForces endForces(const input::Problem& p, bool endToEnd = false) {
  EndForces f;
  for (const auto& [key, pt] : p.contact->points()) {
    if (!key.end() || key.endToEnd() != endToEnd || !pt.result.active) continue;
    ++f.active;
    f.normal += norm(pt.normalForce);
    f.tangential += norm(pt.tangentialForce);
    f.slipping += pt.result.slip[0] || pt.result.slip[1];
  }
  return f;
}

}  // namespace

TEST(EndContact, ColumnPressedOnABeamCarriesTheStiffnessesInSeries) {
  for (bool rect : {false, true})
    for (bool swapped : {false, true})
      for (const std::string type : {"Penalty", "Lagrange Multiplier", "Augmented Lagrange"}) {
        auto p = input::buildProblem(columnDeck(type, rect, swapped), "column");
        const auto r = runQuiet(p, Tpetra::getDefaultComm(), "column");
        ASSERT_TRUE(r.report.completed) << type << ": " << r.report.failure;
        const EndForces f = endForces(p);
        const double exact = columnForce(rect, type == "Penalty" ? 1e4 : 0.0);
        std::printf("column on a beam, %s, %s, A %s: N %.9f, closed form %.9f (%+.2e), Newton %d\n",
                    rect ? "rectangles" : "circles", type.c_str(), swapped ? "column" : "beam", f.normal, exact,
                    f.normal / exact - 1.0, r.report.newtonIterations);
        EXPECT_EQ(f.active, 1);
        EXPECT_NEAR(f.normal, exact, 1e-3 * exact) << type;
        EXPECT_TRUE(r.report.warnings.empty()) << r.report.warnings.front();
      }
}

// Slid along the beam: the column's top moves by (5, 0.3, -0.06) in 8 increments (slightly across); the end touches at
// T = 5/6 and slides along X by about 0.5 (more than the column's lateral stiffness 3 E I / L^3 =
// 0.147 lets friction hold: mu N / 0.147 = 0.27; rectangles 0.25, 0.24), crossing the beam's node at
// x = 50: every strategy, both sections, ends slipping with the applied tangential force mu N (1e-9) opposing the
// motion.
TEST(EndContact, EndSlidAlongABeamCarriesMuN) {
  for (bool rect : {false, true})
    for (const std::string type : {"Penalty", "Lagrange Multiplier", "Augmented Lagrange"}) {
      Deck d = columnDeck(type, rect, false);
      input::replaceAtPath(d, "Contact/Pairs/end on beam/Friction Coefficient", 0.3);
      // (the deck's Per Line law: an end point's friction is isotropic all the same)
      if (rect) input::setAtPath(d, "Contact/Friction Law", std::string("Per Line"));
      input::replaceAtPath(d, "Supports/column top/Displacement", vec("5.0, 0.3, -0.06"));
      input::replaceAtPath(d, "Load Stepping/Number of Increments", 8);
      auto p = input::buildProblem(d, "slide");
      const auto r = runQuiet(p, Tpetra::getDefaultComm(), "slide");
      ASSERT_TRUE(r.report.completed) << type << ": " << r.report.failure;
      const EndForces f = endForces(p);
      math::Vec3d ft{};
      for (const auto& [key, pt] : p.contact->points())
        if (key.end() && pt.result.active) ft = pt.tangentialForce;
      std::printf(
          "end slid along a beam, %s, %s: N %.9f, |F_T| %.9f, |F_T| / (mu N) - 1 %+.2e, F_T x %.6f, Newton %d\n",
          rect ? "rectangles" : "circles", type.c_str(), f.normal, f.tangential, f.tangential / (0.3 * f.normal) - 1.0,
          ft[0], r.report.newtonIterations);
      ASSERT_EQ(f.active, 1) << type;
      EXPECT_EQ(f.slipping, 1) << type;
      // (a unit multiplier applies a unit force: EndKinematics.UnitMultipliersApplyOrthonormalForcesOnB)
      EXPECT_NEAR(f.tangential, 0.3 * f.normal, 1e-9 * f.normal) << type;
      // the force on the column (the pair's B) opposes its slide along +X and +Y
      EXPECT_LT(ft[0], 0.0) << type;
      EXPECT_LT(ft[1], 0.0) << type;
      EXPECT_TRUE(r.report.warnings.empty()) << r.report.warnings.front();
    }
}

// The assembled contact tangent of an end point against central differences of the contact residual:
// the column pressed (converged at T = 1, mu = 0.3), then its nodes moved a little further in and
// turned (stick), or also along the beam by 0.02 (slip: the penalties' trial force eps_T 0.02 = 20
// is far above mu N = 0.06), each strategy, both sections.
TEST(EndContact, TangentMatchesCentralDifferences) {
  for (bool rect : {false, true})
    for (double dx : {0.0, 0.02})
      for (const std::string type : {"Penalty", "Lagrange Multiplier", "Augmented Lagrange"}) {
        Deck d = columnDeck(type, rect, false);
        input::replaceAtPath(d, "Contact/Pairs/end on beam/Friction Coefficient", 0.3);
        auto p = input::buildProblem(d, "end_tangent");
        p.solver.loadFactors = {0.8, 1.0};
        const auto run = runQuiet(p, Tpetra::getDefaultComm(), "end_tangent");
        ASSERT_TRUE(run.report.completed) << run.report.failure;
        core::State s = run.finalState;
        for (int n : p.beams->beams()[1].nodes)
          s.applyNodeIncrement(n, std::array<double, 6>{dx, 1e-4 + 0.5 * dx, -1e-3, 1e-3, -2e-3, 0}.data());
        p.contact->prepareIteration(s);
        int ends = 0, slipping = 0;
        for (const auto& [key, pt] : p.contact->points()) {
          if (!key.end()) continue;
          ++ends;
          const auto k = p.contact->kinematics(pt, s);
          std::vector<double> f(constraints::kPairDofs + 3, 0.0);
          const auto r =
              p.contact->enforcer().evaluate(p.contact->strategyView(pt, k, s), *pt.state, f.data(), nullptr);
          slipping += r.slip[0] || r.slip[1];
        }
        ASSERT_EQ(ends, 1) << type;
        EXPECT_EQ(slipping, dx > 0.0 ? 1 : 0) << type;
        double kmax = 0.0;
        const double err = assembledContactTangentError(p, s, kmax);
        std::printf("end contact tangent, %s, %s, %s: max error / max |K| = %.2e\n", rect ? "rectangles" : "circles",
                    type.c_str(), slipping ? "slip" : "stick", err / kmax);
        EXPECT_GT(kmax, 0.0);
        EXPECT_LT(err / kmax, 1e-6) << type;
      }
}

// Pushed through in one increment: a stiff column (E = 1e5: Euler load 121 circles, 205 rectangles,
// above the force here) with its top driven down by 2.5 in 1 increment and in 20 (its end would
// leave the beam's far side if nothing held it). The end is found on the side it came from (its side
// for circles, the face it came through for rectangles, from the last converged state), Lagrange
// holds it there, and the two runs agree (1e-8 of N); each section.
TEST(EndContact, EndPushedThroughInOneIncrementIsHeld) {
  for (bool rect : {false, true}) {
    double force[2] = {0.0, 0.0};
    int k = 0;
    for (int increments : {1, 20}) {
      Deck d = columnDeck("Lagrange Multiplier", rect, false);
      input::replaceAtPath(d, "Supports/column top/Displacement", vec("0.0, 0.0, -2.5"));
      input::replaceAtPath(d, "Beams/column/Material/Young's Modulus", 1e5);
      input::replaceAtPath(d, "Load Stepping/Number of Increments", increments);
      auto p = input::buildProblem(d, "through");
      const auto r = runQuiet(p, Tpetra::getDefaultComm(), "through");
      ASSERT_TRUE(r.report.completed) << r.report.failure;
      const EndForces f = endForces(p);
      double gap = 1.0;
      for (const auto& [key, pt] : p.contact->points())
        if (key.end()) gap = pt.gap;
      std::printf("%s pushed through in %d increments: N %.9f, gap %.2e, Newton %d\n", rect ? "rectangles" : "circles",
                  increments, f.normal, gap, r.report.newtonIterations);
      EXPECT_EQ(f.active, 1);
      EXPECT_GT(gap, -1e-9);
      force[k++] = f.normal;
    }
    EXPECT_NEAR(force[0], force[1], 1e-8 * force[1]);
  }
}

namespace {
// input/columns_end_to_end.xml with the strategy, circular sections (radii 0.6 and 0.5) or
// rectangular ones (the lower column 1.2 x 1.2, the upper 1 x 1), the pair's roles swapped if asked.
Deck endToEndDeck(const std::string& type, bool rectangles, bool swapped) {
  Deck d = inputDeck("columns_end_to_end.xml", type);
  if (rectangles) squareSections(d, {{"lower", 1.2}, {"upper", 1.0}});
  if (swapped) {
    input::replaceAtPath(d, "Contact/Pairs/end to end/Beam A", std::string("upper"));
    input::replaceAtPath(d, "Contact/Pairs/end to end/Beam B", std::string("lower"));
  }
  return d;
}

// The closing 0.01 over the two columns' axial compliances L / (E A) in series (and Penalty's 1 / eps_N).
double endToEndForce(bool rectangles, double epsN) {
  const double lower = rectangles ? 1.44 : M_PI * 0.36, upper = rectangles ? 1.0 : M_PI * 0.25;
  return 0.01 / (10.0 / (1e3 * lower) + 10.0 / (2e3 * upper) + (epsN > 0.0 ? 1.0 / epsN : 0.0));
}

}  // namespace

// Two coaxial columns, the upper one's end pressed onto the lower one's: the force of the two axial
// compliances in series (both sections, each strategy, either column as the pair's A, 1 and 4
// increments, 5 and 20 elements per column); the pressing end is the smaller one on the larger face
// either way. (At 20 elements, shorter than the sections' inscribed radii sum, rectangles in line
// were refused at the start: the unseen-overlap check took their elements' axial distance for an
// overlap.)
TEST(EndToEndContact, ColumnsEndToEndCarryTheStiffnessesInSeries) {
  for (bool rect : {false, true})
    for (bool swapped : {false, true})
      for (int increments : {1, 4})
        for (const std::string type : {"Penalty", "Lagrange Multiplier", "Augmented Lagrange"}) {
          Deck d = endToEndDeck(type, rect, swapped);
          input::replaceAtPath(d, "Load Stepping/Number of Increments", increments);
          if (increments == 1)
            for (const char* column : {"lower", "upper"})
              input::replaceAtPath(d, std::string("Beams/") + column + "/Elements", 20);
          auto p = input::buildProblem(d, "end_to_end");
          const auto r = runQuiet(p, Tpetra::getDefaultComm(), "end_to_end");
          ASSERT_TRUE(r.report.completed) << type << ": " << r.report.failure;
          const EndForces f = endForces(p, true);
          const double exact = endToEndForce(rect, type == "Penalty" ? 1e5 : 0.0);
          if (increments == 4)
            std::printf("columns end to end, %s, %s, A %s: N %.9f, closed form %.9f (%+.2e), Newton %d\n",
                        rect ? "rectangles" : "circles", type.c_str(), swapped ? "upper" : "lower", f.normal, exact,
                        f.normal / exact - 1.0, r.report.newtonIterations);
          ASSERT_EQ(f.active, 1) << type;
          EXPECT_NEAR(f.normal, exact, 1e-6 * exact) << type;
          // the upper end (the smaller face) presses on the lower one's
          for (const auto& [key, pt] : p.contact->points())
            if (key.endToEnd()) {
              EXPECT_EQ(p.beams->elements()[pt.elementA].beam, 1) << type;
            }
          EXPECT_TRUE(r.report.warnings.empty()) << r.report.warnings.front();
        }
}

// With friction 0.3 (endToEndSlide): the upper column starts 0.001 above the lower one (stiffened to
// E = 1e5), its top driven by (0.3, 0.2, -0.0105) in 8 increments (penalties 1e3 / 1e2): the end
// slides, the faces tilt as the columns bend and the upper face's rim presses. Each strategy and section completes,
// and the applied tangential force stays inside the Coulomb cone: |F_T| <= mu N, equal where it slips
// (1e-9); the end stays on the lower face. Lagrange ends on the same state at 8, 16 and 32 increments
// (N 1.76019 circles, 2.42094 rectangles); Augmented Lagrange's stick state depends on the step (at 8
// increments 3.4 % and 1.3 % off, at 16 1.1 % and 1.3 %: docs/contact.md, "End-to-end contact") and
// lands on Lagrange's at 32 increments (2e-5), checked here.
TEST(EndToEndContact, EndSlidAcrossTheOtherEndStaysInTheCone) {
  for (bool rect : {false, true})
    for (const std::string type : {"Penalty", "Lagrange Multiplier", "Augmented Lagrange"}) {
      const bool fine = type == "Augmented Lagrange";  // (32 increments)
      auto p = input::buildProblem(endToEndSlide(type, rect), "end_to_end_slide");
      const auto r = runQuiet(p, Tpetra::getDefaultComm(), "end_to_end_slide");
      ASSERT_TRUE(r.report.completed) << type << ": " << r.report.failure;
      const EndForces f = endForces(p, true);
      std::printf("end slid across an end, %s, %s: N %.6f, |F_T| / (mu N) %.12f, %s, Newton %d\n",
                  rect ? "rectangles" : "circles", type.c_str(), f.normal, f.tangential / (0.3 * f.normal),
                  f.slipping ? "slip" : "stick", r.report.newtonIterations);
      ASSERT_EQ(f.active, 1) << type;
      EXPECT_LE(f.tangential, 0.3 * f.normal * (1.0 + 1e-9)) << type;
      if (f.slipping) {
        EXPECT_NEAR(f.tangential, 0.3 * f.normal, 1e-9 * f.normal) << type;
      }
      EXPECT_GT(f.tangential, 0.0) << type;
      const double lagrange = rect ? 2.42094064772 : 1.76019493106;  // (at 8, 16 and 32 increments)
      if (fine) {
        EXPECT_NEAR(f.normal, lagrange, 1e-4 * lagrange) << "Lagrange's state";
      }
    }
}
