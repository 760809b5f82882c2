#include "SerialKlu.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

// KLU2's headers define their templates in the namespace they are included in (as Amesos2 does).
namespace KLU2 {
#include <klu2_defaults.hpp>
#include <klu2_analyze.hpp>
#include <klu2_factor.hpp>
#include <klu2_tsolve.hpp>
// klu2.h declares klu_refactor with Entry values, klu2_refactor.hpp defines it with double values:
// two templates that no call can choose between. The definition is taken under its own name.
// It also calls klu_scale with NULL for the (template) workspace pointer, which deduces nothing: this
// overload takes that call.
inline int klu_scale(int scale, int n, int Ap[], int Ai[], double Ax[], double Rs[], decltype(NULL),
                     klu_common<double, int>* common) {
  return klu_scale<double, int>(scale, n, Ap, Ai, Ax, Rs, static_cast<int*>(nullptr), common);
}
#undef KLU_refactor
#define KLU_refactor klu_refactor_definition
#include <klu2_refactor.hpp>
#undef KLU_refactor
#include <klu2_free_symbolic.hpp>
#include <klu2_free_numeric.hpp>
#include <klu2_diagnostics.hpp>
}  // namespace KLU2

namespace bc::core {

namespace {
// A's column indices in its row map's local numbering (A on one process: every column is a row).
std::vector<int> rowMapColumns(const Matrix& A) {
  const auto entries = A.getLocalMatrixHost().graph.entries;
  const auto& rowMap = *A.getRowMap();
  const auto& colMap = *A.getColMap();
  std::vector<int> columns(entries.extent(0));
  for (std::size_t k = 0; k < columns.size(); ++k)
    columns[k] = rowMap.getLocalElement(colMap.getGlobalElement(entries(k)));
  return columns;
}
}  // namespace

struct SerialKlu::Data {
  KLU2::klu_common<double, int> common;
  KLU2::klu_symbolic<double, int>* symbolic = nullptr;
  KLU2::klu_numeric<double, int>* numeric = nullptr;
  // A's rows in compressed form with row-map local column indices. KLU2 reads compressed columns:
  // it sees A^T, so a solve with A is its transposed solve.
  std::vector<int> rowStart, columns, rawColumns;  // rawColumns: A's own local column indices
  int n = 0;
  double iterationsWorth = 0.0;  // see factor()

  // Whether A's compressed rows (n rows) are the factorization's, so its column indices serve.
  template <class Local>
  bool samePattern(const Local& local, int rows) const {
    const auto& rowPtr = local.graph.row_map;
    const auto& entries = local.graph.entries;
    return rows == n && rawColumns.size() == entries.extent(0) &&
           std::equal(rowStart.begin(), rowStart.end(), rowPtr.data()) &&
           std::equal(rawColumns.begin(), rawColumns.end(), entries.data());
  }

  void release() {
    if (numeric) ::KLU2::klu_free_numeric<double, int>(&numeric, &common);
    if (symbolic) ::KLU2::klu_free_symbolic<double, int>(&symbolic, &common);
    numeric = nullptr;
    symbolic = nullptr;
  }
};

SerialKlu::SerialKlu() : d_(std::make_unique<Data>()) { ::KLU2::klu_defaults<double, int>(&d_->common); }

SerialKlu::~SerialKlu() { d_->release(); }

bool SerialKlu::factored() const { return d_->numeric != nullptr; }

void SerialKlu::factor(const Matrix& A, bool refactor) {
  const auto local = A.getLocalMatrixHost();
  const int n = static_cast<int>(A.getRowMap()->getNodeNumElements());
  double* values = const_cast<double*>(local.values.data());
  // A refactorization needs the very same compressed rows as the factorization it reuses.
  const auto& rowPtr = local.graph.row_map;
  const auto& entries = local.graph.entries;
  if (!(refactor && factored() && d_->samePattern(local, n))) {
    d_->release();
    d_->n = n;
    d_->rowStart.assign(rowPtr.data(), rowPtr.data() + n + 1);
    d_->rawColumns.assign(entries.data(), entries.data() + entries.extent(0));
    d_->columns = rowMapColumns(A);
    d_->symbolic = ::KLU2::klu_analyze<double, int>(n, d_->rowStart.data(), d_->columns.data(), &d_->common);
    if (!d_->symbolic) throw std::runtime_error("KLU2 analysis failed");
    d_->numeric = ::KLU2::klu_factor<double, int>(d_->rowStart.data(), d_->columns.data(), values, d_->symbolic,
                                                  &d_->common);
    if (!d_->numeric) throw std::runtime_error("KLU2 numeric factorization failed (singular matrix)");
    // The cost of a factorization against that of one GMRES iteration with it (two triangular
    // solves with L and U and the off-diagonal blocks, a product with A, and the orthogonalization
    // against about 10 basis vectors, twice): the iterations one factorization is worth.
    ::KLU2::klu_flops<double, int>(d_->symbolic, d_->numeric, &d_->common);
    const double solve = 2.0 * (double(d_->numeric->lnz) + d_->numeric->unz + d_->numeric->nzoff);
    const double iteration = 2.0 * solve + 2.0 * double(entries.extent(0)) + 40.0 * n;
    d_->iterationsWorth = d_->common.flops / iteration;
    return;
  }
  // A pivot of the old order that is zero now: factor afresh, with pivoting.
  if (!::KLU2::klu_refactor_definition<double, int>(d_->rowStart.data(), d_->columns.data(), values, d_->symbolic,
                                                    d_->numeric, &d_->common))
    factor(A, false);
}

double SerialKlu::iterationsWorth() const { return d_->iterationsWorth; }

int SerialKlu::solvePreconditioned(const Matrix& A, const double* b, double* x, int maxIterations,
                                   double backwardError) const {
  const auto local = A.getLocalMatrixHost();
  const int n = static_cast<int>(A.getRowMap()->getNodeNumElements());
  if (!factored() || n != d_->n) return -1;
  const auto& rowPtr = local.graph.row_map;
  const auto& entries = local.graph.entries;
  const double* values = local.values.data();
  // A's column indices in row-map order: the factorization's when A has its pattern.
  const bool samePattern = d_->samePattern(local, n);
  const std::vector<int> ownColumns = samePattern ? std::vector<int>{} : rowMapColumns(A);
  const int* columns = samePattern ? d_->columns.data() : ownColumns.data();
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
  std::vector<double> V(std::size_t(n) * (m + 1)), H(std::size_t(m + 1) * m, 0.0), cs(m), sn(m), g(m + 1, 0.0);
  std::vector<double> z(n), w(n);
  const double beta = norm(b);
  if (beta == 0.0) {
    std::fill(x, x + n, 0.0);
    return 0;
  }
  solve(b, z.data());
  // The residual GMRES aims at; where x's norm turns out smaller than this estimate, it is lowered.
  double target = backwardError * (frobenius * norm(z.data()) + beta);
  if (!std::isfinite(target)) return -1;
  // x = LU^-1 V y with H y = g (the first k columns).
  std::vector<double> y(m);
  const auto form = [&](int k) {
    for (int i = k - 1; i >= 0; --i) {
      double s = g[i];
      for (int j = i + 1; j < k; ++j) s -= H[std::size_t(m) * i + j] * y[j];
      y[i] = s / H[std::size_t(m) * i + i];
    }
    std::fill(w.begin(), w.end(), 0.0);
    for (int j = 0; j < k; ++j)
      for (int r = 0; r < n; ++r) w[r] += y[j] * V[std::size_t(n) * j + r];
    solve(w.data(), x);
  };
  for (int i = 0; i < n; ++i) V[i] = b[i] / beta;
  g[0] = beta;
  int k = 0;
  bool converged = false;
  while (k < m && !converged) {
    double* v = &V[std::size_t(n) * k];
    solve(v, z.data());
    multiply(z.data(), w.data());
    // Modified Gram-Schmidt, twice (the second pass keeps the basis orthogonal when w has cancelled).
    for (int pass = 0; pass < 2; ++pass)
      for (int i = 0; i <= k; ++i) {
        const double* vi = &V[std::size_t(n) * i];
        double h = 0.0;
        for (int r = 0; r < n; ++r) h += w[r] * vi[r];
        for (int r = 0; r < n; ++r) w[r] -= h * vi[r];
        H[std::size_t(m) * i + k] += h;
      }
    const double h1 = norm(w.data());
    H[std::size_t(m) * (k + 1) + k] = h1;
    if (h1 > 0.0)
      for (int r = 0; r < n; ++r) V[std::size_t(n) * (k + 1) + r] = w[r] / h1;
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

void SerialKlu::solve(const double* b, double* x) const {
  std::copy(b, b + d_->n, x);
  if (!::KLU2::klu_tsolve<double, int>(d_->symbolic, d_->numeric, d_->n, 1, x, &d_->common))
    throw std::runtime_error("KLU2 solve failed");
}

}  // namespace bc::core
