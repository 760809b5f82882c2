// Sparse LU factorizations of a one-process matrix, behind the Direct linear solver: KLU2 (SerialKlu)
// and UMFPACK (SerialUmfpack). Both read A's compressed rows as the compressed columns of A^T, so a
// solve with A is their transposed solve. The GMRES of solvePreconditioned, common to both, reuses a
// factorization as the preconditioner of later matrices (LinearSolver's "Reuse Factorization").
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/TpetraTypes.hpp"

namespace bc::core {

class SerialLu {
 public:
  virtual ~SerialLu() = default;
  SerialLu() = default;
  SerialLu(const SerialLu&) = delete;
  SerialLu& operator=(const SerialLu&) = delete;

  virtual std::string name() const = 0;
  // Factors A (on one process). `refactor`: A is the last factorization's matrix with new values,
  // and the factorization may keep what it chose for it (KLU2: the pivot order). `values`, when not
  // null: factored in place of A's values (one per entry of A's compressed rows). Throws
  // std::runtime_error when the factorization fails (a singular matrix).
  virtual void factor(const Matrix& A, bool refactor, const double* values) = 0;
  void factor(const Matrix& A, bool refactor) { factor(A, refactor, nullptr); }
  // Solves A x = b with the last factorization (x and b: the row map's local order).
  virtual void solve(const double* b, double* x) const = 0;
  virtual bool factored() const = 0;
  // With `on`, the next factorizations take a nonzero diagonal entry as its column's pivot whenever
  // the fill-reducing order reaches it, however small it is against the column (for a saddle point
  // whose zero diagonal was replaced by a small one: DirectSolver with Reuse Factorization); off (the
  // default), the library's threshold test chooses.
  virtual void preferDiagonalPivots(bool on) = 0;
  // Whether factor(A, true) keeps choices made for an earlier matrix that may not suit A (KLU2's
  // pivot order): a solve after it that fails its check is done again with a fresh factorization.
  virtual bool refactorKeepsPivots() const { return false; }
  // The GMRES iterations of solvePreconditioned that cost as many floating-point operations as the
  // last factorization (the library's own flop count).
  double iterationsWorth() const { return iterationsWorth_; }

  // Solves A x = b by GMRES (no restart) right-preconditioned with the last factorization, which may
  // be of an earlier matrix of A's size (A: one process). Stops when the true residual ||b - A x||
  // is at most `backwardError` (||A||_F ||x|| + ||b||). Returns the iterations taken, or -1 when
  // `maxIterations` (at most kMaxKrylov of Krylov.hpp: the basis is kept) did not get there (x is then
  // undefined).
  int solvePreconditioned(const Matrix& A, const double* b, double* x, int maxIterations, double backwardError) const;

 protected:
  // The compressed rows of the last factorization's matrix, column indices in row-map numbering.
  struct Pattern {
    std::vector<int> rowStart, columns;
    std::vector<int> rawColumns;  // A's own local column indices
    int n = 0;
    // Whether A's compressed rows are these (so that `columns` serve for A).
    bool same(const Matrix& A) const;
    void take(const Matrix& A);
  };
  Pattern pattern_;
  // The iterations one factorization is worth (Krylov.hpp's iterationsWorth), from its flop count
  // and the nonzeros of its factors.
  void setIterationsWorth(double factorizationFlops, double factorNonzeros, double matrixNonzeros);

 private:
  double iterationsWorth_ = 0.0;
};

// Each entry of A's compressed rows: its column's index in A's row map (A on one process: every
// column is a row; -1 where a column is not).
std::vector<int> rowMapColumns(const Matrix& A);

}  // namespace bc::core
