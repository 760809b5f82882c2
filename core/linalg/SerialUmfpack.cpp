#include "SerialUmfpack.hpp"

#include "Errors.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>
#include <type_traits>

#include <suitesparse/umfpack.h>

namespace bc::core {

static_assert(std::is_same<SuiteSparse_long, long>::value, "UMFPACK's 64-bit index is long here");

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

SerialUmfpack::SerialUmfpack(bool wide) : wide_(wide), control_(UMFPACK_CONTROL) {
  umfpack_di_defaults(control_.data());
  // No iterative refinement within UMFPACK: every solve is checked by its residual (LinearSolver),
  // and with Reuse Factorization GMRES refines.
  control_[UMFPACK_IRSTEP] = 0;
  symmetricPivotTolerance_ = control_[UMFPACK_SYM_PIVOT_TOLERANCE];
}

// UMFPACK's symmetric strategy (the one it chooses for these structurally symmetric matrices) takes
// the diagonal when it is at least this tolerance times its column's largest entry; zero takes any
// nonzero diagonal (and never a zero one while the column has another entry).
void SerialUmfpack::preferDiagonalPivots(bool on) {
  control_[UMFPACK_SYM_PIVOT_TOLERANCE] = on ? 0.0 : symmetricPivotTolerance_;
}

SerialUmfpack::~SerialUmfpack() { release(); }

void SerialUmfpack::freeNumeric() {
  if (numeric_ && wide_) umfpack_dl_free_numeric(&numeric_);
  if (numeric_ && !wide_) umfpack_di_free_numeric(&numeric_);
  numeric_ = nullptr;
}

void SerialUmfpack::release() {
  freeNumeric();
  if (symbolic_ && wide_) umfpack_dl_free_symbolic(&symbolic_);
  if (symbolic_ && !wide_) umfpack_di_free_symbolic(&symbolic_);
  symbolic_ = nullptr;
}

int SerialUmfpack::analyse(const double* values, double* info) {
  const auto& p = pattern_;
  if (!wide_)
    return umfpack_di_symbolic(p.n, p.n, p.rowStart.data(), sortedColumns_.data(), values, &symbolic_, control_.data(),
                               info);
  wideRowStart_.assign(p.rowStart.begin(), p.rowStart.end());
  wideColumns_.assign(sortedColumns_.begin(), sortedColumns_.end());
  return umfpack_dl_symbolic(p.n, p.n, wideRowStart_.data(), wideColumns_.data(), values, &symbolic_, control_.data(),
                             info);
}

int SerialUmfpack::factorValues(const double* values, double* info) {
  freeNumeric();
  const int status = wide_ ? umfpack_dl_numeric(wideRowStart_.data(), wideColumns_.data(), values, symbolic_, &numeric_,
                                                control_.data(), info)
                           : umfpack_di_numeric(pattern_.rowStart.data(), sortedColumns_.data(), values, symbolic_,
                                                &numeric_, control_.data(), info);
  // Warnings of an under- or overflowing determinant say nothing about the solve.
  if (status == UMFPACK_WARNING_determinant_underflow || status == UMFPACK_WARNING_determinant_overflow)
    return UMFPACK_OK;
  if (status != UMFPACK_OK) freeNumeric();
  return status;
}

void SerialUmfpack::factor(const Matrix& A, bool /*refactor: the symbolic analysis is kept by pattern*/,
                           const double* given) {
  const auto local = A.getLocalMatrixHost();
  const double* values = given ? given : local.values.data();
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
  const std::string matrix =
      "the " + std::to_string(p.n) + "-row matrix (" + std::to_string(p.columns.size()) + " entries)";
  // The 32-bit version first (about 15 % faster where it fits); when its 32-bit addressing of the
  // factors runs out (it did on the crossed layers' 10^5 contact points, 1.2e6 rows, at 6 GB
  // resident), the 64-bit version from then on. An out-of-memory of the 64-bit version is the
  // machine's.
  for (;;) {
    int status = UMFPACK_OK;
    if (!symbolic_) {
      status = analyse(values, info.data());
      if (status != UMFPACK_OK) {
        release();
        if (status != UMFPACK_ERROR_out_of_memory)
          throw std::runtime_error("UMFPACK analysis failed (" + statusText(status) + ")");
      }
    }
    if (status == UMFPACK_OK) status = factorValues(values, info.data());
    if (status == UMFPACK_OK) break;
    if (status != UMFPACK_ERROR_out_of_memory)
      throw std::runtime_error("UMFPACK numeric factorization failed (" + statusText(status) + ")");
    release();
    if (wide_)
      throw LinearSolverOutOfMemory("UMFPACK (64-bit) ran out of memory factoring " + matrix +
                                    ": a smaller model, a machine with more memory, or Linear Solver/Type = GMRES");
    wide_ = true;
  }
  setIterationsWorth(info[UMFPACK_FLOPS], info[UMFPACK_LNZ] + info[UMFPACK_UNZ] + p.n, double(p.columns.size()));
}

void SerialUmfpack::solve(const double* b, double* x) const {
  // UMFPACK holds A^T (A's rows as its columns): A x = b is its transposed system. (No statistics
  // wanted: a null Info.)
  const int status =
      wide_ ? umfpack_dl_solve(UMFPACK_At, nullptr, nullptr, nullptr, x, b, numeric_, control_.data(), nullptr)
            : umfpack_di_solve(UMFPACK_At, nullptr, nullptr, nullptr, x, b, numeric_, control_.data(), nullptr);
  if (status != UMFPACK_OK) throw std::runtime_error("UMFPACK solve failed (" + statusText(status) + ")");
}

}  // namespace bc::core
