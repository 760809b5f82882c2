// The linear solvers on small Tpetra systems whose solutions are known (x = A^-1 b by construction):
//  - Direct, with KLU2 and with UMFPACK, solves unsymmetric systems (also with descending column
//    numbering) and refactors a matrix of the same pattern (KLU2: with the last factorization's pivot
//    order); new values, also values that make an old pivot zero, still give x to round-off, on 1
//    and 2 ranks;
//  - with Reuse Factorization, GMRES preconditioned with the last factorization solves later matrices
//    of the same size (same or new pattern) to the direct solve's accuracy, and the matrix is
//    factored again once the iterations since the last factorization reach the limit;
//  - with Reuse Factorization, a saddle point (a zero diagonal in the pattern) is factored with that
//    diagonal regularized, and GMRES solves the saddle point itself to the direct solve's accuracy;
//  - a singular matrix is an error (LinearSolveError), not a huge x that passes a backward-error test;
//  - GMRES with the MueLu preconditioner (rigid-body modes as near-null space) solves a system of
//    6-dof nodes to its tolerance;
//  - Direct Solver = Automatic (the default) becomes UMFPACK with Reuse Factorization from
//    kAutomaticLuUnknowns unknowns with a contact point per kAutomaticUnknownsPerPoint unknowns (MUMPS on
//    several ranks from kAutomaticMumpsUnknowns), KLU2 otherwise; a Direct Solver or a Reuse Factorization the list
//    names is kept, and an unresolved Automatic is not made into a solver.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <Teuchos_ParameterList.hpp>
#include <Tpetra_Core.hpp>

#include "core/LinearSolver.hpp"
#include "core/linalg/SerialUmfpack.hpp"

using namespace bc::core;

namespace {

// `choice`: GMRES's Preconditioner or Direct's Direct Solver (empty: the default).
Teuchos::ParameterList solverList(const std::string& type, const std::string& choice = "") {
  Teuchos::ParameterList p;
  p.set("Type", type);
  if (!choice.empty()) p.set(type == "GMRES" ? "Preconditioner" : "Direct Solver", choice);
  linearSolverSpec().apply(p, "Linear Solver");
  return p;
}

// A tridiagonal n x n matrix over all ranks: diag d(i), off-diagonals o(i) (row i to i+1 and back;
// a zero o(i) is left out of the pattern), or o(i) below and up(i) above the diagonal. With
// `descendingColumns` the column map numbers each rank's columns in descending global order: a row's
// local column indices then descend, and a library that wants them ascending has to sort them.
Teuchos::RCP<Matrix> tridiagonal(GO n, const std::function<double(GO)>& d, const std::function<double(GO)>& o,
                                 std::function<double(GO)> up = {}, bool descendingColumns = false,
                                 Teuchos::RCP<const Teuchos::Comm<int>> comm = Tpetra::getDefaultComm()) {
  if (!up) up = o;
  const auto map = Teuchos::rcp(new Map(n, 0, comm));
  Teuchos::RCP<Matrix> A;
  if (descendingColumns) {
    std::vector<GO> columns;
    const GO first = map->getMinGlobalIndex(), last = map->getMaxGlobalIndex();
    for (GO j = std::min(last + 1, n - 1); j >= std::max<GO>(first - 1, 0); --j) columns.push_back(j);
    const auto colMap = Teuchos::rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(),
                                             Teuchos::ArrayView<const GO>(columns), 0, comm));
    A = Teuchos::rcp(new Matrix(map, colMap, 3));
  } else {
    A = Teuchos::rcp(new Matrix(map, 3));
  }
  for (std::size_t l = 0; l < map->getNodeNumElements(); ++l) {
    const GO i = map->getGlobalElement(static_cast<LO>(l));
    std::vector<GO> cols;
    std::vector<double> vals;
    if (i > 0 && o(i - 1) != 0.0) cols.push_back(i - 1), vals.push_back(o(i - 1));
    cols.push_back(i), vals.push_back(d(i));
    if (i + 1 < n && o(i) != 0.0) cols.push_back(i + 1), vals.push_back(up(i));
    A->insertGlobalValues(i, Teuchos::ArrayView<const GO>(cols), Teuchos::ArrayView<const double>(vals));
  }
  A->fillComplete(map, map);
  return A;
}

// New values in the same matrix object (the assembler's way): the pattern stays.
void setValues(Matrix& A, const std::function<double(GO)>& d, const std::function<double(GO)>& o) {
  A.resumeFill();
  const auto& map = *A.getRowMap();
  const GO n = static_cast<GO>(map.getGlobalNumElements());
  for (std::size_t l = 0; l < map.getNodeNumElements(); ++l) {
    const GO i = map.getGlobalElement(static_cast<LO>(l));
    std::vector<GO> cols;
    std::vector<double> vals;
    if (i > 0) cols.push_back(i - 1), vals.push_back(o(i - 1));
    cols.push_back(i), vals.push_back(d(i));
    if (i + 1 < n) cols.push_back(i + 1), vals.push_back(o(i));
    A.replaceGlobalValues(i, Teuchos::ArrayView<const GO>(cols), Teuchos::ArrayView<const double>(vals));
  }
  A.fillComplete();
}

// b = A x for the x_i = 1 + i / n, solved; returns the solve's report and the solution's largest error.
std::pair<SolveReport, double> reportAndError(LinearSolver& s, const Teuchos::RCP<Matrix>& A) {
  const auto map = A->getRowMap();
  Vector xTrue(map), b(map), x(map);
  const double n = static_cast<double>(map->getGlobalNumElements());
  for (std::size_t l = 0; l < map->getNodeNumElements(); ++l)
    xTrue.replaceLocalValue(static_cast<LO>(l), 1.0 + map->getGlobalElement(static_cast<LO>(l)) / n);
  A->apply(xTrue, b);
  const SolveReport report = s.solve(A, b, x);
  x.update(-1.0, xTrue, 1.0);
  return {report, x.normInf()};
}

// A saddle point over all ranks: n displacements with a tridiagonal stiffness (diagonal 4 + 0.01 i,
// off-diagonals -1), and m multipliers, multiplier k tying displacement 10 k to displacement 10 k + 5
// (u_10k - u_10k+5 = c: rows [B 0], columns B^T), as Lagrange multipliers do. With
// `diagonalInPattern`, the multipliers' rows hold their zero diagonal as an entry (the assembled
// contact blocks do).
Teuchos::RCP<Matrix> saddlePoint(GO n, GO m, bool diagonalInPattern) {
  const auto map = Teuchos::rcp(new Map(n + m, 0, Tpetra::getDefaultComm()));
  auto A = Teuchos::rcp(new Matrix(map, 5));
  for (std::size_t l = 0; l < map->getNodeNumElements(); ++l) {
    const GO i = map->getGlobalElement(static_cast<LO>(l));
    std::vector<GO> cols;
    std::vector<double> vals;
    if (i < n) {
      if (i > 0) cols.push_back(i - 1), vals.push_back(-1.0);
      cols.push_back(i), vals.push_back(4.0 + 0.01 * i);
      if (i + 1 < n) cols.push_back(i + 1), vals.push_back(-1.0);
      if (i % 10 == 0 && i / 10 < m) cols.push_back(n + i / 10), vals.push_back(1.0);
      if (i % 10 == 5 && i / 10 < m) cols.push_back(n + i / 10), vals.push_back(-1.0);
    } else {
      const GO k = i - n;
      cols = {10 * k, 10 * k + 5};
      vals = {1.0, -1.0};
      if (diagonalInPattern) cols.push_back(i), vals.push_back(0.0);
    }
    A->insertGlobalValues(i, Teuchos::ArrayView<const GO>(cols), Teuchos::ArrayView<const double>(vals));
  }
  A->fillComplete(map, map);
  return A;
}

// The same, the largest error only.
double solveError(LinearSolver& s, const Teuchos::RCP<Matrix>& A) { return reportAndError(s, A).second; }

// The Direct solver's tests run with each sparse LU.
class DirectSolver : public ::testing::TestWithParam<std::string> {};

}  // namespace

TEST_P(DirectSolver, RefactorsNewValuesOfTheSamePattern) {
  auto solver = makeLinearSolver(solverList("Direct", GetParam()));
  const GO n = 200;
  auto A = tridiagonal(
      n, [](GO i) { return 4.0 + 0.01 * i; }, [](GO) { return -1.0; });
  const double e0 = solveError(*solver, A);
  // New values: refactored with the first pivot order.
  setValues(
      *A, [](GO i) { return 3.0 + std::sin(0.1 * i); }, [](GO i) { return -1.0 + 0.001 * i; });
  const double e1 = solveError(*solver, A);
  // Values whose first pivot (a_00 = 0) the old order cannot take: factored afresh, with pivoting.
  setValues(
      *A, [](GO i) { return i == 0 ? 0.0 : 4.0; }, [](GO) { return 1.0; });
  const double e2 = solveError(*solver, A);
  // Unsymmetric values (the solve with A, not A^T, is checked: the libraries read A's rows as the
  // columns of A^T) in a new matrix.
  auto U = tridiagonal(
      n, [](GO i) { return 4.0 + 0.01 * i; }, [](GO) { return -1.5; }, [](GO i) { return 0.5 + 0.005 * i; });
  const double e3 = solveError(*solver, U);
  // Unsymmetric values with each row's columns in descending order (KLU2 takes them so, UMFPACK's
  // are sorted).
  auto D = tridiagonal(
      n, [](GO) { return 4.0; }, [](GO) { return -1.5; }, [](GO i) { return 0.5 + 0.005 * i; }, true);
  const double e4 = solveError(*solver, D);
  std::printf(
      "  Direct (%s), solution error: first factorization %.1e, refactored %.1e, old pivot zero %.1e, "
      "unsymmetric %.1e, columns descending %.1e\n",
      GetParam().c_str(), e0, e1, e2, e3, e4);
  EXPECT_LT(e0, 1e-12);
  EXPECT_LT(e1, 1e-12);
  EXPECT_LT(e2, 1e-12);
  EXPECT_LT(e3, 1e-12);
  EXPECT_LT(e4, 1e-12);
}

TEST_P(DirectSolver, ReuseSolvesLaterMatricesWithTheLastFactorization) {
  Teuchos::ParameterList p = solverList("Direct", GetParam());
  p.set("Reuse Factorization", true);
  p.set("Reuse Iteration Limit", 20);  // GMRES iterations summed over the solves since a factorization
  auto solver = makeLinearSolver(p);
  const GO n = 300;
  auto A = tridiagonal(
      n, [](GO i) { return 4.0 + 0.01 * i; }, [](GO) { return -1.0; });
  const auto [r0, e0] = reportAndError(*solver, A);  // nothing to reuse: factored
  // The same values: the factorization is the exact inverse, GMRES stops after one iteration.
  const auto [r1, e1] = reportAndError(*solver, A);
  // Values within 2 % of the factored ones: GMRES with the old factorization, no new one.
  setValues(
      *A, [](GO i) { return (4.0 + 0.01 * i) * (1.0 + 0.02 * std::sin(0.3 * i)); },
      [](GO i) { return -1.0 + 0.01 * std::cos(0.2 * i); });
  const auto [r2, e2] = reportAndError(*solver, A);
  // Another matrix object of the same size with another pattern (a new graph, as when contact points
  // come or go): two couplings fewer than the factored matrix.
  auto B = tridiagonal(
      n, [](GO i) { return 4.0 + 0.01 * i; }, [](GO i) { return i % 150 == 75 ? 0.0 : -1.0; });
  const auto [r3, e3] = reportAndError(*solver, B);
  // Values far from the factored ones (the diagonal halved and doubled in alternation, off-diagonals
  // flipped): more iterations than the limit leaves (20 less those spent above), so B is factored.
  setValues(
      *B, [](GO i) { return i % 2 ? 8.0 : 2.5; }, [](GO i) { return i % 3 ? 1.2 : -0.7; });
  const auto [r4, e4] = reportAndError(*solver, B);
  // The same values again: B's own factorization, one iteration (the count starts afresh).
  const auto [r5, e5] = reportAndError(*solver, B);
  std::printf(
      "  Direct (%s) with reuse: GMRES iterations %d (factored), %d (same values), %d (values within 2 %%), "
      "%d (new pattern), %d (far values: factored), %d (their values again); errors %.1e %.1e %.1e %.1e "
      "%.1e %.1e\n",
      GetParam().c_str(), r0.iterations, r1.iterations, r2.iterations, r3.iterations, r4.iterations, r5.iterations, e0,
      e1, e2, e3, e4, e5);
  EXPECT_EQ(r0.iterations, 0);
  EXPECT_EQ(r1.iterations, 1);
  EXPECT_GE(r2.iterations, 2);
  EXPECT_LE(r2.iterations, 12);
  EXPECT_GE(r3.iterations, 2);
  EXPECT_LE(r3.iterations, 12);
  EXPECT_EQ(r4.iterations, 0);
  EXPECT_EQ(r5.iterations, 1);
  for (double e : {e0, e1, e2, e3, e4, e5}) EXPECT_LT(e, 1e-11);
  // Each solve meets the check the direct solve meets, with the margin that keeps it from a redo.
  for (const SolveReport& r : {r0, r1, r2, r3, r4, r5}) EXPECT_LT(r.backwardError, 1e-13);
}

TEST_P(DirectSolver, ReuseFactorsASaddlePointWithItsZeroDiagonalRegularized) {
  Teuchos::ParameterList p = solverList("Direct", GetParam());
  p.set("Reuse Factorization", true);
  auto reuse = makeLinearSolver(p);
  auto direct = makeLinearSolver(solverList("Direct", GetParam()));
  const auto K = saddlePoint(200, 19, true);
  // Reuse: the multipliers' zero diagonal regularized for the factorization, GMRES with it solves A
  // itself (at least one iteration, where the exact factorization's solve reports none).
  const auto [r, e] = reportAndError(*reuse, K);
  const auto [d, ed] = reportAndError(*direct, K);
  // The zero diagonal outside the pattern: nothing to regularize, A factored as it is.
  auto reuseAgain = makeLinearSolver(p);
  const auto [u, eu] = reportAndError(*reuseAgain, saddlePoint(200, 19, false));
  std::printf(
      "  Direct (%s) on a saddle point: with reuse %d GMRES iterations, error %.1e, backward error %.1e; "
      "exact factorization error %.1e; zero diagonal outside the pattern: %d iterations, error %.1e\n",
      GetParam().c_str(), r.iterations, e, r.backwardError, ed, u.iterations, eu);
  EXPECT_GE(r.iterations, 1);
  EXPECT_LE(r.iterations, 4);
  EXPECT_LT(e, 1e-11);
  EXPECT_LT(r.backwardError, 1e-13);
  EXPECT_EQ(d.iterations, 0);
  EXPECT_LT(ed, 1e-11);
  EXPECT_EQ(u.iterations, 0);
  EXPECT_LT(eu, 1e-11);
}

TEST_P(DirectSolver, ASingularMatrixIsAnError) {
  auto solver = makeLinearSolver(solverList("Direct", GetParam()));
  // Rows 10 and 11 equal: singular.
  auto A = tridiagonal(
      40, [](GO i) { return i == 10 || i == 11 ? 1.0 : 4.0; },
      [](GO i) { return i == 10 ? 1.0 : (i == 9 || i == 11 ? 0.0 : -1.0); });
  const auto map = A->getRowMap();
  Vector b(map), x(map);
  b.putScalar(1.0);
  EXPECT_THROW(solver->solve(A, b, x), LinearSolveError);
}

INSTANTIATE_TEST_SUITE_P(LinearSolver, DirectSolver, ::testing::Values("KLU2", "UMFPACK", "MUMPS"));

TEST(LinearSolver, UmfpackSixtyFourBitVersionSolvesAsTheThirtyTwoBit) {
  // The 64-bit version, which takes over when the 32-bit one's addressing runs out (10^5 contact
  // points), on one process's unsymmetric matrices: x to round-off and the 32-bit version's x, also
  // after a new pattern (its analysis and factors freed and made again).
  const auto world = Tpetra::getDefaultComm();
  const auto self = world->split(world->getRank(), 0);
  SerialUmfpack narrow, wide(true);
  for (const bool newPattern : {false, true}) {
    const GO n = 500;
    auto A = tridiagonal(
        n, [](GO i) { return 4.0 + 0.01 * i; }, [&](GO i) { return newPattern && i % 7 == 3 ? 0.0 : -1.0; },
        [](GO i) { return 0.5 + 0.005 * i; }, false, self);
    std::vector<double> xTrue(n), b(n), x32(n), x64(n);
    for (GO i = 0; i < n; ++i) xTrue[i] = 1.0 + double(i) / n;
    Vector xv(A->getRowMap()), bv(A->getRowMap());
    for (GO i = 0; i < n; ++i) xv.replaceLocalValue(static_cast<LO>(i), xTrue[i]);
    A->apply(xv, bv);
    const auto bData = bv.getData(0);
    std::copy(bData.begin(), bData.end(), b.begin());
    narrow.factor(*A, false);
    wide.factor(*A, false);
    narrow.solve(b.data(), x32.data());
    wide.solve(b.data(), x64.data());
    double error = 0.0, difference = 0.0;
    for (GO i = 0; i < n; ++i) {
      error = std::max(error, std::abs(x64[i] - xTrue[i]));
      difference = std::max(difference, std::abs(x64[i] - x32[i]));
    }
    std::printf("UMFPACK 64-bit, %s pattern: error %.2e, against 32-bit %.2e\n", newPattern ? "new" : "first", error,
                difference);
    EXPECT_LT(error, 1e-13);
    EXPECT_LT(difference, 1e-14);
  }
}

TEST(LinearSolver, GmresWithMultigridSolvesNodalSystems) {
  // 6 dofs per node along a chain: a block-tridiagonal SPD matrix (a discrete Laplacian per dof plus
  // a small mass), and the constant and linear modes as the near-null space's stand-in.
  auto solver = makeLinearSolver(solverList("GMRES", "MueLu"));
  ASSERT_TRUE(solver->wantsNearNullSpace());
  const GO nodes = 300, n = 6 * nodes;
  auto A = tridiagonal(
      n, [](GO) { return 2.0 + 1e-3; }, [](GO i) { return (i + 1) % 6 == 0 ? -1.0 : 0.0; });
  // The couplings above join dof 5 of a node to dof 0 of the next only; give every dof its own chain.
  const auto map = A->getRowMap();
  auto B = Teuchos::rcp(new Matrix(map, 3));
  for (std::size_t l = 0; l < map->getNodeNumElements(); ++l) {
    const GO i = map->getGlobalElement(static_cast<LO>(l));
    std::vector<GO> cols{i};
    std::vector<double> vals{2.0 + 1e-3};
    if (i >= 6) cols.push_back(i - 6), vals.push_back(-1.0);
    if (i + 6 < n) cols.push_back(i + 6), vals.push_back(-1.0);
    B->insertGlobalValues(i, Teuchos::ArrayView<const GO>(cols), Teuchos::ArrayView<const double>(vals));
  }
  B->fillComplete();
  auto modes = Teuchos::rcp(new MultiVector(map, 6));
  for (std::size_t l = 0; l < map->getNodeNumElements(); ++l)
    modes->replaceLocalValue(static_cast<LO>(l), static_cast<int>(map->getGlobalElement(static_cast<LO>(l)) % 6), 1.0);
  solver->setNearNullSpace(modes);
  const double e = solveError(*solver, B);
  std::printf("  GMRES (MueLu), solution error %.1e\n", e);
  EXPECT_LT(e, 1e-6);
}

// The rule of Direct Solver = Automatic (core/LinearSolver.hpp; its numbers are bench_default_solver.py's).
TEST(LinearSolver, AutomaticChoosesBySizeContactPointsAndRanks) {
  const long long t = kAutomaticLuUnknowns, k = kAutomaticUnknownsPerPoint, m = kAutomaticMumpsUnknowns;
  struct Case {
    SystemSize size;
    const char* method;
    bool reuse;
  };
  for (const Case& c :
       {// Example 1: small
        Case{{132, 2, 1}, "KLU2", false},
        // just below the size, however many points
        Case{{t - 1, t, 1}, "KLU2", false}, Case{{t - 1, t, 2}, "KLU2", false},
        // at the size, a point per k unknowns: UMFPACK, also on several ranks below m
        Case{{t, (t + k - 1) / k, 1}, "UMFPACK", true}, Case{{t, (t + k - 1) / k, 2}, "UMFPACK", true},
        Case{{m - 1, m, 2}, "UMFPACK", true}, Case{{m, m, 2}, "MUMPS", true}, Case{{m, m, 1}, "UMFPACK", true},
        // the 100 x 100 layers, 10^4 points
        Case{{122400, 10000, 1}, "UMFPACK", true}, Case{{122400, 10000, 4}, "MUMPS", true},
        // the 16 x 16 weave (256 points on 26304 unknowns) and a large model without contact
        Case{{26304, 256, 1}, "KLU2", false}, Case{{100000, 0, 2}, "KLU2", false},
        // one point short of a point per k unknowns
        Case{{40 * k, 39, 1}, "KLU2", false}}) {
    Teuchos::ParameterList p = solverList("Direct");
    EXPECT_EQ(p.get<std::string>("Direct Solver"), "Automatic");
    EXPECT_FALSE(p.isParameter("Reuse Factorization"));
    const std::string line = resolveLinearSolver(p, c.size);
    SCOPED_TRACE(line);
    EXPECT_EQ(p.get<std::string>("Direct Solver"), c.method);
    EXPECT_EQ(p.get<bool>("Reuse Factorization"), c.reuse);
    // The reason goes with the values into effective_parameters.xml (their doc strings) and the header.
    const std::string numbers =
        std::to_string(c.size.unknowns) + " unknowns, " + std::to_string(c.size.contactPoints) + " contact points";
    EXPECT_NE(p.getEntry("Direct Solver").docString().find(numbers), std::string::npos);
    EXPECT_EQ(line.rfind(c.method, 0), 0u);
    EXPECT_NE(line.find(numbers), std::string::npos);
    EXPECT_NE(makeLinearSolver(p), nullptr);
  }
}

TEST(LinearSolver, AnExplicitChoiceWins) {
  const SystemSize large{10 * kAutomaticLuUnknowns, 10 * kAutomaticLuUnknowns, 2};
  // A Direct Solver named: kept at any size, Reuse Factorization false unless given.
  for (const char* method : {"KLU2", "UMFPACK", "MUMPS"}) {
    Teuchos::ParameterList p = solverList("Direct", method);
    EXPECT_EQ(resolveLinearSolver(p, large), "");
    EXPECT_EQ(p.get<std::string>("Direct Solver"), method);
    EXPECT_FALSE(p.get<bool>("Reuse Factorization"));
  }
  // Automatic with Reuse Factorization given: the method is chosen, the reuse kept.
  Teuchos::ParameterList p;
  p.set("Reuse Factorization", false);
  linearSolverSpec().apply(p, "Linear Solver");
  const std::string line = resolveLinearSolver(p, {large.unknowns, large.contactPoints, 1});
  EXPECT_EQ(p.get<std::string>("Direct Solver"), "UMFPACK");
  EXPECT_FALSE(p.get<bool>("Reuse Factorization"));
  EXPECT_NE(line.find("Reuse Factorization as given"), std::string::npos);
  // GMRES: nothing to choose.
  Teuchos::ParameterList g = solverList("GMRES", "ILUT");
  EXPECT_EQ(resolveLinearSolver(g, large), "");
  EXPECT_EQ(g.get<std::string>("Direct Solver"), "Automatic");
  // An Automatic left unresolved is a mistake of the caller, not a silent KLU2.
  EXPECT_THROW(makeLinearSolver(solverList("Direct")), std::logic_error);
  EXPECT_NE(makeLinearSolver(solverList("Direct"), {10, 0, 1}), nullptr);
}
