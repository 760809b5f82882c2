// UMFPACK (SuiteSparse's multifrontal LU, dense kernels through BLAS) on a one-process matrix. Against
// KLU2 (no supernodes) it pays from about 10^4 rows: at 10^4 contact points of the crossed layers,
// 1.7-1.9 s against 5.1-6.7 s per factorization of the Penalty matrix and 5-8 s against 39-54 s of
// the Lagrange saddle point (docs/scale.md). A later matrix of the same pattern keeps the symbolic
// analysis (the column ordering); its pivots are chosen afresh.
#pragma once
#include <vector>

#include "SerialLu.hpp"

namespace bc::core {

class SerialUmfpack : public SerialLu {
 public:
  SerialUmfpack();
  ~SerialUmfpack() override;
  std::string name() const override { return "UMFPACK"; }
  void factor(const Matrix& A, bool refactor) override;
  void solve(const double* b, double* x) const override;
  bool factored() const override { return numeric_ != nullptr; }

 private:
  void release();
  void* symbolic_ = nullptr;
  void* numeric_ = nullptr;
  std::vector<double> control_;
  // UMFPACK wants the indices within a compressed column (here: a row of A) ascending: the pattern's
  // rows sorted, and where A's entry k of such a row went (empty when already in order).
  std::vector<int> sortedColumns_, order_;
  std::vector<double> sortedValues_;
};

}  // namespace bc::core
