#include "SerialLu.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "Krylov.hpp"

namespace bc::core {

std::vector<int> rowMapColumns(const Matrix& A) {
  const auto entries = A.getLocalMatrixHost().graph.entries;
  const auto& rowMap = *A.getRowMap();
  const auto& colMap = *A.getColMap();
  std::vector<int> columns(entries.extent(0));
  for (std::size_t k = 0; k < columns.size(); ++k)
    columns[k] = rowMap.getLocalElement(colMap.getGlobalElement(entries(k)));
  return columns;
}

bool SerialLu::Pattern::same(const Matrix& A) const {
  const auto local = A.getLocalMatrixHost();
  const auto& rowPtr = local.graph.row_map;
  const auto& entries = local.graph.entries;
  const int rows = static_cast<int>(A.getRowMap()->getNodeNumElements());
  return rows == n && rawColumns.size() == entries.extent(0) &&
         std::equal(rowStart.begin(), rowStart.end(), rowPtr.data()) &&
         std::equal(rawColumns.begin(), rawColumns.end(), entries.data());
}

void SerialLu::Pattern::take(const Matrix& A) {
  const auto local = A.getLocalMatrixHost();
  const auto& rowPtr = local.graph.row_map;
  const auto& entries = local.graph.entries;
  n = static_cast<int>(A.getRowMap()->getNodeNumElements());
  rowStart.assign(rowPtr.data(), rowPtr.data() + n + 1);
  rawColumns.assign(entries.data(), entries.data() + entries.extent(0));
  columns = rowMapColumns(A);
}

void SerialLu::setIterationsWorth(double factorizationFlops, double factorNonzeros, double matrixNonzeros) {
  iterationsWorth_ = core::iterationsWorth(factorizationFlops, factorNonzeros, matrixNonzeros, pattern_.n);
}

int SerialLu::solvePreconditioned(const Matrix& A, const double* b, double* x, int maxIterations,
                                  double backwardError) const {
  const auto local = A.getLocalMatrixHost();
  const int n = static_cast<int>(A.getRowMap()->getNodeNumElements());
  if (!factored() || n != pattern_.n) return -1;
  const auto& rowPtr = local.graph.row_map;
  const auto& entries = local.graph.entries;
  const double* values = local.values.data();
  // A's column indices in row-map order: the factorization's when A has its pattern.
  const bool samePattern = pattern_.same(A);
  const std::vector<int> ownColumns = samePattern ? std::vector<int>{} : rowMapColumns(A);
  const int* columns = samePattern ? pattern_.columns.data() : ownColumns.data();
  KrylovSpace space;
  space.n = n;
  space.multiply = [&](const double* v, double* out) {
    for (int i = 0; i < n; ++i) {
      double sum = 0.0;
      for (auto k = rowPtr(i); k < rowPtr(i + 1); ++k) sum += values[k] * v[columns[k]];
      out[i] = sum;
    }
  };
  space.precondition = [this](const double* v, double* out) { solve(v, out); };
  space.sum = [](double s) { return s; };
  double frobenius = 0.0;
  for (std::size_t k = 0; k < entries.extent(0); ++k) frobenius += values[k] * values[k];
  return gmres(space, b, x, maxIterations, backwardError, std::sqrt(frobenius));
}

}  // namespace bc::core
