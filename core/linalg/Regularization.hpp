// The saddle point of Reuse Factorization: a matrix with Lagrange multiplier rows (a zero diagonal)
// is factored with that diagonal regularized, and GMRES preconditioned with that factorization solves
// the matrix itself (DirectMethod). The regularized values, on one process (regularize) or over the
// ranks (regularizeOverRanks, for MUMPS).
#pragma once
#include <vector>

#include "core/TpetraTypes.hpp"

namespace bc::core {

class SaddlePointRegularization {
 public:
  // values() = A's values, except each row i with a zero diagonal that couples to rows j with a
  // nonzero one (a multiplier's row): its diagonal becomes s_i / kRegularization,
  // s_i = -sum_j a_ij a_ji / a_jj, the diagonal of the Schur complement A_ii - A_iK A_KK^-1 A_Ki with
  // A_KK taken as its diagonal (same sign: the eliminated multiplier leaves a penalty, not a negative
  // stiffness). With the diagonal as pivot (preferDiagonalPivots) the factorization follows its
  // fill-reducing order: at 10^4 contact points 1.8e9 to 9.4e9 floating-point operations, against
  // 4.2e9 to 8.2e10 when the zero diagonal sends the pivots off it. A on one process (on more than
  // one rank rank 0 alone runs this, on the gathered matrix: no Tpetra object is made). Returns the
  // rows changed.
  int regularize(const Matrix& A);
  // As regularize, A over the ranks: the rows j that couple to a zero-diagonal row i are anywhere, so
  // each rank sends, for its rows j, the a_ji / a_jj to the owner of row i, which sums a_ij a_ji /
  // a_jj. Collective; returns the rows changed over all ranks (values(): this rank's).
  int regularizeOverRanks(const Matrix& A);
  // The regularized values, one per entry of A's local compressed rows.
  const double* values() const { return regularized_.data(); }

  // How much smaller than the Schur complement's diagonal estimate the regularized diagonal is. Its
  // pivot then adds that many times the constraint's own stiffness to the nodes it ties, as a penalty
  // would. The 10^4 crossed layers (Lagrange multipliers) took 1 or 2 GMRES iterations per first solve
  // with 1e4, 1e6 and 1e8 alike.
  static constexpr double kRegularization = 1e6;

 private:
  // A coupling a_ji / a_jj of a row j to a zero-diagonal row i, sent to the owner of row i.
  struct Coupling {
    GO i, j;
    double ratio;
  };
  // Each row's diagonal entry among A's local entries (diagonalEntry_, -1: none), found again only
  // for a new graph; returns whether it was.
  bool locateDiagonals(const Matrix& A);
  double diagonal(const Matrix::local_matrix_host_type& a, int i) const {
    return diagonalEntry_[i] < 0 ? 0.0 : a.values(diagonalEntry_[i]);
  }
  // This rank's couplings to zero-diagonal rows anywhere, with the rank that owns each such row;
  // false when no rank has a zero diagonal (collective).
  bool localCouplings(const Matrix& A, std::vector<Coupling>& couplings, std::vector<int>& owners);
  // Each coupling to its owner (collective); returns those that came to this rank.
  static std::vector<Coupling> exchange(const std::vector<Coupling>& couplings, const std::vector<int>& owners,
                                        MPI_Comm mpi);
  // regularized_ = A's values, with the diagonal of each zero-diagonal row i whose s[i] (the Schur
  // complement's diagonal estimate) is nonzero and finite set to s[i] / kRegularization. Returns the
  // rows changed (on this process).
  int setRegularized(const Matrix& A, const std::vector<double>& s);

  // The values factored in A's place, and for the graph they were laid out for, each entry's column
  // as a local row (-1: none) and each row's diagonal entry (-1: none).
  std::vector<double> regularized_;
  Teuchos::RCP<const Tpetra::CrsGraph<LO, GO, Node>> regularizedGraph_;
  std::vector<int> entryRow_;
  std::vector<long> diagonalEntry_;
};

}  // namespace bc::core
