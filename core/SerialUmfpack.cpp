#include "SerialUmfpack.hpp"

#include "LinearSolver.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

#include <suitesparse/umfpack.h>

namespace bc::core {

namespace {
std::string statusText(int status) {
  switch (status) {
    case UMFPACK_WARNING_singular_matrix: return "singular matrix";
    case UMFPACK_ERROR_out_of_memory: return "out of memory";
    case UMFPACK_ERROR_invalid_matrix: return "invalid matrix";
    default: return "UMFPACK status " + std::to_string(status);
  }
}
}  // namespace

SerialUmfpack::SerialUmfpack() : control_(UMFPACK_CONTROL) {
  umfpack_di_defaults(control_.data());
  // No iterative refinement within UMFPACK: every solve is checked by its residual (LinearSolver),
  // and with Reuse Factorization GMRES refines.
  control_[UMFPACK_IRSTEP] = 0;
}

SerialUmfpack::~SerialUmfpack() { release(); }

void SerialUmfpack::release() {
  if (numeric_) umfpack_di_free_numeric(&numeric_);
  if (symbolic_) umfpack_di_free_symbolic(&symbolic_);
  numeric_ = symbolic_ = nullptr;
}

void SerialUmfpack::factor(const Matrix& A, bool /*refactor: the symbolic analysis is kept by pattern*/) {
  const auto local = A.getLocalMatrixHost();
  const double* values = local.values.data();
  std::vector<double> info(UMFPACK_INFO);
  if (!(symbolic_ && pattern_.same(A))) {
    release();
    pattern_.take(A);
    // Each row's entries in ascending column order.
    const auto& p = pattern_;
    order_.clear();
    sortedColumns_ = p.columns;
    bool sorted = true;
    for (int i = 0; i < p.n && sorted; ++i)
      sorted = std::is_sorted(p.columns.begin() + p.rowStart[i], p.columns.begin() + p.rowStart[i + 1]);
    if (!sorted) {
      order_.resize(p.columns.size());
      std::iota(order_.begin(), order_.end(), 0);
      for (int i = 0; i < p.n; ++i)
        std::sort(order_.begin() + p.rowStart[i], order_.begin() + p.rowStart[i + 1],
                  [&](int a, int b) { return p.columns[a] < p.columns[b]; });
      for (std::size_t k = 0; k < order_.size(); ++k) sortedColumns_[k] = p.columns[order_[k]];
    }
  }
  if (!order_.empty()) {
    sortedValues_.resize(order_.size());
    for (std::size_t k = 0; k < order_.size(); ++k) sortedValues_[k] = values[order_[k]];
    values = sortedValues_.data();
  }
  const auto& p = pattern_;
  if (!symbolic_) {
    const int status = umfpack_di_symbolic(p.n, p.n, p.rowStart.data(), sortedColumns_.data(), values, &symbolic_,
                                           control_.data(), info.data());
    if (status != UMFPACK_OK) {
      release();
      if (status == UMFPACK_ERROR_out_of_memory)
        throw LinearSolverOutOfMemory("UMFPACK ran out of memory analysing the " + std::to_string(p.n) +
                                      "-row matrix");
      throw std::runtime_error("UMFPACK analysis failed (" + statusText(status) + ")");
    }
  }
  if (numeric_) umfpack_di_free_numeric(&numeric_);
  const int status = umfpack_di_numeric(p.rowStart.data(), sortedColumns_.data(), values, symbolic_, &numeric_,
                                        control_.data(), info.data());
  // Warnings of an under- or overflowing determinant say nothing about the solve.
  if (status != UMFPACK_OK && status != UMFPACK_WARNING_determinant_underflow &&
      status != UMFPACK_WARNING_determinant_overflow) {
    if (numeric_) umfpack_di_free_numeric(&numeric_);
    numeric_ = nullptr;
    if (status == UMFPACK_ERROR_out_of_memory) {
      release();
      throw LinearSolverOutOfMemory(
          "UMFPACK ran out of memory factoring the " + std::to_string(p.n) + "-row matrix (" +
          std::to_string(p.columns.size()) + " entries; UMFPACK's 32-bit version addresses at most 16 GB of "
          "factors, and it stopped so on the crossed layers' 10^5 contact points, 1.2e6 rows): a smaller "
          "model, or Linear Solver/Type = GMRES");
    }
    throw std::runtime_error("UMFPACK numeric factorization failed (" + statusText(status) + ")");
  }
  setIterationsWorth(info[UMFPACK_FLOPS], info[UMFPACK_LNZ] + info[UMFPACK_UNZ] + p.n, double(p.columns.size()));
}

void SerialUmfpack::solve(const double* b, double* x) const {
  // UMFPACK holds A^T (A's rows as its columns): A x = b is its transposed system. (No statistics
  // wanted: a null Info.)
  const int status = umfpack_di_solve(UMFPACK_At, nullptr, nullptr, nullptr, x, b, numeric_, control_.data(),
                                      nullptr);
  if (status != UMFPACK_OK) throw std::runtime_error("UMFPACK solve failed (" + statusText(status) + ")");
}

}  // namespace bc::core
