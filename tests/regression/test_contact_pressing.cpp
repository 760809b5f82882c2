// Contact on the seed paper's Example 1 geometry (input/example1.xml), pressing and whole runs:
//  - pressing only (no sideways motion): total normal force against the linear closed form with the
//    penalty spring in series; penetration falls like 1 / eps_N; augmented Lagrange meets the gap
//    tolerance and its force does not depend on eps_N; crossed cantilevers against their closed form;
//  - Example 1 to T = 1 and Examples 2 and 3 with each strategy; Newton's order near a solution;
//  - every registered strategy, and one registered from inside the test, runs a case;
//  - bad contact input names its cause.
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

TEST(Pressing, PenaltyForceMatchesSeriesSpringsAndPenetrationFallsLikeOneOverEps) {
  // W = 0.6: 0.1 of closure after the 0.5 gap; rotations ~1e-4, so linear theory holds.
  const double W = 0.6;
  std::vector<double> eps = {1e3, 1e4, 1e5}, pen;
  for (double e : eps) {
    auto p = input::buildProblem(example1("Penalty", "0.0, 0.0, " + test::num(-W), 4, e, 400.0, 0.0), "press");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "press");
    ASSERT_TRUE(r.report.completed) << r.report.failure;
    const auto c = sums(p);
    const double expected = pressingForce(W, e, c.active);
    std::printf("eps_N %.0e: %d points, N = %.5f (series springs %.5f, rigid contact %.5f), penetration %.3e\n", e,
                c.active, c.normal, expected, pressingForce(W, 0, 1), c.maxPenetration);
    EXPECT_EQ(c.active, 4);
    // The closed form puts the load on the centre lines; here the 4 edge points sit at x = 50 +- 2.5,
    // y = +-5 and load the beams through linearly interpolated edges: 7 % above it (exact closed
    // form: the circular-section test below).
    EXPECT_NEAR(c.normal, expected, 0.08 * expected);
    pen.push_back(c.maxPenetration);
  }
  for (std::size_t i = 1; i < eps.size(); ++i) {
    const double rate = std::log(pen[i] / pen[i - 1]) / std::log(eps[i] / eps[i - 1]);
    std::printf("penetration rate d log(penetration) / d log(eps_N) = %.3f\n", rate);
    EXPECT_LT(rate, -0.8);
  }
}

TEST(Pressing, CircularSectionsMatchTheExactClosedForm) {
  const double pi = std::acos(-1.0), E = 30000.0, W = 0.6;
  const double I1 = pi * std::pow(5.0, 4) / 4, I2 = pi * std::pow(2.5, 4) / 4;
  const double c1 = std::pow(50.0, 3) / (3 * E * I1), c2 = std::pow(100.0, 3) / (48 * E * I2);
  std::vector<double> eps = {1e4, 1e5, 1e6}, pen;
  for (double e : eps) {
    auto p = input::buildProblem(circles("Penalty", W, e), "circles");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "circles");
    ASSERT_TRUE(r.report.completed) << r.report.failure;
    const auto c = sums(p);
    const double N = circlesForce(W, e);
    const double A = -r.finalState.displacement(p.beams->beams()[0].nodes.back())[2];
    const double Aexact = N * 50.0 * 50.0 * (300.0 - 50.0) / (6 * E * I1);
    std::printf("circles, eps_N %.0e: %d point, N = %.6f (closed form %.6f), A = %.6f (%.6f), penetration %.3e\n", e,
                c.active, c.normal, N, A, Aexact, c.maxPenetration);
    EXPECT_EQ(c.active, 1);  // one point, though it sits on nodes shared by two elements of each beam
    EXPECT_NEAR(c.normal, N, 2e-3 * N);  // geometric nonlinearity of a 0.1 closure: < 0.2 %
    EXPECT_NEAR(A, Aexact, 2e-3 * Aexact);
    EXPECT_NEAR(c.maxPenetration, c.normal / e, 1e-9);  // penalty law: penetration = N / eps_N
    pen.push_back(c.maxPenetration);
  }
  for (std::size_t i = 1; i < eps.size(); ++i) {
    const double rate = std::log(pen[i] / pen[i - 1]) / std::log(eps[i] / eps[i - 1]);
    const double e = std::sqrt(eps[i] * eps[i - 1]), c = c1 + c2;
    std::printf("penetration rate %.4f (closed form -c eps / (c eps + 1) = %.4f)\n", rate, -c * e / (c * e + 1));
    EXPECT_NEAR(rate, -1.0, 0.02);
  }
  // Lagrange multipliers: the rigid-contact answer with the gap at solver precision.
  double lagrangeN = 0.0;
  {
    auto p = input::buildProblem(circles("Lagrange Multiplier", W, 1e4), "circles_lm");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "circles_lm");
    ASSERT_TRUE(r.report.completed) << r.report.failure;
    const auto c = sums(p);
    lagrangeN = c.normal;
    const double N = circlesForce(W, 0.0);
    std::printf("circles, Lagrange multiplier: N = %.6f (closed form %.6f), |gap| %.2e\n", c.normal, N,
                std::abs(p.contact->points().begin()->second.gap));
    EXPECT_NEAR(c.normal, N, 2e-3 * N);
    for (const auto& [key, pt] : p.contact->points()) EXPECT_LT(std::abs(pt.gap), 1e-12);
  }
  // Augmented Lagrange: the rigid-contact answer, whatever eps_N, and the Lagrange one.
  for (double e : {1e3, 1e5}) {
    auto p = input::buildProblem(circles("Augmented Lagrange", W, e), "circles_al");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "circles_al");
    ASSERT_TRUE(r.report.completed) << r.report.failure;
    const auto c = sums(p);
    const double N = (W - 0.5) / (c1 + c2);
    int passes = 0;
    for (const auto& st : r.steps) passes += st.passes;
    std::printf("circles, augmented Lagrange eps_N %.0e: N = %.6f (closed form %.6f), penetration %.2e, %d passes\n", e,
                c.normal, N, c.maxPenetration, passes);
    EXPECT_NEAR(c.normal, N, 2e-3 * N);
    EXPECT_LT(c.maxPenetration, 1e-6);
    // Lands at the Lagrange answer: the remaining gap (< 1e-6) times the contact stiffness 1/c.
    EXPECT_NEAR(c.normal, lagrangeN, 1e-6 / (c1 + c2) + 1e-9);
  }
}

TEST(Pressing, AugmentedLagrangeGapFallsWithEachAugmentation) {
  // Circular sections pressed by W = 0.6 in one increment with a soft eps_N = 1e3: the penetration
  // after each pass (Uzawa update of lambda_N) must fall, and end below the Gap Tolerance 1e-6.
  // Linear theory for the rate of the plain update (the first one: no gap of an earlier pass to
  // measure over-relaxation from): penetration_1 / penetration_0 = (1/eps_N) / (1/eps_N + c1 + c2)
  // (the penalty spring in series with the structure's compliance), here 0.0378; asserted to 5 %.
  // The next updates are over-relaxed by omega = 1 / (1 - r), r that measured ratio: a secant on a
  // gap linear in the estimate, which closes it in one pass; here the gap depends on it linearly up to
  // the small rotations, so each later ratio is asserted below rate^2 (plain Uzawa: rate).
  const double pi = std::acos(-1.0), E = 30000.0;
  const double c1 = std::pow(50.0, 3) / (3 * E * pi * std::pow(5.0, 4) / 4);
  const double c2 = std::pow(100.0, 3) / (48 * E * pi * std::pow(2.5, 4) / 4);
  // The points' own updates: the estimates are not moved within Newton (Maximum Coupled Constraints
  // 0; the test below moves them).
  Deck d = circles("Augmented Lagrange", 0.6, 1e3);
  input::sublistAtPath(d, "Contact/Enforcement/Augmented Lagrange", false).set("Maximum Coupled Constraints", 0);
  auto p = input::buildProblem(d, "al_passes");
  auto comm = Tpetra::getDefaultComm();
  auto linear = core::makeLinearSolver(p.linearSolver, {p.model.initial.numDofs(), 0, comm->getSize()});
  core::StaticSolver solver(comm, p.model, p.solver, *linear);
  core::State end;
  solver.iterateFrom(p.model.initial, 0.0, 1.0, end);
  const auto& v = p.contact->passViolations();
  const double rate = (1.0 / 1e3) / (1.0 / 1e3 + c1 + c2);
  std::printf("augmented Lagrange, penetration after each pass:");
  for (double x : v) std::printf(" %.3e", x);
  std::printf("  (linear rate %.4f)\n", rate);
  ASSERT_GE(v.size(), 3u);  // the start, one plain and one over-relaxed update
  EXPECT_NEAR(v[1] / v[0], rate, 0.05 * rate);
  for (std::size_t k = 2; k < v.size(); ++k) EXPECT_LT(v[k] / v[k - 1], rate * rate) << "pass " << k;
  EXPECT_LT(v.back(), 1e-6);
}

TEST(Pressing, AugmentedLagrangeEstimatesMovedWithNewtonConvergeQuadraticallyOnTheLagrangeAnswer) {
  // The same press with the estimates moved with Newton's steps near the solution (the default): each
  // such step is Newton's on the motion and the estimate together, D delta = g + R du with D = R^T K^-1
  // R. So the increment needs one pass (no augmentation after it), Newton's steps fall quadratically
  // near the solution (below), and the force is Lagrange's to 1e-9 (the gap closed to round-off; the
  // per-point updates above stop at the Gap Tolerance 1e-6, worth 1e-6 / (c1 + c2) = 6e-3 N), with
  // eps_N 1e3 and 1e5.
  const double pi = std::acos(-1.0), E = 30000.0, W = 0.6;
  const double c1 = std::pow(50.0, 3) / (3 * E * pi * std::pow(5.0, 4) / 4);
  const double c2 = std::pow(100.0, 3) / (48 * E * pi * std::pow(2.5, 4) / 4);
  double lagrangeN = 0.0;
  for (const std::string type : {"Lagrange Multiplier", "Augmented Lagrange"}) {
    for (double e : {1e3, 1e5}) {
      if (type == "Lagrange Multiplier" && e > 1e3) continue;
      auto p = input::buildProblem(circles(type, W, e, "", 1), "al_coupled");
      auto comm = Tpetra::getDefaultComm();
      auto linear = core::makeLinearSolver(p.linearSolver, {p.model.initial.numDofs(), 0, comm->getSize()});
      core::StaticSolver solver(comm, p.model, p.solver, *linear);
      core::State end;
      const auto step = solver.iterateFrom(p.model.initial, 0.0, 1.0, end);
      ASSERT_FALSE(step.history.empty());
      // (The contact manager's results are committed by commitStep; the gap is read at the end state.)
      p.contact->commitStep(end);
      const auto c = sums(p);
      const double first = step.history.front().residualNorm;
      std::printf("%s eps_N %.0e: N = %.12f (closed form %.12f), passes %d, coupled steps %d, ||r|| / ||r_0||:",
                  type.c_str(), e, c.normal, (W - 0.5) / (c1 + c2), step.passes, step.coupledSteps);
      for (const auto& it : step.history) std::printf(" %.1e", it.residualNorm / first);
      std::printf("\n  ||du||:");
      for (const auto& it : step.history) std::printf(" %.1e", it.incrementNorm);
      std::printf("\n");
      if (type == "Lagrange Multiplier") {
        lagrangeN = c.normal;
        continue;
      }
      EXPECT_EQ(step.passes, 1);
      EXPECT_GE(step.coupledSteps, 1);
      EXPECT_NEAR(c.normal, lagrangeN, 1e-9 * lagrangeN);
      EXPECT_LT(c.maxPenetration, 1e-10);
      // Quadratic: e_k+1 <= 10 e_k^2 for the steps e_k = ||du_k|| / ||du_0|| (motion and estimates'
      // motion) near the solution (e_k <= 1e-2) while above the round-off floor (e_k+1 >= 1e-12).
      const double du0 = step.history.front().incrementNorm;
      int pairs = 0;
      for (std::size_t k = 0; k + 1 < step.history.size(); ++k) {
        const double a = step.history[k].incrementNorm / du0, b = step.history[k + 1].incrementNorm / du0;
        if (a > 1e-2 || b < 1e-12) continue;
        ++pairs;
        std::printf("  e_%zu / e_%zu^2 = %.3f (order %.2f)\n", k + 1, k, b / (a * a), std::log(b) / std::log(a));
        EXPECT_LE(b, 10.0 * a * a) << "step " << k + 1;
      }
      EXPECT_GE(pairs, 1);
    }
  }
}

TEST(Pressing, AugmentedLagrangeMeetsGapToleranceIndependentlyOfEps) {
  const double W = 0.6;
  std::vector<double> forces;
  for (double e : {1e3, 1e4}) {
    auto p = input::buildProblem(example1("Augmented Lagrange", "0.0, 0.0, " + test::num(-W), 4, e, 400.0, 0.0), "al");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "al_press");
    ASSERT_TRUE(r.report.completed) << r.report.failure;
    const auto c = sums(p);
    int passes = 0;
    for (const auto& s : r.steps) passes += s.passes;
    std::printf(
        "augmented Lagrange eps_N %.0e: N = %.6f (rigid-contact closed form %.4f), max penetration %.2e, "
        "%d passes over %zu steps\n",
        e, c.normal, pressingForce(W, 0, 1), c.maxPenetration, passes, r.steps.size());
    EXPECT_LT(c.maxPenetration, 1e-6);
    // Edge points off the centre lines: see the penalty test (7 %).
    EXPECT_NEAR(c.normal, pressingForce(W, 0, 1), 0.08 * pressingForce(W, 0, 1));
    forces.push_back(c.normal);
  }
  // Independent of eps_N beyond the tolerance: each of the 4 points may keep a gap up to the Gap
  // Tolerance 1e-6, worth at most 4 * 1e-6 * (structural stiffness 1 / (1/600 + 1/75) = 67) in N.
  EXPECT_NEAR(forces[0], forces[1], 4 * 1e-6 * 67.0);
}

TEST(Example1, EachStrategyRunsToTheEnd) {
  for (const std::string type : {"Penalty", "Lagrange Multiplier", "Augmented Lagrange"}) {
    auto p = input::buildProblem(example1(type), "example1");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "example1");
    ASSERT_TRUE(r.report.completed) << type << ": " << r.report.failure;
    const auto& s = r.finalState;
    const int A = p.beams->beams()[0].nodes.back(), B = p.beams->beams()[1].nodes[5];
    const auto c = sums(p);
    int maxIt = 0;
    for (const auto& st : r.steps) maxIt = std::max(maxIt, st.iterations);
    std::printf(
        "%s: A (%.4f, %.4f)  B (%.4f, %.4f)  N %.2f  T1 %.2f  points %d  steps %d  Newton %d (max %d)  solve %.2f s\n",
        type.c_str(), s.displacement(A)[0], s.displacement(A)[2], s.displacement(B)[0], s.displacement(B)[2], c.normal,
        c.tangential1, c.active, r.report.steps, r.report.newtonIterations, maxIt, r.solveSeconds);
    // Paper, Table 1 and 2 (magnitudes; B's labels swapped in the paper): A (0.54-0.57, 9.8-9.9),
    // B (35.4-36.2 along X, 8.0-8.1 down). Our reconstructed layout: within 8 %.
    EXPECT_NEAR(std::abs(s.displacement(A)[0]), 0.55, 0.08 * 0.55);
    EXPECT_NEAR(std::abs(s.displacement(A)[2]), 9.85, 0.08 * 9.85);
    EXPECT_NEAR(s.displacement(B)[0], 35.8, 0.08 * 35.8);
    EXPECT_NEAR(-s.displacement(B)[2], 8.05, 0.08 * 8.05);
    // Beam 2 slides on beam 1 from first contact to the end: the friction along beam 1 is mu N.
    EXPECT_NEAR(std::abs(c.tangential1), 0.5 * c.normal, 1e-6 * c.normal);
  }
}

namespace {
// Examples 2 and 3 (input/example2.xml, example3.xml) with each strategy to T = 1. Their gold values
// live beside the decks (input/example2.gold, checked through the command line by
// tests/cli/check_gold.py); here the independent checks: the augmented Lagrange result lands on the
// Lagrange one (to 1e-4; measured <= 2.2e-6, its gap tolerance being 1e-6), and the friction stays
// within mu N. With `costRatio` > 0, augmented Lagrange's Newton iterations (a deterministic count)
// are at most costRatio times Penalty's with the deck's parameters and tolerances (issue 36's target
// of 2 for the paper's examples; docs/contact.md "Cost of the augmentations").
void checkExample(const std::string& deckName, double costRatio = 0.0) {
  std::map<std::string, std::array<double, 3>> got;
  std::map<std::string, int> newton;
  for (const char* type : {"Lagrange Multiplier", "Penalty", "Augmented Lagrange"}) {
    auto p = input::buildProblem(inputDeck(deckName, type), "example");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "example");
    ASSERT_TRUE(r.report.completed) << deckName << ", " << type << ": " << r.report.failure;
    const auto A = r.finalState.displacement(p.beams->beams()[0].nodes.back());
    const auto c = sums(p);
    std::printf("%s, %s: A (%.9f, %.9f)  N %.6f  T1 %.6f  steps %d  Newton %d  solve %.2f s\n", deckName.c_str(), type,
                A[0], A[2], c.normal, c.tangential1, r.report.steps, r.report.newtonIterations, r.solveSeconds);
    for (const auto& [key, pt] : p.contact->points()) {
      if (!pt.result.active) continue;
      for (double t : pt.result.lambdaT) EXPECT_LE(std::abs(t), -1.0 * pt.result.lambdaN * (1 + 1e-9));
    }
    got[type] = {A[0], A[2], c.normal};
    newton[type] = r.report.newtonIterations;
  }
  if (costRatio > 0.0) {
    EXPECT_LE(newton["Augmented Lagrange"], costRatio * newton["Penalty"]);
  }
  const auto& l = got["Lagrange Multiplier"];
  const auto& a = got["Augmented Lagrange"];
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], l[k], 1e-4 * std::abs(l[k])) << "quantity " << k;
}
}  // namespace

TEST(PaperExamples, Example1AugmentedLagrangeLandsOnLagrangeAtMostTwicePenaltysNewtonIterations) {
  checkExample("example1.xml", 2.0);
}
TEST(PaperExamples, Example2AugmentedLagrangeLandsOnLagrangeAtMostTwicePenaltysNewtonIterations) {
  checkExample("example2.xml", 2.0);
}
TEST(PaperExamples, Example3AugmentedLagrangeLandsOnLagrangeAtMostTwicePenaltysNewtonIterations) {
  checkExample("example3.xml", 2.0);
}

TEST(PaperExamples, Example2IsotropicCoulombAugmentedLagrangeSlidesWhereLagrangeSlides) {
  // Example 2 with the Isotropic Coulomb law: every contact point slides, and the friction force's
  // direction is the fixed point of the augmentations (its estimate turned towards the slip until the
  // slip across it is below the Gap Tolerance), where Lagrange multipliers put it on the slip. So the
  // tracked point A and the total normal force land on Lagrange's to 1e-5 (measured 1.9e-7). Before,
  // the stopping test did not look at the direction: 3.4e-4 with the per-point updates, 1.1e-2 once the
  // estimates moved with Newton (one pass per increment).
  std::map<std::string, std::array<double, 3>> got;
  for (const char* type : {"Lagrange Multiplier", "Augmented Lagrange"}) {
    Deck d = inputDeck("example2.xml", type);
    input::replaceAtPath(d, "Contact/Friction Law", std::string("Isotropic Coulomb"));
    auto p = input::buildProblem(d, "example2_isotropic");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "example2_isotropic");
    ASSERT_TRUE(r.report.completed) << type << ": " << r.report.failure;
    const auto A = r.finalState.displacement(p.beams->beams()[0].nodes.back());
    const auto c = sums(p);
    std::printf("example2.xml Isotropic Coulomb, %s: A (%.9f, %.9f)  N %.6f  Newton %d\n", type, A[0], A[2], c.normal,
                r.report.newtonIterations);
    for (const auto& [key, pt] : p.contact->points())
      if (pt.result.active) {
        EXPECT_TRUE(pt.result.slip[0] && pt.result.slip[1]);
      }
    got[type] = {A[0], A[2], c.normal};
  }
  const auto& l = got["Lagrange Multiplier"];
  const auto& a = got["Augmented Lagrange"];
  const double scale = std::max(std::abs(l[0]), std::abs(l[1]));
  for (int k = 0; k < 2; ++k) EXPECT_NEAR(a[k], l[k], 1e-5 * scale) << "displacement " << k;
  EXPECT_NEAR(a[2], l[2], 1e-5 * l[2]);
}

namespace {
// A strategy defined here, registered from the test: frictionless penalty with a stiffness given
// as a "Contact Stiffness" (the one-file-pair extension path; here one class).
class FrictionlessSpring : public constraints::ConstraintEnforcer {
 public:
  static const char* name() { return "Frictionless Spring"; }
  static const char* description() { return "a normal spring only"; }
  static const core::ParameterSpec& spec() {
    static const core::ParameterSpec s = [] {
      core::ParameterSpec p;
      p.addRequired("Contact Stiffness", 1e4, "normal spring [force/length]", core::positive(), "> 0");
      return p;
    }();
    return s;
  }
  explicit FrictionlessSpring(const Teuchos::ParameterList& v) : stiffness_(v.get<double>("Contact Stiffness")) {}
  std::string type() const override { return name(); }
  bool contributes(double gapN, const constraints::PointState&) const override { return gapN < 0.0; }
  constraints::PointResult evaluate(const constraints::ContactPoint& p, const constraints::PointState&, double* f,
                                    double* K) const override {
    constraints::ContactPoint frictionless = p;
    frictionless.friction = 0.0;
    return constraints::regularizedEvaluate(frictionless, constraints::linearNormalLaw(0.0, stiffness_), {}, f, K);
  }
  bool acceptPoint(const constraints::ContactPoint&, constraints::PointState&, double&) const override { return true; }

 private:
  double stiffness_;
};
}  // namespace

TEST(Registry, StrategyRegisteredFromATestRuns) {
  constraints::registerEnforcer<FrictionlessSpring>();
  Deck deck = example1("Frictionless Spring", "0.0, 0.0, -0.6", 4, 1e4, 400.0, 0.0);
  input::setAtPath(deck, "Contact/Enforcement/Frictionless Spring/Contact Stiffness", 1e4);
  auto p = input::buildProblem(deck, "custom");
  EXPECT_EQ(p.contact->enforcer().type(), "Frictionless Spring");
  const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "custom");
  ASSERT_TRUE(r.report.completed) << r.report.failure;
  const auto c = sums(p);
  // Same spring law as the penalty method's normal part: the series-spring closed form.
  EXPECT_NEAR(c.normal, pressingForce(0.6, 1e4, c.active), 0.08 * pressingForce(0.6, 1e4, c.active));
}

// Every registered strategy (from the registry, no names here), built from its parameter
// specification (defaults and documented examples), solves the frictionless pressing case of
// Example 1 (W = 0.6, 0.1 of closure after the 0.5 gap): the normal force lies within 8 % of the
// rigid-contact closed form (the edge points load the beams 7 % above the centre-line closed form;
// see the penalty test above), on the deck edited by parameter path.
TEST(Registry, EveryStrategySolvesThePressingCaseFromItsSpecification) {
  const double W = 0.6, rigid = pressingForce(W, 0.0, 1);
  for (const auto& entry : constraints::enforcers()) {
    Teuchos::ParameterList deck = input::readParameterXmlFile(std::string(BC_SOURCE_DIR) + "/input/example1.xml");
    input::replaceAtPath(deck, "Contact/Enforcement/Type", entry.name);
    input::sublistAtPath(deck, "Contact/Enforcement/" + entry.name).setParameters(entry.spec->example());
    input::replaceAtPath(deck, "Contact/Pairs/crossing/Friction Coefficient", 0.0);
    input::replaceAtPath(deck, "Load Stepping/Number of Increments", 4);
    for (const char* end : {"Supports/beam 2 start/Displacement", "Supports/beam 2 end/Displacement"})
      input::replaceAtPath(deck, end, Teuchos::Array<double>(std::vector<double>{0.0, 0.0, -W}));
    auto p = input::buildProblem(deck, "registry");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "registry");
    ASSERT_TRUE(r.report.completed) << entry.name << ": " << r.report.failure;
    const auto c = sums(p);
    std::printf("%-20s N = %.5f (rigid contact %.5f), %d points\n", entry.name.c_str(), c.normal, rigid, c.active);
    EXPECT_EQ(c.active, 4) << entry.name;
    EXPECT_NEAR(c.normal, rigid, 0.08 * rigid) << entry.name;
  }
}

TEST(ContactInput, BadInputsNameTheirCause) {
  auto expectError = [](const Deck& deck, const std::string& pattern) {
    try {
      input::buildProblem(deck, "test");
      ADD_FAILURE() << "no error; expected: " << pattern;
    } catch (const core::InputError& e) {
      EXPECT_TRUE(std::regex_search(std::string(e.what()), std::regex(pattern))) << e.what();
    }
  };
  expectError(
      example1("Mortar"),
      R"("BeamContact/Contact/Enforcement/Type": unknown enforcement strategy "Mortar"; valid strategies are "Penalty", .*"Augmented Lagrange")");
  expectError(example1("Penalty", "40.0, 0.0, -20.0", 50, -5.0),
              R"("BeamContact/Contact/Enforcement/Penalty/Normal Penalty Parameter": must be > 0, got -5)");
  Deck noFriction = example1("Penalty");
  input::sublistAtPath(noFriction, "Contact/Pairs/crossing", false).remove("Friction Coefficient");
  expectError(noFriction, R"(missing required parameter "BeamContact/Contact/Pairs/crossing/Friction Coefficient")");
  Deck overlapping = example1("Penalty");
  moveBeam2(overlapping, "50.0, -50.0, 7.0", "50.0, 50.0, 7.0");
  expectError(overlapping, R"(beams "beam 1" and "beam 2" overlap at the start: gap -0.5)");
}

TEST(Newton, ConvergesQuadraticallyNearAContactSolutionForEachStrategy) {
  // Circular sections pressed (frictionless, one point): from the converged state at T = 1, Newton
  // solves for T = 1.02 with the contact set unchanged. Orders as in the beam test:
  // p = log(eps_k+1) / log(eps_k), eps_k = ||du_k|| / ||du_0||, counted while eps_k < 1e-2 and
  // ||du_k+1|| > 1e-12, over the first Newton solve (before any augmentation pass).
  for (const std::string type : {"Penalty", "Lagrange Multiplier", "Augmented Lagrange"}) {
    auto p = input::buildProblem(circles(type, 3.0, 1e4), "newton_contact");
    auto comm = Tpetra::getDefaultComm();
    const auto r = test::runQuiet(p, comm, "newton_contact");
    ASSERT_TRUE(r.report.completed) << r.report.failure;
    expectQuadraticNewton(p, r.finalState, type);
  }
}

TEST(CrossedCantilevers, NormalForceMatchesClosedForm) {
  const auto [c, f11, f22, g0, delta] = crossedCantileverForm();
  const double N = (c * delta - g0) / (f11 + f22);
  for (const std::string type : {"Lagrange Multiplier", "Augmented Lagrange", "Penalty"}) {
    auto p = input::buildProblem(crossedCantilevers(type, delta), "crossed");
    const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), "crossed");
    ASSERT_TRUE(r.report.completed) << r.report.failure;
    const auto cs = sums(p);
    const double expected = type == "Penalty" ? (c * delta - g0) / (f11 + f22 + 1e-4) : N;  // eps_N = 1e4 in series
    std::printf("crossed cantilevers, %s: N = %.6f (closed form %.6f)\n", type.c_str(), cs.normal, expected);
    EXPECT_EQ(cs.active, 1);
    EXPECT_NEAR(cs.normal, expected, 1e-3 * expected);
  }
}
