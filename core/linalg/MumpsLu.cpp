#include "MumpsLu.hpp"

#include "Krylov.hpp"
#include "Errors.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <dmumps_c.h>

namespace bc::core {

struct MumpsLu::Handle {
  DMUMPS_STRUC_C id{};
  MPI_Comm comm = MPI_COMM_NULL;
};

namespace {
// MUMPS's control and information arrays are documented 1-based: ICNTL(k) is icntl[k - 1].
constexpr int icntl(int k) { return k - 1; }
}  // namespace

MumpsLu::MumpsLu(const Teuchos::Comm<int>& comm) : h_(std::make_unique<Handle>()) {
  const MPI_Comm mpi = rawMpiComm(comm);
  if (mpi == MPI_COMM_NULL) throw std::invalid_argument("MUMPS needs an MPI communicator");
  // Its own communicator: MUMPS's messages cannot meet Tpetra's.
  MPI_Comm_dup(mpi, &h_->comm);
  auto& id = h_->id;
  id.comm_fortran = static_cast<MUMPS_INT>(MPI_Comm_c2f(h_->comm));
  id.par = 1;  // rank 0 factors and solves too
  id.sym = 0;  // unsymmetric (friction and multipliers make the Newton matrix so)
  id.job = -1;
  dmumps_c(&id);
  // No output from MUMPS itself: its failures reach the caller through INFOG.
  id.icntl[icntl(1)] = -1;
  id.icntl[icntl(2)] = -1;
  id.icntl[icntl(3)] = -1;
  id.icntl[icntl(4)] = 0;
  id.icntl[icntl(18)] = 3;  // the matrix distributed: each rank gives its own rows
  id.icntl[icntl(20)] = 0;  // a dense right-hand side on rank 0
  id.icntl[icntl(21)] = 0;  // the solution on rank 0
  // QAMD ordering: on the 10^4-point crossed layers as few operations as the automatic choice (PORD
  // in this build, which has no METIS or SCOTCH), with a 25 % cheaper analysis and factorizations
  // that parallelize better (2 ranks: 0.80-0.87 s against 0.92-1.03 s).
  id.icntl[icntl(7)] = 6;
  // No iterative refinement and no error analysis: every solve is checked by its residual
  // (LinearSolver), and with Reuse Factorization GMRES refines.
  id.icntl[icntl(10)] = 0;
  id.icntl[icntl(11)] = 0;
  pivotThreshold_ = id.cntl[0];
}

void MumpsLu::preferDiagonalPivots(bool on) { h_->id.cntl[0] = on ? 0.0 : pivotThreshold_; }

bool MumpsLu::fits(const Matrix& A) const {
  const int mine = rowMap_.is_null() ? 0 : 1;
  int all = 0;
  MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MIN, h_->comm);
  if (!all) return false;
  return rowMap_->isSameAs(*A.getRowMap());  // collective: on every rank, never short-cut
}

MumpsLu::~MumpsLu() {
  h_->id.job = -2;
  dmumps_c(&h_->id);
  MPI_Comm_free(&h_->comm);
}

void MumpsLu::run(int job, const char* what) {
  auto& id = h_->id;
  id.job = job;
  dmumps_c(&id);
  const int error = id.infog[0];
  if (error >= 0) return;
  const std::string detail = std::string("MUMPS ") + what + " failed (INFOG(1) = " + std::to_string(error) +
                             ", INFOG(2) = " + std::to_string(id.infog[1]) + ")";
  if (error == -13 || error == -19)
    throw LinearSolverOutOfMemory(detail +
                                  ": it could not allocate the memory it needs; a smaller model, a "
                                  "machine with more memory, or Linear Solver/Type = GMRES");
  if (error == -10 || error == -6) throw std::runtime_error(detail + ": the matrix is singular");
  throw std::runtime_error(detail);
}

void MumpsLu::analyse(const Matrix& A) {
  const auto local = A.getLocalMatrixHost();
  const auto& rowPtr = local.graph.row_map;
  const auto& entries = local.graph.entries;
  const auto& rowMap = *A.getRowMap();
  const auto& colMap = *A.getColMap();
  localRows_ = static_cast<int>(rowMap.getNodeNumElements());
  const GO n = static_cast<GO>(rowMap.getGlobalNumElements());
  if (n > GO(2147483647)) throw std::runtime_error("MUMPS: more rows than its 32-bit indices hold");
  rows_.resize(entries.extent(0));
  columns_.resize(entries.extent(0));
  for (int i = 0; i < localRows_; ++i)
    for (auto k = rowPtr(i); k < rowPtr(i + 1); ++k) {
      rows_[k] = static_cast<int>(rowMap.getGlobalElement(i) + 1);
      columns_[k] = static_cast<int>(colMap.getGlobalElement(entries(k)) + 1);
    }
  values_.resize(entries.extent(0));
  static_assert(sizeof(GO) == sizeof(long long), "entry counts travel as MPI_LONG_LONG");
  GO entryCount = static_cast<GO>(rows_.size()), allEntries = 0;
  MPI_Allreduce(&entryCount, &allEntries, 1, MPI_LONG_LONG, MPI_SUM, h_->comm);
  matrixEntries_ = double(allEntries);
  // Rank 0 learns where each rank's rows go in the dense right-hand side.
  int ranks = 0, rank = 0;
  MPI_Comm_size(h_->comm, &ranks);
  MPI_Comm_rank(h_->comm, &rank);
  counts_.assign(ranks, 0);
  offsets_.assign(ranks, 0);
  MPI_Gather(&localRows_, 1, MPI_INT, counts_.data(), 1, MPI_INT, 0, h_->comm);
  int total = 0;
  for (int r = 0; r < ranks; ++r) offsets_[r] = total, total += counts_[r];
  std::vector<int> mine(localRows_);
  for (int i = 0; i < localRows_; ++i) mine[i] = static_cast<int>(rowMap.getGlobalElement(i));
  rowIds_.assign(rank == 0 ? total : 0, 0);
  MPI_Gatherv(mine.data(), localRows_, MPI_INT, rowIds_.data(), counts_.data(), offsets_.data(), MPI_INT, 0, h_->comm);
  gathered_.assign(rowIds_.size(), 0.0);
  dense_.assign(rank == 0 ? n : 0, 0.0);

  auto& id = h_->id;
  id.n = static_cast<MUMPS_INT>(n);
  id.nnz_loc = static_cast<MUMPS_INT8>(rows_.size());
  id.irn_loc = rows_.data();
  id.jcn_loc = columns_.data();
  id.a_loc = values_.data();
  factored_ = false;
  graph_ = Teuchos::null;
  rowMap_ = Teuchos::null;
  run(1, "analysis");
  rowMap_ = A.getRowMap();
  graph_ = A.getCrsGraph();
}

void MumpsLu::analyseIfNew(const Matrix& A) {
  // Every rank has the same answer: the graph is the matrix's, the same object on all ranks or none.
  int same = graph_ == A.getCrsGraph() ? 1 : 0, all = 0;
  MPI_Allreduce(&same, &all, 1, MPI_INT, MPI_MIN, h_->comm);
  if (!all) analyse(A);
}

void MumpsLu::factor(const Matrix& A, const double* values) {
  analyseIfNew(A);
  const auto local = A.getLocalMatrixHost();
  const double* v = values ? values : local.values.data();
  std::copy(v, v + values_.size(), values_.begin());
  factored_ = false;
  auto& id = h_->id;
  // The working space MUMPS estimated at its analysis can fall short when pivots are delayed: it is
  // enlarged and the factorization run again.
  const int defaultRelaxation = id.icntl[icntl(14)];
  for (int attempt = 0;; ++attempt) {
    try {
      run(2, "factorization");
      break;
    } catch (const std::runtime_error&) {
      const int error = id.infog[0];
      const bool workspace = error == -8 || error == -9 || error == -14 || error == -15 || error == -17 || error == -20;
      if (!workspace || attempt == 4) {
        id.icntl[icntl(14)] = defaultRelaxation;
        throw;
      }
      id.icntl[icntl(14)] = 2 * id.icntl[icntl(14)] + 20;
    }
  }
  id.icntl[icntl(14)] = defaultRelaxation;
  factored_ = true;
  // RINFOG(3): the factorization's floating-point operations; INFOG(29): the factors' entries (in
  // millions when negative).
  const double flops = id.rinfog[2];
  const double entries = id.infog[28] >= 0 ? double(id.infog[28]) : -1e6 * double(id.infog[28]);
  iterationsWorth_ = core::iterationsWorth(flops, entries, matrixEntries_, double(id.n));
}

void MumpsLu::solve(const double* b, double* x) {
  if (!factored_) throw std::logic_error("MumpsLu::solve before a factorization");
  int rank = 0;
  MPI_Comm_rank(h_->comm, &rank);
  MPI_Gatherv(b, localRows_, MPI_DOUBLE, gathered_.data(), counts_.data(), offsets_.data(), MPI_DOUBLE, 0, h_->comm);
  auto& id = h_->id;
  if (rank == 0) {
    for (std::size_t k = 0; k < rowIds_.size(); ++k) dense_[rowIds_[k]] = gathered_[k];
    id.rhs = dense_.data();
    id.nrhs = 1;
    id.lrhs = id.n;
  }
  run(3, "solve");
  if (rank == 0)
    for (std::size_t k = 0; k < rowIds_.size(); ++k) gathered_[k] = dense_[rowIds_[k]];
  MPI_Scatterv(gathered_.data(), counts_.data(), offsets_.data(), MPI_DOUBLE, x, localRows_, MPI_DOUBLE, 0, h_->comm);
}

}  // namespace bc::core
