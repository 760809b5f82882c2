// GMRES without restart, right-preconditioned, on vectors split over ranks or on one process: the
// Krylov part of the Direct solver's Reuse Factorization, where the preconditioner is a sparse LU
// factorization of an earlier matrix (SerialLu on one process, MumpsLu over all ranks).
#pragma once
#include <functional>

namespace bc::core {

struct KrylovSpace {
  int n = 0;  // this rank's entries of a vector
  // out = A v and out = M^-1 v (this rank's entries; every rank calls them together).
  std::function<void(const double*v, double*out)> multiply, precondition;
  // The sum over the ranks of a value each rank computed from its entries (the identity on one
  // process). Its result must be the same on every rank: the iteration's decisions follow it.
  std::function<double(double)> sum;
};

// The most iterations a solve takes (the basis is kept).
constexpr int kMaxKrylov = 100;

// Solves A x = b. Stops when the true residual ||b - A x|| is at most `backwardError`
// (`frobenius` ||x|| + ||b||), `frobenius` = ||A||_F. Returns the iterations taken, or -1 when
// `maxIterations` (at most kMaxKrylov) did not get there (x is then undefined).
int gmres(const KrylovSpace& space, const double* b, double* x, int maxIterations, double backwardError,
          double frobenius);

// The GMRES iterations of one solve each (a solve with the factors, a product with A, and the
// orthogonalization against about 10 basis vectors, twice) whose floating-point operations equal a
// factorization's: from its flop count, the nonzeros of its factors and of A, and A's rows.
double iterationsWorth(double factorizationFlops, double factorNonzeros, double matrixNonzeros, double rows);

}  // namespace bc::core
