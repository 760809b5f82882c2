#include "SerialLu.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "SerialKlu.hpp"
#include "SerialUmfpack.hpp"

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
  const double solve = 2.0 * factorNonzeros;
  const double iteration = 2.0 * solve + 2.0 * matrixNonzeros + 40.0 * pattern_.n;
  iterationsWorth_ = factorizationFlops / iteration;
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
  const auto multiply = [&](const double* v, double* out) {
    for (int i = 0; i < n; ++i) {
      double sum = 0.0;
      for (auto k = rowPtr(i); k < rowPtr(i + 1); ++k) sum += values[k] * v[columns[k]];
      out[i] = sum;
    }
  };
  const auto norm = [n](const double* v) {
    double s = 0.0;
    for (int i = 0; i < n; ++i) s += v[i] * v[i];
    return std::sqrt(s);
  };
  double frobenius = 0.0;
  for (std::size_t k = 0; k < entries.extent(0); ++k) frobenius += values[k] * values[k];
  frobenius = std::sqrt(frobenius);

  const int m = std::min(maxIterations, kMaxKrylov);
  if (m < 1) return -1;
  std::vector<double> H(std::size_t(m + 1) * m, 0.0), cs(m), sn(m), g(m + 1, 0.0);
  std::vector<double> z0(n), w(n);
  const double beta = norm(b);
  if (beta == 0.0) {
    std::fill(x, x + n, 0.0);
    return 0;
  }
  solve(b, z0.data());
  // The residual GMRES aims at; where x's norm turns out smaller than this estimate, it is lowered.
  double target = backwardError * (frobenius * norm(z0.data()) + beta);
  if (!std::isfinite(target)) return -1;
  // The basis V and its images Z = LU^-1 V, as many as the iterations take (x = Z y then needs no
  // further solve).
  std::vector<std::vector<double>> V, Z;
  // x = Z y with H y = g (the first k columns).
  std::vector<double> y(m);
  const auto form = [&](int k) {
    for (int i = k - 1; i >= 0; --i) {
      double s = g[i];
      for (int j = i + 1; j < k; ++j) s -= H[std::size_t(m) * i + j] * y[j];
      y[i] = s / H[std::size_t(m) * i + i];
    }
    std::fill(x, x + n, 0.0);
    for (int j = 0; j < k; ++j)
      for (int r = 0; r < n; ++r) x[r] += y[j] * Z[j][r];
  };
  V.emplace_back(n);
  for (int i = 0; i < n; ++i) V[0][i] = b[i] / beta;
  g[0] = beta;
  int k = 0;
  bool converged = false;
  while (k < m && !converged) {
    Z.emplace_back(n);
    double* z = Z[k].data();
    // LU^-1 v_0 = LU^-1 b / beta: solved above for the target.
    if (k == 0)
      for (int r = 0; r < n; ++r) z[r] = z0[r] / beta;
    else
      solve(V[k].data(), z);
    multiply(z, w.data());
    // Modified Gram-Schmidt, twice (the second pass keeps the basis orthogonal when w has cancelled).
    for (int pass = 0; pass < 2; ++pass)
      for (int i = 0; i <= k; ++i) {
        const double* vi = V[i].data();
        double h = 0.0;
        for (int r = 0; r < n; ++r) h += w[r] * vi[r];
        for (int r = 0; r < n; ++r) w[r] -= h * vi[r];
        H[std::size_t(m) * i + k] += h;
      }
    const double h1 = norm(w.data());
    H[std::size_t(m) * (k + 1) + k] = h1;
    V.emplace_back(n);
    if (h1 > 0.0)
      for (int r = 0; r < n; ++r) V[k + 1][r] = w[r] / h1;
    // Givens rotations keep H upper triangular; |g[k + 1]| is the residual norm.
    for (int i = 0; i < k; ++i) {
      const double a = H[std::size_t(m) * i + k], c = H[std::size_t(m) * (i + 1) + k];
      H[std::size_t(m) * i + k] = cs[i] * a + sn[i] * c;
      H[std::size_t(m) * (i + 1) + k] = -sn[i] * a + cs[i] * c;
    }
    const double a = H[std::size_t(m) * k + k], c = H[std::size_t(m) * (k + 1) + k];
    const double r = std::hypot(a, c);
    if (!(r > 0.0) || !std::isfinite(r)) return -1;
    cs[k] = a / r;
    sn[k] = c / r;
    H[std::size_t(m) * k + k] = r;
    H[std::size_t(m) * (k + 1) + k] = 0.0;
    g[k + 1] = -sn[k] * g[k];
    g[k] = cs[k] * g[k];
    ++k;
    if (std::abs(g[k]) > target && h1 != 0.0) continue;
    // Converged by GMRES's own measure: the true backward error of x decides.
    form(k);
    multiply(x, w.data());
    for (int i = 0; i < n; ++i) w[i] = b[i] - w[i];
    const double residual = norm(w.data()), required = backwardError * (frobenius * norm(x) + beta);
    if (!std::isfinite(residual) || !std::isfinite(required)) return -1;
    converged = residual <= required;
    if (!converged) {
      if (h1 == 0.0) return -1;
      target = std::min(target, std::abs(g[k])) * 0.5 * required / residual;
    }
  }
  return converged ? k : -1;
}

std::unique_ptr<SerialLu> makeSerialLu(const std::string& name) {
  if (name == "KLU2") return std::make_unique<SerialKlu>();
  if (name == "UMFPACK") return std::make_unique<SerialUmfpack>();
  throw std::invalid_argument("no sparse LU factorization named \"" + name + "\"");
}

}  // namespace bc::core
