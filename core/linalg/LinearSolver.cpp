#include "LinearSolver.hpp"

#include <cmath>
#include <sstream>

#include "core/ScopedTimer.hpp"

namespace bc::core {

SolveReport LinearSolver::attempt(const Teuchos::RCP<const Matrix>& A, const Vector& b, Vector& x) {
  SolveReport report;
  try {
    report.iterations = doSolve(A, b, x);
  } catch (const LinearSolveError&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    rethrowIfOutOfMemory(e);  // (Kokkos' failed allocation: a std::runtime_error)
    // Belos and MueLu report over several lines; the first names the failure.
    std::string what = e.what();
    what = what.substr(0, what.find('\n'));
    throw LinearSolveError(name() +
                           " failed, the tangent matrix is probably singular (a free motion: a beam "
                           "without enough supports, or a contact constraint that fixes nothing): " +
                           what);
  }
  ScopedTimer stage(timer_, "Residual Check");
  const int iterations = report.iterations;
  report = residualReport(*A, b, x);
  report.iterations = iterations;
  return report;
}

double scaledNorm2(const Vector& v) {
  const double m = v.normInf();
  if (!(m > 0.0) || !std::isfinite(m)) return m;
  if (m >= 1e-150 && m <= 1e150) return v.norm2();
  Vector scaled(v, Teuchos::Copy);
  scaled.scale(1.0 / m);
  return m * scaled.norm2();
}

SolveReport residualReport(const Matrix& A, const Vector& b, const Vector& x) {
  SolveReport report;
  Vector r(b.getMap());
  A.apply(x, r);
  r.update(1.0, b, -1.0);
  // Scaled norms: with forces of 1e-200 the plain norms of b and r are 0, and both checks pass
  // whatever x is.
  const double bn = scaledNorm2(b), rn = scaledNorm2(r), an = A.getFrobeniusNorm();
  report.solutionNorm = scaledNorm2(x);
  const double scale = an * report.solutionNorm + bn;
  report.relativeResidual = bn > 0.0 ? rn / bn : rn;
  report.backwardError = scale > 0.0 ? rn / scale : rn;
  report.conditionBound = bn > 0.0 ? an * report.solutionNorm / bn : 0.0;
  return report;
}

SolveReport LinearSolver::solve(const Teuchos::RCP<const Matrix>& A, const Vector& b, Vector& x) {
  SolveReport report = attempt(A, b, x);
  // A solve that took a shortcut (Direct: a refactorization with the last factorization's pivots,
  // chosen for other values) and is not accurate well below the check is redone without it.
  if (!(report.backwardError <= 1e-3 * checks_.residualTolerance) && redoWithoutShortcut()) report = attempt(A, b, x);
  check(report);
  return report;
}

void LinearSolver::check(const SolveReport& report) const {
  // ||A|| ||x|| / ||b|| is a lower bound of A's condition number (x = A^-1 b). Beyond what double
  // precision resolves, x has no correct digit even when its backward error is small: a solve of a
  // singular matrix returns a huge x whose residual is small against ||A|| ||x||.
  if (report.conditionBound > checks_.conditionLimit) {
    std::ostringstream s;
    s << name()
      << " linear solve: the tangent matrix is singular or nearly so (||A||_F ||x|| / ||b|| = " << report.conditionBound
      << " > Condition Limit " << checks_.conditionLimit
      << "): a free motion (a beam without enough supports) or dependent constraints (contact held at more "
         "points along a beam than its elements' nodes can move independently: refine the beams; with Lagrange "
         "multipliers, Penalty or Augmented Lagrange may pass there)";
    throw LinearSolveError(s.str());
  }
  if (!std::isfinite(report.backwardError) || !std::isfinite(report.solutionNorm) ||
      report.backwardError > checks_.residualTolerance) {
    std::ostringstream s;
    s << name()
      << " linear solve failed its residual check: ||b - A x|| / (||A||_F ||x|| + ||b||) = " << report.backwardError
      << " > Residual Check Tolerance " << checks_.residualTolerance
      << " (||b - A x|| / ||b|| = " << report.relativeResidual << ")";
    throw LinearSolveError(s.str());
  }
}

namespace {

// A sparse LU of the registry (DirectMethod.hpp), made for the matrix's communicator at the first
// solve. The Newton loop's shortcuts (a refactorization with old pivots, an old factorization reused)
// are left out of the solve after one whose result was not accurate well below the check.
class DirectSolver : public LinearSolver {
 public:
  explicit DirectSolver(const DirectSettings& s) : LinearSolver(s.checks), settings_(s) {}
  std::string name() const override { return "Direct (" + settings_.method + ")"; }

 protected:
  int doSolve(const Teuchos::RCP<const Matrix>& A, const Vector& b, Vector& x) override {
    if (!method_) method_ = makeDirectMethod(settings_.method, *A->getRowMap()->getComm(), settings_.reuse);
    method_->setTimer(timer_);
    // The same matrix object with new values: the assembler keeps it while its graph stands.
    const bool sameGraph = A == lastMatrix_;
    const bool shortcuts = !fresh_;  // on every rank alike
    fresh_ = false;
    lastMatrix_ = A;
    return method_->solve(*A, shortcuts, sameGraph, b, x);
  }
  // fresh_: the next solve is to take no shortcut.
  bool redoWithoutShortcut() override {
    fresh_ = method_ && method_->tookShortcut();
    return fresh_;
  }

 private:
  DirectSettings settings_;
  std::unique_ptr<DirectMethod> method_;
  Teuchos::RCP<const Matrix> lastMatrix_;
  bool fresh_ = false;
};

}  // namespace

std::unique_ptr<LinearSolver> makeDirectSolver(const DirectSettings& settings) {
  return std::make_unique<DirectSolver>(settings);
}

}  // namespace bc::core
