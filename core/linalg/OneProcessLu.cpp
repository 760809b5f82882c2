// The Direct solver's factorization on one process (KLU2, UMFPACK), with Reuse Factorization.
#include <algorithm>
#include <stdexcept>

#include "core/ScopedTimer.hpp"
#include "DirectMethod.hpp"
#include "Krylov.hpp"
#include "Regularization.hpp"
#include "SerialLu.hpp"

namespace bc::core {

namespace {

// Solves A x = b on one process (A: all rows here). With `shortcuts`: GMRES preconditioned with the
// last factorization when reuse is on (of any pattern), and a refactorization with the last pivot
// order when A is the last matrix with new values (`sameGraph`). After a graph change the pivots are
// chosen afresh: the old order, chosen for another active set, made the factorizations of the
// 32 x 32 layers with Lagrange multipliers 80 % slower (11.0 s against 6.1 s for 19).
class OneProcessLu : public DirectMethod {
 public:
  OneProcessLu(std::unique_ptr<SerialLu> lu, const ReuseSettings& reuse) : lu_(std::move(lu)), reuse_(reuse) {}
  std::string name() const override { return lu_->name(); }

  int solve(const Matrix& A, bool shortcuts, bool sameGraph, const Vector& b, Vector& x) override {
    shortcut_ = false;
    auto xv = x.getDataNonConst();
    const auto bv = b.getData();
    int iterations = -1;
    if (shortcuts && reuse_.on && reuseOld(A, bv.getRawPtr(), xv.getRawPtr(), iterations)) return iterations;
    // A saddle point (Lagrange multipliers) is factored with its zero diagonal regularized, and GMRES
    // preconditioned with that factorization solves A itself; when GMRES does not get there, A is
    // factored as it is.
    bool regularizedFailed = false;
    if (reuse_.on && regularization_.regularize(A) > 0) {
      if (regularizedSolve(A, shortcuts && sameGraph, bv.getRawPtr(), xv.getRawPtr(), iterations)) return iterations;
      regularizedFailed = true;
    }
    {
      ScopedTimer stage(timer_, "Factorization");
      const bool refactor = !regularizedFailed && shortcuts && sameGraph && lu_->factored();
      shortcut_ = refactor && lu_->refactorKeepsPivots();
      sinceFactorization_ = 0;
      lu_->factor(A, refactor);
    }
    ScopedTimer stage(timer_, "Triangular Solves");
    lu_->solve(bv.getRawPtr(), xv.getRawPtr());
    return 0;
  }

 private:
  // Rent or buy: GMRES iterations with the last factorization, summed over the solves since it, are
  // spent up to the limit (about what one factorization costs); then the matrix is factored.
  // Automatic: the flop count puts a factorization at 8 to 48 iterations from 10^2 to 10^4 contact
  // points, where timings put it at 17 to 26 (triangular solves are slower per flop at scale); half
  // the count, at least 10, keeps within a factor of two of the time where it matters. Returns
  // whether GMRES solved (its iterations in `iterations`).
  bool reuseOld(const Matrix& A, const double* b, double* x, int& iterations) {
    const int limit = reuse_.iterationLimit > 0 ? reuse_.iterationLimit
                                                : std::max(10, static_cast<int>(0.5 * lu_->iterationsWorth()));
    if (!lu_->factored() || sinceFactorization_ >= limit) return false;
    ScopedTimer stage(timer_, "Krylov Iterations");
    iterations = lu_->solvePreconditioned(A, b, x, limit - sinceFactorization_, reuse_.target);
    if (iterations < 0) return false;
    shortcut_ = true;
    sinceFactorization_ += iterations;
    return true;
  }

  // The regularized saddle point factored (refactored with the last pivots when `mayRefactor` and
  // there is a factorization) and GMRES preconditioned with it; returns whether GMRES solved A.
  bool regularizedSolve(const Matrix& A, bool mayRefactor, const double* b, double* x, int& iterations) {
    const bool refactor = mayRefactor && lu_->factored();
    {
      ScopedTimer stage(timer_, "Factorization");
      sinceFactorization_ = 0;
      shortcut_ = refactor && lu_->refactorKeepsPivots();
      lu_->preferDiagonalPivots(true);
      try {
        lu_->factor(A, refactor, regularization_.values());
      } catch (const std::runtime_error&) {
        lu_->preferDiagonalPivots(false);
        return false;  // (a singular regularized matrix): A as it is
      }
      lu_->preferDiagonalPivots(false);
    }
    ScopedTimer stage(timer_, "Krylov Iterations");
    iterations = lu_->solvePreconditioned(A, b, x, kMaxKrylov, reuse_.target);
    if (iterations < 0) return false;
    sinceFactorization_ = iterations;
    return true;
  }

  std::unique_ptr<SerialLu> lu_;
  ReuseSettings reuse_;
  SaddlePointRegularization regularization_;
  int sinceFactorization_ = 0;  // GMRES iterations with the last factorization
};

}  // namespace

std::unique_ptr<DirectMethod> oneProcessLu(std::unique_ptr<SerialLu> lu, const ReuseSettings& reuse) {
  return std::make_unique<OneProcessLu>(std::move(lu), reuse);
}

}  // namespace bc::core
