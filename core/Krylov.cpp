#include "Krylov.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace bc::core {

double iterationsWorth(double factorizationFlops, double factorNonzeros, double matrixNonzeros, double rows) {
  const double solve = 2.0 * factorNonzeros;
  const double iteration = 2.0 * solve + 2.0 * matrixNonzeros + 40.0 * rows;
  return factorizationFlops / iteration;
}

int gmres(const KrylovSpace& space, const double* b, double* x, int maxIterations, double backwardError,
          double frobenius) {
  const int n = space.n;
  const auto dot = [&](const double* u, const double* v) {
    double s = 0.0;
    for (int i = 0; i < n; ++i) s += u[i] * v[i];
    return space.sum(s);
  };
  const auto norm = [&](const double* v) { return std::sqrt(dot(v, v)); };
  const int m = std::min(maxIterations, kMaxKrylov);
  if (m < 1) return -1;
  std::vector<double> H(std::size_t(m + 1) * m, 0.0), cs(m), sn(m), g(m + 1, 0.0);
  std::vector<double> z0(n), w(n);
  const double beta = norm(b);
  if (beta == 0.0) {
    std::fill(x, x + n, 0.0);
    return 0;
  }
  space.precondition(b, z0.data());
  // The residual GMRES aims at; where x's norm turns out smaller than this estimate, it is lowered.
  double target = backwardError * (frobenius * norm(z0.data()) + beta);
  if (!std::isfinite(target)) return -1;
  // The basis V and its images Z = M^-1 V, as many as the iterations take (x = Z y then needs no
  // further preconditioner solve).
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
    // M^-1 v_0 = M^-1 b / beta: solved above for the target.
    if (k == 0)
      for (int r = 0; r < n; ++r) z[r] = z0[r] / beta;
    else
      space.precondition(V[k].data(), z);
    space.multiply(z, w.data());
    // Modified Gram-Schmidt, twice (the second pass keeps the basis orthogonal when w has cancelled).
    for (int pass = 0; pass < 2; ++pass)
      for (int i = 0; i <= k; ++i) {
        const double* vi = V[i].data();
        const double h = dot(w.data(), vi);
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
    space.multiply(x, w.data());
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

}  // namespace bc::core
