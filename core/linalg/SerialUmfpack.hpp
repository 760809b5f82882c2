// UMFPACK (SuiteSparse's multifrontal LU, dense kernels through BLAS) on a one-process matrix. Against
// KLU2 (no dense kernels) it pays from about 10^3 contact points of the crossed layers with Reuse
// Factorization; at 10^4 points it factors the Penalty matrix in 1.7-2.2 s against KLU2's 5.1-6.7 s,
// and the Lagrange saddle point in 8-13 s against 39-54 s (docs/scale.md). A later matrix of the same
// pattern keeps the symbolic analysis (the column ordering); its pivots are chosen afresh. The 32-bit
// version (umfpack_di) serves until its 32-bit addressing of the factors runs out, the 64-bit one
// (umfpack_dl, about 15 % slower at 10^4 points) from then on.
#pragma once
#include <vector>

#include "SerialLu.hpp"

namespace bc::core {

class SerialUmfpack : public SerialLu {
 public:
  // `wide`: the 64-bit version from the start (tests; otherwise it is taken when the 32-bit one runs
  // out).
  explicit SerialUmfpack(bool wide = false);
  ~SerialUmfpack() override;
  std::string name() const override { return "UMFPACK"; }
  using SerialLu::factor;
  void factor(const Matrix& A, bool refactor, const double* values) override;
  void preferDiagonalPivots(bool on) override;
  void solve(const double* b, double* x) const override;
  bool factored() const override { return numeric_ != nullptr; }

 private:
  void release();
  void freeNumeric();
  // UMFPACK's symbolic analysis and numeric factorization with the 32- or 64-bit version (wide_);
  // they return its status.
  int analyse(const double* values, double* info);
  int factorValues(const double* values, double* info);
  bool wide_ = false;
  double symmetricPivotTolerance_ = 0.001;  // the library default, restored by preferDiagonalPivots(false)
  void* symbolic_ = nullptr;
  void* numeric_ = nullptr;
  std::vector<double> control_;
  // UMFPACK wants the indices within a compressed column (here: a row of A) ascending: the pattern's
  // rows sorted, and where A's entry k of such a row went (empty when already in order).
  std::vector<int> sortedColumns_, order_;
  std::vector<double> sortedValues_;
  // The pattern's indices for the 64-bit version.
  std::vector<long> wideRowStart_, wideColumns_;
};

}  // namespace bc::core
