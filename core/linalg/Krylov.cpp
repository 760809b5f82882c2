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

namespace {

// The state of one GMRES solve: the basis V and its images Z = M^-1 V (as many as the iterations
// take: x = Z y then needs no further preconditioner solve), the Hessenberg matrix H (m + 1 rows of
// m) kept upper triangular by the Givens rotations (cs, sn), and g, whose entry k + 1 is the residual
// norm after k + 1 iterations.
struct Arnoldi {
  Arnoldi(const KrylovSpace& space, int m)
      : space(space), n(space.n), m(m), H(std::size_t(m + 1) * m, 0.0), cs(m), sn(m), g(m + 1, 0.0), w(n), y(m) {}
  const KrylovSpace& space;
  const int n, m;
  std::vector<double> H, cs, sn, g, w, y;
  std::vector<std::vector<double>> V, Z;

  double& h(int i, int j) { return H[std::size_t(m) * i + j]; }
  double dot(const double* u, const double* v) const {
    double s = 0.0;
    for (int i = 0; i < n; ++i) s += u[i] * v[i];
    return space.sum(s);
  }
  double norm(const double* v) const { return std::sqrt(dot(v, v)); }

  // w = A z_k orthogonalized against v_0 .. v_k by modified Gram-Schmidt, twice (the second pass
  // keeps the basis orthogonal when w has cancelled), into column k of H and v_{k+1}; returns
  // ||w||, the subdiagonal entry.
  double extend(int k) {
    space.multiply(Z[k].data(), w.data());
    for (int pass = 0; pass < 2; ++pass)
      for (int i = 0; i <= k; ++i) {
        const double* vi = V[i].data();
        const double hik = dot(w.data(), vi);
        for (int r = 0; r < n; ++r) w[r] -= hik * vi[r];
        h(i, k) += hik;
      }
    const double h1 = norm(w.data());
    h(k + 1, k) = h1;
    V.emplace_back(n);
    if (h1 > 0.0)
      for (int r = 0; r < n; ++r) V[k + 1][r] = w[r] / h1;
    return h1;
  }

  // The earlier rotations and a new one applied to column k of H and to g; false when the new one
  // is not defined (a zero or non-finite column).
  bool rotate(int k) {
    for (int i = 0; i < k; ++i) {
      const double a = h(i, k), c = h(i + 1, k);
      h(i, k) = cs[i] * a + sn[i] * c;
      h(i + 1, k) = -sn[i] * a + cs[i] * c;
    }
    const double a = h(k, k), c = h(k + 1, k);
    const double r = std::hypot(a, c);
    if (!(r > 0.0) || !std::isfinite(r)) return false;
    cs[k] = a / r;
    sn[k] = c / r;
    h(k, k) = r;
    h(k + 1, k) = 0.0;
    g[k + 1] = -sn[k] * g[k];
    g[k] = cs[k] * g[k];
    return true;
  }

  // x = Z y with H y = g (the first k columns).
  void form(int k, double* x) {
    for (int i = k - 1; i >= 0; --i) {
      double s = g[i];
      for (int j = i + 1; j < k; ++j) s -= h(i, j) * y[j];
      y[i] = s / h(i, i);
    }
    std::fill(x, x + n, 0.0);
    for (int j = 0; j < k; ++j)
      for (int r = 0; r < n; ++r) x[r] += y[j] * Z[j][r];
  }
};

}  // namespace

int gmres(const KrylovSpace& space, const double* b, double* x, int maxIterations, double backwardError,
          double frobenius) {
  const int n = space.n;
  const int m = std::min(maxIterations, kMaxKrylov);
  if (m < 1) return -1;
  Arnoldi a(space, m);
  std::vector<double> z0(n);
  const double beta = a.norm(b);
  if (beta == 0.0) {
    std::fill(x, x + n, 0.0);
    return 0;
  }
  space.precondition(b, z0.data());
  // The residual GMRES aims at; where x's norm turns out smaller than this estimate, it is lowered.
  double target = backwardError * (frobenius * a.norm(z0.data()) + beta);
  if (!std::isfinite(target)) return -1;
  a.V.emplace_back(n);
  for (int i = 0; i < n; ++i) a.V[0][i] = b[i] / beta;
  a.g[0] = beta;
  for (int k = 0; k < m;) {
    a.Z.emplace_back(n);
    double* z = a.Z[k].data();
    // M^-1 v_0 = M^-1 b / beta: solved above for the target.
    if (k == 0)
      for (int r = 0; r < n; ++r) z[r] = z0[r] / beta;
    else space.precondition(a.V[k].data(), z);
    const double h1 = a.extend(k);
    if (!a.rotate(k)) return -1;
    ++k;
    if (std::abs(a.g[k]) > target && h1 != 0.0) continue;
    // Converged by GMRES's own measure: the true backward error of x decides.
    a.form(k, x);
    space.multiply(x, a.w.data());
    for (int i = 0; i < n; ++i) a.w[i] = b[i] - a.w[i];
    const double residual = a.norm(a.w.data()), required = backwardError * (frobenius * a.norm(x) + beta);
    if (!std::isfinite(residual) || !std::isfinite(required)) return -1;
    if (residual <= required) return k;
    if (h1 == 0.0) return -1;
    target = std::min(target, std::abs(a.g[k])) * 0.5 * required / residual;
  }
  return -1;
}

}  // namespace bc::core
