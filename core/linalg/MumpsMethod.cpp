// The Direct solver's MUMPS: the matrix factored where its rows are, by every rank, with Reuse
// Factorization's GMRES over the ranks.
#include <algorithm>
#include <stdexcept>

#include "core/ScopedTimer.hpp"
#include "DirectMethod.hpp"
#include "Krylov.hpp"
#include "MumpsLu.hpp"
#include "Regularization.hpp"

namespace bc::core {

namespace {

class MumpsMethod : public DirectMethod {
 public:
  MumpsMethod(const Comm& comm, const ReuseSettings& reuse) : mumps_(comm), reuse_(reuse) {}
  std::string name() const override { return "MUMPS"; }

  // As OneProcessLu's solve (the pivots are chosen afresh at every factorization: `sameGraph` is not
  // needed), the GMRES of Reuse Factorization over the ranks.
  int solve(const Matrix& A, bool shortcuts, bool /*sameGraph*/, const Vector& b, Vector& x) override {
    shortcut_ = false;
    auto xv = x.getDataNonConst();
    const auto bv = b.getData();
    const int n = static_cast<int>(A.getRowMap()->getNodeNumElements());
    Vector in(A.getDomainMap()), out(A.getRangeMap());
    const KrylovSpace space = krylovSpace(A, n, in, out);
    int iterations = -1;
    if (shortcuts && reuse_.on && reuseOld(A, space, bv.getRawPtr(), xv.getRawPtr(), iterations)) return iterations;
    if (reuse_.on && regularization_.regularizeOverRanks(A) > 0 &&
        regularizedSolve(A, space, bv.getRawPtr(), xv.getRawPtr(), iterations))
      return iterations;
    {
      ScopedTimer analysis(timer_, "Analysis");
      mumps_.analyseIfNew(A);
    }
    {
      ScopedTimer stage(timer_, "Factorization");
      sinceFactorization_ = 0;
      mumps_.factor(A);
    }
    ScopedTimer stage(timer_, "Triangular Solves");
    mumps_.solve(bv.getRawPtr(), xv.getRawPtr());
    return 0;
  }

 private:
  // GMRES's operations on this rank's rows: products with A through the Tpetra vectors `in` and
  // `out`, MUMPS's solve as preconditioner, and sums reduced on rank 0 and sent to all (every rank
  // follows the same iteration).
  KrylovSpace krylovSpace(const Matrix& A, int n, Vector& in, Vector& out) {
    const MPI_Comm mpi = rawMpiComm(*A.getRowMap()->getComm());
    KrylovSpace space;
    space.n = n;
    space.multiply = [&A, &in, &out, n](const double* v, double* result) {
      {
        auto d = in.getDataNonConst();
        std::copy(v, v + n, d.getRawPtr());
      }
      A.apply(in, out);
      const auto r = out.getData();
      std::copy(r.getRawPtr(), r.getRawPtr() + n, result);
    };
    space.precondition = [this](const double* v, double* result) { mumps_.solve(v, result); };
    space.sum = [mpi](double mine) {
      double all = 0.0;
      MPI_Reduce(&mine, &all, 1, MPI_DOUBLE, MPI_SUM, 0, mpi);
      MPI_Bcast(&all, 1, MPI_DOUBLE, 0, mpi);
      return all;
    };
    return space;
  }

  // GMRES preconditioned with the last factorization, up to the iteration limit (OneProcessLu's
  // reuseOld); returns whether it solved.
  bool reuseOld(const Matrix& A, const KrylovSpace& space, const double* b, double* x, int& iterations) {
    const int limit = reuse_.iterationLimit > 0 ? reuse_.iterationLimit
                                                : std::max(10, static_cast<int>(0.5 * mumps_.iterationsWorth()));
    if (!(mumps_.factored() && sinceFactorization_ < limit && mumps_.fits(A))) return false;
    ScopedTimer stage(timer_, "Krylov Iterations");
    iterations = gmres(space, b, x, limit - sinceFactorization_, reuse_.target, A.getFrobeniusNorm());
    if (iterations < 0) return false;
    shortcut_ = true;
    sinceFactorization_ += iterations;
    return true;
  }

  // The regularized saddle point factored and GMRES preconditioned with it; returns whether GMRES
  // solved A.
  bool regularizedSolve(const Matrix& A, const KrylovSpace& space, const double* b, double* x, int& iterations) {
    {
      {
        ScopedTimer analysis(timer_, "Analysis");
        mumps_.analyseIfNew(A);
      }
      ScopedTimer stage(timer_, "Factorization");
      sinceFactorization_ = 0;
      mumps_.preferDiagonalPivots(true);
      try {
        mumps_.factor(A, regularization_.values());
      } catch (const std::runtime_error&) {
        mumps_.preferDiagonalPivots(false);
        return false;  // (a singular regularized matrix, on every rank): A as it is
      }
      mumps_.preferDiagonalPivots(false);
    }
    ScopedTimer stage(timer_, "Krylov Iterations");
    iterations = gmres(space, b, x, kMaxKrylov, reuse_.target, A.getFrobeniusNorm());
    if (iterations < 0) return false;
    sinceFactorization_ = iterations;
    return true;
  }

  MumpsLu mumps_;
  ReuseSettings reuse_;
  SaddlePointRegularization regularization_;
  int sinceFactorization_ = 0;  // GMRES iterations with the last factorization
};

}  // namespace

std::unique_ptr<DirectMethod> makeMumpsMethod(const Comm& comm, const ReuseSettings& reuse) {
  return std::make_unique<MumpsMethod>(comm, reuse);
}

}  // namespace bc::core
