// MUMPS (a multifrontal sparse LU over MPI; Debian's libmumps, which Trilinos links but Debian's
// Amesos2 13.2 does not wrap) factoring a matrix whose rows stay on the ranks that own them: no
// gather to rank 0, and every rank works on the factorization. The Direct solver's "MUMPS".
//  - A new pattern gets MUMPS's analysis (ordering and symbolic factorization); a matrix of the last
//    one's graph with new values only its numeric factorization.
//  - The right-hand side goes to rank 0 and the solution comes back to the rows' owners (MUMPS's
//    centralized right-hand side); the factors stay distributed.
//  - Failures are collective (MUMPS reports them on every rank): a singular matrix throws
//    std::runtime_error on every rank, a factorization that cannot have its memory
//    LinearSolverOutOfMemory.
#pragma once
#include <memory>
#include <vector>

#include <Teuchos_Comm.hpp>

#include "core/TpetraTypes.hpp"

namespace bc::core {

class MumpsLu {
 public:
  // Every rank of `comm` constructs, factors, solves and destroys together.
  explicit MumpsLu(const Teuchos::Comm<int>& comm);
  ~MumpsLu();
  MumpsLu(const MumpsLu&) = delete;
  MumpsLu& operator=(const MumpsLu&) = delete;

  // Factors A (square, row map = domain map = range map). `values`, when not null: factored in place
  // of this rank's values of A (one per entry of its local compressed rows).
  void factor(const Matrix& A, const double* values = nullptr);
  // MUMPS's analysis (ordering, symbolic factorization) of A's pattern, unless it is the last one's
  // (collective; factor calls it, a caller may call it first to time it apart).
  void analyseIfNew(const Matrix& A);
  // x = A^-1 b, both in this rank's rows of the last factored matrix's row map (local order).
  void solve(const double* b, double* x);
  bool factored() const { return factored_; }
  // Whether the last factorization is of a matrix with A's row map (collective).
  bool fits(const Matrix& A) const;
  // With `on`, the next factorizations take the pivots on the diagonal in the order of the analysis
  // (no threshold pivoting: for a saddle point whose zero diagonal was replaced by a small one, see
  // SerialLu::preferDiagonalPivots); off (the default), MUMPS's threshold test chooses.
  void preferDiagonalPivots(bool on);
  // The GMRES iterations that cost as many floating-point operations as the last factorization
  // (Krylov.hpp's iterationsWorth).
  double iterationsWorth() const { return iterationsWorth_; }

 private:
  struct Handle;
  std::unique_ptr<Handle> h_;
  // The graph analysed, and this rank's entries as MUMPS reads them (1-based global indices).
  Teuchos::RCP<const Tpetra::CrsGraph<LO, GO, Node>> graph_;
  std::vector<int> rows_, columns_;
  std::vector<double> values_;
  // Rank 0: every rank's row count and offset, and the global index of each row as the ranks send
  // them; the dense right-hand side (solution) of all rows.
  std::vector<int> counts_, offsets_, rowIds_;
  std::vector<double> gathered_, dense_;
  int localRows_ = 0;
  Teuchos::RCP<const Map> rowMap_;
  double pivotThreshold_ = 0.01;  // MUMPS's CNTL(1) as it came
  bool factored_ = false;
  double iterationsWorth_ = 0.0;
  double matrixEntries_ = 0.0;  // the analysed matrix's entries over all ranks
  void analyse(const Matrix& A);
  // MUMPS's phase `job` on every rank; throws on its global error.
  void run(int job, const char* what);
};

}  // namespace bc::core
