// The linear solvers behind Newton (the deck's "Linear Solver": core/LinearSolver.hpp reads it):
//  - Direct: a sparse LU of the registry of DirectMethod.hpp (KLU2, UMFPACK, MUMPS), with Reuse
//    Factorization's GMRES preconditioned with an earlier factorization;
//  - GMRES: Belos GMRES, right-preconditioned by Ifpack2 (additive Schwarz with ILUT or RILUK
//    subdomain solves) or by smoothed-aggregation multigrid (MueLu, with the nodes' rigid-body modes
//    as near-null space; for matrices without multiplier rows).
// Every solve is checked: the residual b - A x of the returned x is computed on the distributed
// system, and its normwise backward error ||b - A x|| / (||A||_F ||x|| + ||b||) above "Residual Check
// Tolerance" raises LinearSolveError. (The backward error is scale-invariant: a backward-stable solve
// gives ~1e-16 even when ||b|| is small against the terms of A x that cancel, where ||b - A x|| / ||b||
// can be 1e-8 for a perfectly good solve.) A singular matrix can pass that test with a huge x, so
// ||A||_F ||x|| / ||b||, a lower bound of the condition number, above "Condition Limit" is an error too.
#pragma once
#include <memory>
#include <string>

#include <Teuchos_StackedTimer.hpp>

#include "core/TpetraTypes.hpp"
#include "DirectMethod.hpp"
#include "Errors.hpp"

namespace bc::core {

struct SolveReport {
  int iterations = 0;  // Krylov iterations (0 for direct)
  double relativeResidual = 0;  // ||b - A x|| / ||b|| of the returned solution
  double backwardError = 0;  // ||b - A x|| / (||A||_F ||x|| + ||b||), checked
  double conditionBound = 0;  // ||A||_F ||x|| / ||b||, a lower bound of cond(A), checked
  double solutionNorm = 0;  // ||x||
};

// The residual measures of x as a solution of A x = b (iterations 0): what every solve is checked by.
SolveReport residualReport(const Matrix& A, const Vector& b, const Vector& x);

// ||v||_2 without underflow or overflow: Tpetra's norm2 squares the entries, so entries below about
// 1e-154 square to 0 (forces of a model that is very soft in its units: a residual of 1e-298 had the
// norm 0). Scaled by the largest entry when that lies outside 1e-150 .. 1e150; else the plain norm.
double scaledNorm2(const Vector& v);

// What every solve is checked by ("Residual Check Tolerance", "Condition Limit").
struct SolveChecks {
  double residualTolerance = 1e-10;
  double conditionLimit = 1e14;
};

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  virtual std::string name() const = 0;
  SolveReport solve(const Teuchos::RCP<const Matrix>& A, const Vector& b, Vector& x);
  // Whether the solver wants the matrix's near-null space (the rigid-body modes of the nodes) with
  // every solve (the multigrid preconditioner does), and where it is given.
  virtual bool wantsNearNullSpace() const { return false; }
  void setNearNullSpace(const Teuchos::RCP<MultiVector>& modes) { nearNull_ = modes; }
  // With a timer, the stages of a solve are timed within the caller's running timer.
  void setTimer(Teuchos::RCP<Teuchos::StackedTimer> timer) { timer_ = timer; }

 protected:
  explicit LinearSolver(const SolveChecks& checks) : checks_(checks) {}
  virtual int doSolve(const Teuchos::RCP<const Matrix>& A, const Vector& b, Vector& x) = 0;
  // The last doSolve took a shortcut (Direct: a refactorization with old pivots): the next one is to
  // do without it; return false when there was none. The same answer on every rank.
  virtual bool redoWithoutShortcut() { return false; }
  // A solver that hands its solves to another (Direct Solver = Automatic's, which may change its
  // method during a run) calls that one's doSolve and redoWithoutShortcut through these.
  static int forwardSolve(LinearSolver& to, const Teuchos::RCP<const Matrix>& A, const Vector& b, Vector& x) {
    return to.doSolve(A, b, x);
  }
  static bool forwardRedo(LinearSolver& to) { return to.redoWithoutShortcut(); }
  Teuchos::RCP<MultiVector> nearNull_;
  Teuchos::RCP<Teuchos::StackedTimer> timer_;

 private:
  // doSolve and the residual of its x (the report, unchecked).
  SolveReport attempt(const Teuchos::RCP<const Matrix>& A, const Vector& b, Vector& x);
  // Throws LinearSolveError when the report fails the checks.
  void check(const SolveReport& report) const;
  SolveChecks checks_;
};

struct DirectSettings {
  std::string method = "KLU2";  // a name of directMethods()
  ReuseSettings reuse;
  SolveChecks checks;
};

struct GmresSettings {
  std::string preconditioner = "ILUT";  // ILUT, RILUK or MueLu
  int overlap = 1;  // of the additive Schwarz subdomains
  double fill = 2.0;  // ILUT level of fill, RILUK level k, MueLu's sweeps per level
  double tolerance = 1e-12;  // relative residual at which GMRES stops
  int maxIterations = 1000;
  int restart = 200;  // Krylov vectors kept before a restart
  SolveChecks checks;
};

std::unique_ptr<LinearSolver> makeDirectSolver(const DirectSettings& settings);
std::unique_ptr<LinearSolver> makeGmresSolver(const GmresSettings& settings);

}  // namespace bc::core
