// KLU2 called directly on a one-process matrix, so that Newton's later matrices of the same pattern
// are refactored with the pivot order of the last full factorization (klu_refactor: no pivot search,
// no new allocation) instead of factored afresh as Amesos2 does. Its own translation unit: KLU2's
// templates are instantiated here. Its GMRES reuses a factorization as the preconditioner of later
// matrices (LinearSolver's "Reuse Factorization").
#pragma once
#include <memory>
#include <vector>

#include "TpetraTypes.hpp"

namespace bc::core {

class SerialKlu {
 public:
  SerialKlu();
  ~SerialKlu();
  SerialKlu(const SerialKlu&) = delete;
  SerialKlu& operator=(const SerialKlu&) = delete;

  // Factors A (on one process). `refactor`: A has the pattern of the last factorization; its pivot
  // order is kept. Throws std::runtime_error when KLU2 fails (a singular matrix).
  void factor(const Matrix& A, bool refactor);
  // Solves A x = b with the last factorization (x and b: the row map's local order).
  void solve(const double* b, double* x) const;
  bool factored() const;
  // The GMRES iterations of solvePreconditioned that cost as many floating-point operations as the
  // last full factorization (KLU2's flop count).
  double iterationsWorth() const;
  // Solves A x = b by GMRES (no restart) right-preconditioned with the last factorization, which may
  // be of an earlier matrix of A's size (A: one process). Stops when the true residual ||b - A x||
  // is at most `backwardError` (||A||_F ||x|| + ||b||). Returns the iterations taken, or -1 when
  // `maxIterations` (at most kMaxKrylov: the basis is kept) did not get there (x is then undefined).
  static constexpr int kMaxKrylov = 100;
  int solvePreconditioned(const Matrix& A, const double* b, double* x, int maxIterations, double backwardError) const;

 private:
  struct Data;
  std::unique_ptr<Data> d_;
};

}  // namespace bc::core
