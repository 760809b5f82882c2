#include "LinearSolver.hpp"

#include "Faults.hpp"
#include "Krylov.hpp"
#include "Multigrid.hpp"
#include "MumpsLu.hpp"
#include "SerialLu.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <thread>

#include <BelosSolverFactory.hpp>
#include <BelosTpetraAdapter.hpp>
#include <Ifpack2_Factory.hpp>
#include <Teuchos_DefaultMpiComm.hpp>
#include <Tpetra_CrsGraph.hpp>
#include <Tpetra_Export.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_Import_Util.hpp>

namespace bc::core {

namespace {

// The largest of each of n ints over the ranks, into `global`; the ranks that arrive first sleep
// between polls instead of spinning.
void quietMaxAll(const Teuchos::Comm<int>& comm, int n, const int* local, int* global) {
  const MPI_Comm mpi = rawMpiComm(comm);
  if (mpi == MPI_COMM_NULL) {
    Teuchos::reduceAll(comm, Teuchos::REDUCE_MAX, n, local, global);
    return;
  }
  MPI_Request request;
  MPI_Iallreduce(local, global, n, MPI_INT, MPI_MAX, mpi, &request);
  int done = 0;
  for (;;) {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done) return;
    std::this_thread::sleep_for(std::chrono::microseconds(100));
  }
}

}  // namespace

SolveReport LinearSolver::attempt(const Teuchos::RCP<const Matrix>& A, const Vector& b, Vector& x) {
  SolveReport report;
  try {
    report.iterations = doSolve(A, b, x);
  } catch (const LinearSolveError&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    rethrowIfOutOfMemory(e);  // (Kokkos' failed allocation: a std::runtime_error)
    // Belos and MueLu report over several lines; the first names the failure.
    std::string what = e.what();
    what = what.substr(0, what.find('\n'));
    throw LinearSolveError(name() + " failed, the tangent matrix is probably singular (a free motion: a beam "
                           "without enough supports, or a contact constraint that fixes nothing): " + what);
  }
  Stage stage(*this, "Residual Check");
  const int iterations = report.iterations;
  report = residualReport(*A, b, x);
  report.iterations = iterations;
  return report;
}

double scaledNorm2(const Vector& v) {
  const double m = v.normInf();
  if (!(m > 0.0) || !std::isfinite(m)) return m;
  if (m >= 1e-150 && m <= 1e150) return v.norm2();
  Vector scaled(v, Teuchos::Copy);
  scaled.scale(1.0 / m);
  return m * scaled.norm2();
}

SolveReport residualReport(const Matrix& A, const Vector& b, const Vector& x) {
  SolveReport report;
  Vector r(b.getMap());
  A.apply(x, r);
  r.update(1.0, b, -1.0);
  // Scaled norms: with forces of 1e-200 the plain norms of b and r are 0, and both checks pass
  // whatever x is.
  const double bn = scaledNorm2(b), rn = scaledNorm2(r), an = A.getFrobeniusNorm();
  report.solutionNorm = scaledNorm2(x);
  const double scale = an * report.solutionNorm + bn;
  report.relativeResidual = bn > 0.0 ? rn / bn : rn;
  report.backwardError = scale > 0.0 ? rn / scale : rn;
  report.conditionBound = bn > 0.0 ? an * report.solutionNorm / bn : 0.0;
  return report;
}

SolveReport LinearSolver::solve(const Teuchos::RCP<const Matrix>& A, const Vector& b, Vector& x) {
  SolveReport report = attempt(A, b, x);
  // A solve that took a shortcut (Direct: a refactorization with the last factorization's pivots,
  // chosen for other values) and is not accurate well below the check is redone without it.
  if (!(report.backwardError <= 1e-3 * checkTolerance_) && redoWithoutShortcut()) report = attempt(A, b, x);
  // ||A|| ||x|| / ||b|| is a lower bound of A's condition number (x = A^-1 b). Beyond what double
  // precision resolves, x has no correct digit even when its backward error is small: a solve of a
  // singular matrix returns a huge x whose residual is small against ||A|| ||x||.
  if (report.conditionBound > conditionLimit_) {
    std::ostringstream s;
    s << name() << " linear solve: the tangent matrix is singular or nearly so (||A||_F ||x|| / ||b|| = "
      << report.conditionBound << " > Condition Limit " << conditionLimit_
      << "): a free motion (a beam without enough supports) or dependent constraints (Lagrange multipliers "
         "at more contact points along a beam than its elements' nodes can move independently; refine the "
         "beams or use Penalty or Augmented Lagrange)";
    throw LinearSolveError(s.str());
  }
  if (!std::isfinite(report.backwardError) || !std::isfinite(report.solutionNorm) ||
      report.backwardError > checkTolerance_) {
    std::ostringstream s;
    s << name() << " linear solve failed its residual check: ||b - A x|| / (||A||_F ||x|| + ||b||) = "
      << report.backwardError << " > Residual Check Tolerance " << checkTolerance_
      << " (||b - A x|| / ||b|| = " << report.relativeResidual << ")";
    throw LinearSolveError(s.str());
  }
  return report;
}

namespace {

// A sparse LU (SerialLu: KLU2, refactoring with old pivots, or UMFPACK), called directly; on more
// than one rank the matrix is gathered to rank 0 and factored there. With "Reuse Factorization",
// GMRES preconditioned with the last factorization solves first, and the matrix is factored only
// when that takes too many iterations.
class DirectSolver : public LinearSolver {
 public:
  explicit DirectSolver(const Teuchos::ParameterList& p)
      : LinearSolver(p.get<double>("Residual Check Tolerance"), p.get<double>("Condition Limit")),
        parallel_(p.get<std::string>("Direct Solver") == "MUMPS"),
        lu_(parallel_ ? nullptr : makeSerialLu(p.get<std::string>("Direct Solver"))),
        reuse_(p.get<bool>("Reuse Factorization")),
        reuseLimit_(p.isType<int>("Reuse Iteration Limit") ? p.get<int>("Reuse Iteration Limit") : 0),
        // The GMRES target leaves the backward error well below the check (LinearSolver::solve
        // redoes a shortcut's solve that is not).
        reuseTarget_(0.5e-3 * p.get<double>("Residual Check Tolerance")) {}
  std::string name() const override { return parallel_ ? "Direct (MUMPS)" : "Direct (" + lu_->name() + ")"; }

 protected:
  int doSolve(const Teuchos::RCP<const Matrix>& A, const Vector& b, Vector& x) override {
    const auto comm = A->getRowMap()->getComm();
    // The same matrix object with new values: the assembler keeps it while its graph stands.
    const bool sameGraph = A == lastMatrix_;
    const bool shortcuts = !fresh_;  // on every rank alike
    fresh_ = false;
    shortcut_ = false;
    lastMatrix_ = A;
    if (parallel_) return parallelSolve(*A, shortcuts, b, x);
    if (comm->getSize() == 1) return factorAndSolve(*A, shortcuts, sameGraph, b, x);
    {
      Stage gather(*this, "Gather to Rank 0");
      if (!sameGraph || gathered_.is_null()) {
        Stage setup(*this, "New Graph");
        // A new matrix (graph): rank 0's map holds every row, in global order, so the gathered
        // matrix's local rows and vectors are in global order too.
        // The maps and the vectors' export and import stay while the rows do (a new active set with
        // as many multipliers: 0.3 s of a new graph's 0.84 s at 10^4 points, Lagrange, 2 ranks).
        const auto owned = A->getRowMap();
        if (ownedRows_.is_null() || !owned->isSameAs(*ownedRows_)) {
          const GO n = static_cast<GO>(owned->getGlobalNumElements());
          std::vector<GO> mine;
          if (comm->getRank() == 0)
            for (GO g = 0; g < n; ++g) mine.push_back(g);
          rootMap_ = Teuchos::rcp(new Map(n, Teuchos::ArrayView<const GO>(mine), 0, comm));
          toRoot_ = Teuchos::rcp(new Tpetra::Export<LO, GO, Node>(owned, rootMap_));
          fromRoot_ = Teuchos::rcp(new Tpetra::Import<LO, GO, Node>(rootMap_, owned));
          ownedRows_ = owned;
        }
        gatherGraph(*A, *comm);
      }
      Stage values(*this, "Values");
      gatherValues(*A, *comm);
    }
    Vector b0(rootMap_), x0(rootMap_);
    b0.doExport(b, *toRoot_, Tpetra::INSERT);
    int local[3] = {0, 0, 0}, global[3] = {0, 0, 0};  // failed, iterations, shortcut taken
    std::string what;
    if (comm->getRank() == 0) {
      try {
        local[1] = factorAndSolve(*gathered_, shortcuts, sameGraph, b0, x0);
        local[2] = shortcut_;
      } catch (const std::bad_alloc& e) {
        local[0] = 2;
        what = e.what();
      } catch (const std::exception& e) {
        local[0] = isOutOfMemory(e) ? 2 : 1;
        what = isOutOfMemory(e) ? outOfMemoryText(e) : e.what();
      }
    }
    {
      // The other ranks wait for rank 0 without spinning on a core that rank 0's factorization
      // shares (on two cores a busy wait slowed it by 40 %).
      Stage wait(*this, "Wait for Rank 0");
      quietMaxAll(*comm, 3, local, global);
    }
    shortcut_ = global[2] != 0;
    if (global[0]) {
      gathered_ = Teuchos::null;
      lastMatrix_ = Teuchos::null;
      if (global[0] == 2)
        throw LinearSolverOutOfMemory(comm->getRank() == 0 ? what : lu_->name() + " ran out of memory on rank 0");
      throw LinearSolveError(lu_->name() + " failed on rank 0: " + what);
    }
    x.doImport(x0, *fromRoot_, Tpetra::INSERT);
    return global[1];
  }

 private:
  Teuchos::RCP<const Matrix> lastMatrix_;
  // MUMPS (parallel_): the matrix factored where its rows are, by every rank; otherwise lu_ on rank 0.
  bool parallel_;
  std::unique_ptr<SerialLu> lu_;
  std::unique_ptr<MumpsLu> mumps_;
  // Reuse Factorization on a saddle point: the values factored in A's place (see regularize), and
  // for the graph they were laid out for, each entry's column as a local row (-1: none) and each
  // row's diagonal entry (-1: none).
  std::vector<double> regularized_;
  Teuchos::RCP<const Tpetra::CrsGraph<LO, GO, Node>> regularizedGraph_;
  std::vector<int> entryRow_;
  std::vector<long> diagonalEntry_;
  bool reuse_;
  int reuseLimit_;  // 0: automatic
  int sinceFactorization_ = 0;  // GMRES iterations with the last factorization
  double reuseTarget_;
  // More than one rank: the system gathered to rank 0, kept while the graph stands.
  Teuchos::RCP<const Map> rootMap_, ownedRows_;
  Teuchos::RCP<Tpetra::Export<LO, GO, Node>> toRoot_;
  Teuchos::RCP<Tpetra::Import<LO, GO, Node>> fromRoot_;
  Teuchos::RCP<Matrix> gathered_;
  // Rank 0: where each value to arrive (each rank's rows in its own order, a row's columns by global
  // index, rank after rank) goes among the gathered matrix's entries, and the counts and offsets of
  // the ranks' entries.
  std::vector<int> slots_, entryCounts_, entryOffsets_;
  std::vector<double> gatheredValues_;
  // Each rank: its matrix entries in the order they travel (each row's columns by global index).
  std::vector<int> sendOrder_;
  std::vector<double> sendValues_;

  // Each rank's rows (global indices, lengths, columns by global index) to rank 0, which builds the
  // gathered graph from them (rows and columns in global order) and notes where each entry went.
  // Once per graph: later matrices of the graph travel as their values alone (gatherValues: 4 ms per
  // solve at 4096 contact points, where a Tpetra export with ADD into the gathered matrix took 90 ms).
  void gatherGraph(const Matrix& A, const Teuchos::Comm<int>& comm) {
    static_assert(sizeof(GO) == sizeof(long long), "global indices travel as MPI_LONG_LONG");
    const MPI_Comm mpi = rawMpiComm(comm);  // more than one rank: an MPI communicator
    const auto local = A.getLocalMatrixHost();
    const auto& rowPtr = local.graph.row_map;
    const auto& entries = local.graph.entries;
    const auto& rowMap = *A.getRowMap();
    const auto& colMap = *A.getColMap();
    const int rows = static_cast<int>(rowMap.getNodeNumElements());
    // Each rank sorts its own rows' columns by global index (all ranks at once, where rank 0 sorted
    // every row before), and sends its rows' global indices, their lengths and the sorted columns;
    // sendOrder_ keeps the order in which its values are to travel.
    std::vector<long long> rowIds(rows), cols(entries.extent(0));
    std::vector<int> lengths(rows);
    sendOrder_.resize(entries.extent(0));
    std::vector<std::pair<long long, int>> row;
    for (int i = 0; i < rows; ++i) {
      row.clear();
      for (auto k = rowPtr(i); k < rowPtr(i + 1); ++k)
        row.emplace_back(colMap.getGlobalElement(entries(k)), static_cast<int>(k));
      std::sort(row.begin(), row.end());
      for (std::size_t j = 0; j < row.size(); ++j) {
        cols[rowPtr(i) + j] = row[j].first;
        sendOrder_[rowPtr(i) + j] = row[j].second;
      }
      rowIds[i] = rowMap.getGlobalElement(i);
      lengths[i] = static_cast<int>(row.size());
    }
    const int ranks = comm.getSize(), rank = comm.getRank();
    int counts[2] = {rows, static_cast<int>(entries.extent(0))};
    std::vector<int> allCounts(2 * ranks);
    MPI_Gather(counts, 2, MPI_INT, allCounts.data(), 2, MPI_INT, 0, mpi);
    std::vector<int> rowCounts(ranks), rowOffsets(ranks);
    entryCounts_.assign(ranks, 0);
    entryOffsets_.assign(ranks, 0);
    long long totalRows = 0, total = 0;
    for (int r = 0; r < ranks; ++r) {
      rowCounts[r] = allCounts[2 * r];
      rowOffsets[r] = static_cast<int>(totalRows);
      entryCounts_[r] = allCounts[2 * r + 1];
      entryOffsets_[r] = static_cast<int>(total);
      totalRows += rowCounts[r];
      total += entryCounts_[r];
    }
    if (rank != 0) totalRows = total = 0;
    std::vector<long long> allRows(totalRows), allCols(total);
    std::vector<int> allLengths(totalRows);
    MPI_Gatherv(rowIds.data(), rows, MPI_LONG_LONG, allRows.data(), rowCounts.data(), rowOffsets.data(),
                MPI_LONG_LONG, 0, mpi);
    MPI_Gatherv(lengths.data(), rows, MPI_INT, allLengths.data(), rowCounts.data(), rowOffsets.data(), MPI_INT, 0,
                mpi);
    MPI_Gatherv(cols.data(), counts[1], MPI_LONG_LONG, allCols.data(), entryCounts_.data(), entryOffsets_.data(),
                MPI_LONG_LONG, 0, mpi);
    // Rank 0: the compressed rows in global order (rootMap_'s local index of a global index is the
    // global index itself); each row comes whole from the rank that owns it. slots_[e]: where the
    // e-th value to arrive goes.
    const std::size_t n = rootMap_->getNodeNumElements();
    Teuchos::ArrayRCP<std::size_t> start(n + 1, 0);
    Teuchos::ArrayRCP<LO> columns(total);
    for (long long r = 0; r < totalRows; ++r) {
      if (allRows[r] < 0 || allRows[r] >= static_cast<long long>(n) || start[allRows[r] + 1] != 0)
        throw std::logic_error("Direct solver: a gathered row outside the matrix, or sent twice");
      start[allRows[r] + 1] = allLengths[r];
    }
    for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
    if (rank == 0 && static_cast<long long>(start[n]) != total)
      throw std::logic_error("Direct solver: the gathered rows do not hold every entry");
    slots_.assign(total, 0);
    long long e = 0;
    for (long long r = 0; r < totalRows; ++r)
      for (int j = 0; j < allLengths[r]; ++j, ++e) {
        const std::size_t k = start[allRows[r]] + j;
        if (allCols[e] < 0 || allCols[e] >= static_cast<long long>(n))
          throw std::logic_error("Direct solver: a matrix entry outside the gathered rows");
        columns[k] = static_cast<LO>(allCols[e]);
        slots_[e] = static_cast<int>(k);
      }
    gatheredValues_.assign(total, 0.0);
    auto graph = Teuchos::rcp(new Tpetra::CrsGraph<LO, GO, Node>(rootMap_, rootMap_, start, columns));
    graph->expertStaticFillComplete(rootMap_, rootMap_);
    gathered_ = Teuchos::rcp(new Matrix(graph));
    gathered_->fillComplete(rootMap_, rootMap_);
  }

  // The matrix's values, every rank's in one message, summed into the gathered matrix's entries.
  void gatherValues(const Matrix& A, const Teuchos::Comm<int>& comm) {
    const auto local = A.getLocalMatrixHost();
    const int count = static_cast<int>(local.values.extent(0));
    sendValues_.resize(count);
    for (int k = 0; k < count; ++k) sendValues_[k] = local.values(sendOrder_[k]);
    MPI_Gatherv(sendValues_.data(), count, MPI_DOUBLE, gatheredValues_.data(), entryCounts_.data(),
                entryOffsets_.data(), MPI_DOUBLE, 0, rawMpiComm(comm));
    if (comm.getRank() != 0) return;
    const auto values = gathered_->getLocalMatrixHost().values;
    for (std::size_t e = 0; e < slots_.size(); ++e) values(slots_[e]) = gatheredValues_[e];
  }

  // How much smaller than the Schur complement's diagonal estimate the regularized diagonal is. Its
  // pivot then adds that many times the constraint's own stiffness to the nodes it ties, as a penalty
  // would. The 10^4 crossed layers (Lagrange multipliers) took 1 or 2 GMRES iterations per first solve
  // with 1e4, 1e6 and 1e8 alike.
  static constexpr double kRegularization = 1e6;

  // regularized_ = A's values, except each row i with a zero diagonal that couples to rows j with a nonzero
  // one (a multiplier's row): its diagonal becomes s_i / kRegularization, s_i = -sum_j a_ij a_ji / a_jj,
  // the diagonal of the Schur complement A_ii - A_iK A_KK^-1 A_Ki with A_KK taken as its diagonal
  // (same sign: the eliminated multiplier leaves a penalty, not a negative stiffness). With the
  // diagonal as pivot (preferDiagonalPivots) the factorization follows its fill-reducing order: at
  // 10^4 contact points 1.8e9 to 9.4e9 floating-point operations, against 4.2e9 to 8.2e10 when the
  // zero diagonal sends the pivots off it. Returns the rows changed.
  int regularize(const Matrix& A) {
    const auto a = A.getLocalMatrixHost();
    const auto& rowPtr = a.graph.row_map;
    const int n = static_cast<int>(A.getRowMap()->getNodeNumElements());
    // (No Tpetra object is made here: on more than one rank rank 0 alone runs this.)
    if (locateDiagonals(A)) entryRow_ = rowMapColumns(A);
    const auto diagonal = [&](int i) { return diagonalEntry_[i] < 0 ? 0.0 : a.values(diagonalEntry_[i]); };
    std::vector<int> zero;
    for (int i = 0; i < n; ++i)
      if (diagonalEntry_[i] >= 0 && diagonal(i) == 0.0) zero.push_back(i);
    if (zero.empty()) return 0;
    std::vector<double> s(n, 0.0);
    for (int i : zero)
      for (auto k = rowPtr(i); k < rowPtr(i + 1); ++k) {
        const int j = entryRow_[k];
        if (j < 0 || j == i || a.values(k) == 0.0 || diagonal(j) == 0.0) continue;
        for (auto m = rowPtr(j); m < rowPtr(j + 1); ++m)
          if (entryRow_[m] == i) s[i] -= a.values(k) * a.values(m) / diagonal(j);
      }
    return setRegularized(A, s);
  }

  // Each row's diagonal entry among A's local entries (diagonalEntry_, -1: none), found again only
  // for a new graph; returns whether it was.
  bool locateDiagonals(const Matrix& A) {
    if (!regularizedGraph_.is_null() && regularizedGraph_ == A.getCrsGraph()) return false;
    regularizedGraph_ = A.getCrsGraph();
    const auto graph = A.getLocalMatrixHost().graph;
    const auto& rowMap = *A.getRowMap();
    const auto& colMap = *A.getColMap();
    const int n = static_cast<int>(rowMap.getNodeNumElements());
    diagonalEntry_.assign(n, -1);
    for (int i = 0; i < n; ++i)
      for (auto k = graph.row_map(i); k < graph.row_map(i + 1); ++k)
        if (colMap.getGlobalElement(graph.entries(k)) == rowMap.getGlobalElement(i)) diagonalEntry_[i] = static_cast<long>(k);
    return true;
  }

  // regularized_ = A's values, with the diagonal of each zero-diagonal row i whose s[i] (the Schur
  // complement's diagonal estimate) is nonzero and finite set to s[i] / kRegularization. Returns the
  // rows changed (on this process).
  int setRegularized(const Matrix& A, const std::vector<double>& s) {
    const auto values = A.getLocalMatrixHost().values;
    regularized_.assign(values.data(), values.data() + values.extent(0));
    int changed = 0;
    for (std::size_t i = 0; i < s.size(); ++i)
      if (diagonalEntry_[i] >= 0 && values(diagonalEntry_[i]) == 0.0 && s[i] != 0.0 && std::isfinite(s[i])) {
        regularized_[diagonalEntry_[i]] = s[i] / kRegularization;
        ++changed;
      }
    return changed;
  }

  // MUMPS: Reuse Factorization's saddle point regularized as in regularize, over the ranks. The rows
  // j that couple to a zero-diagonal row i are anywhere, so each rank sends, for its rows j, the
  // a_ji / a_jj to the owner of row i, which sums a_ij a_ji / a_jj. Collective; returns the rows
  // changed over all ranks (regularized_: this rank's values).
  int regularizeOverRanks(const Matrix& A) {
    const auto a = A.getLocalMatrixHost();
    const auto& rowPtr = a.graph.row_map;
    const auto& entries = a.graph.entries;
    const auto& rowMap = *A.getRowMap();
    const auto& colMap = *A.getColMap();
    const MPI_Comm mpi = rawMpiComm(*rowMap.getComm());
    const int n = static_cast<int>(rowMap.getNodeNumElements());
    locateDiagonals(A);
    const auto diagonal = [&](int i) { return diagonalEntry_[i] < 0 ? 0.0 : a.values(diagonalEntry_[i]); };
    // The rows with a zero diagonal in the pattern, marked in the column map.
    Vector zero(A.getRowMap()), zeroColumn(A.getColMap());
    int zeros = 0, allZeros = 0;
    {
      auto z = zero.getDataNonConst();
      for (int i = 0; i < n; ++i)
        if (diagonalEntry_[i] >= 0 && diagonal(i) == 0.0) z[i] = 1.0, ++zeros;
    }
    MPI_Allreduce(&zeros, &allZeros, 1, MPI_INT, MPI_SUM, mpi);
    if (allZeros == 0) return 0;
    const auto importer = A.getGraph()->getImporter();
    if (importer.is_null())
      zeroColumn = zero;  // the column map is the domain (= row) map
    else
      zeroColumn.doImport(zero, *importer, Tpetra::INSERT);
    const auto zc = zeroColumn.getData();
    // For each of this rank's rows j with a nonzero diagonal, and each zero-diagonal row i among its
    // columns: (i, j, a_ji / a_jj), to go to the owner of row i.
    int ranks = 0, rank = 0;
    MPI_Comm_size(mpi, &ranks);
    MPI_Comm_rank(mpi, &rank);
    // Each column's owner: this rank, or for a column of another rank's row the importer's record.
    Teuchos::Array<int> columnOwner(colMap.getNodeNumElements(), rank);
    if (!importer.is_null()) Tpetra::Import_Util::getPids(*importer, columnOwner, false);
    std::vector<GO> targets, from;
    std::vector<int> owners;
    std::vector<double> ratios;
    for (int j = 0; j < n; ++j) {
      const double d = diagonal(j);
      if (d == 0.0) continue;
      for (auto k = rowPtr(j); k < rowPtr(j + 1); ++k)
        if (zc[entries(k)] == 1.0 && a.values(k) != 0.0) {
          targets.push_back(colMap.getGlobalElement(entries(k)));
          owners.push_back(columnOwner[entries(k)]);
          from.push_back(rowMap.getGlobalElement(j));
          ratios.push_back(a.values(k) / d);
        }
    }
    std::vector<int> sendCounts(ranks, 0), sendOffsets(ranks, 0), receiveCounts(ranks), receiveOffsets(ranks, 0);
    for (int o : owners) ++sendCounts[o];
    for (int r = 1; r < ranks; ++r) sendOffsets[r] = sendOffsets[r - 1] + sendCounts[r - 1];
    std::vector<GO> sendIds(2 * targets.size());
    std::vector<double> sendRatios(targets.size());
    {
      std::vector<int> next = sendOffsets;
      for (std::size_t t = 0; t < targets.size(); ++t) {
        const int slot = next[owners[t]]++;
        sendIds[2 * slot] = targets[t];
        sendIds[2 * slot + 1] = from[t];
        sendRatios[slot] = ratios[t];
      }
    }
    MPI_Alltoall(sendCounts.data(), 1, MPI_INT, receiveCounts.data(), 1, MPI_INT, mpi);
    for (int r = 1; r < ranks; ++r) receiveOffsets[r] = receiveOffsets[r - 1] + receiveCounts[r - 1];
    const int received = receiveOffsets[ranks - 1] + receiveCounts[ranks - 1];
    std::vector<GO> receiveIds(2 * static_cast<std::size_t>(received));
    std::vector<double> receiveRatios(received);
    MPI_Alltoallv(sendRatios.data(), sendCounts.data(), sendOffsets.data(), MPI_DOUBLE, receiveRatios.data(),
                  receiveCounts.data(), receiveOffsets.data(), MPI_DOUBLE, mpi);
    for (int r = 0; r < ranks; ++r) sendCounts[r] *= 2, sendOffsets[r] *= 2, receiveCounts[r] *= 2, receiveOffsets[r] *= 2;
    MPI_Alltoallv(sendIds.data(), sendCounts.data(), sendOffsets.data(), MPI_LONG_LONG, receiveIds.data(),
                  receiveCounts.data(), receiveOffsets.data(), MPI_LONG_LONG, mpi);
    // s_i = -sum_j a_ij a_ji / a_jj, with a_ij from this rank's row i.
    std::vector<double> s(n, 0.0);
    for (int t = 0; t < received; ++t) {
      const LO i = rowMap.getLocalElement(receiveIds[2 * t]);
      const LO j = colMap.getLocalElement(receiveIds[2 * t + 1]);
      if (i < 0) throw std::logic_error("Direct (MUMPS): a multiplier's coupling sent to a rank without its row");
      if (j < 0) continue;  // a_ij is not in row i's pattern
      for (auto k = rowPtr(i); k < rowPtr(i + 1); ++k)
        if (entries(k) == j) s[i] -= a.values(k) * receiveRatios[t];
    }
    int changed = setRegularized(A, s), allChanged = 0;
    MPI_Allreduce(&changed, &allChanged, 1, MPI_INT, MPI_SUM, mpi);
    return allChanged;
  }

  // Solves A x = b with MUMPS on every rank (returns the Krylov iterations; 0: direct): as
  // factorAndSolve, with the GMRES of Reuse Factorization over the ranks.
  int parallelSolve(const Matrix& A, bool shortcuts, const Vector& b, Vector& x) {
    const MPI_Comm mpi = rawMpiComm(*A.getRowMap()->getComm());
    if (!mumps_) mumps_ = std::make_unique<MumpsLu>(*A.getRowMap()->getComm());
    auto xv = x.getDataNonConst();
    const auto bv = b.getData();
    const int n = static_cast<int>(A.getRowMap()->getNodeNumElements());
    Vector in(A.getDomainMap()), out(A.getRangeMap());
    KrylovSpace space;
    space.n = n;
    space.multiply = [&](const double* v, double* result) {
      {
        auto d = in.getDataNonConst();
        std::copy(v, v + n, d.getRawPtr());
      }
      A.apply(in, out);
      const auto r = out.getData();
      std::copy(r.getRawPtr(), r.getRawPtr() + n, result);
    };
    space.precondition = [&](const double* v, double* result) { mumps_->solve(v, result); };
    // Reduced on rank 0 and sent to all: every rank follows the same iteration.
    space.sum = [mpi](double mine) {
      double all = 0.0;
      MPI_Reduce(&mine, &all, 1, MPI_DOUBLE, MPI_SUM, 0, mpi);
      MPI_Bcast(&all, 1, MPI_DOUBLE, 0, mpi);
      return all;
    };
    const int limit = reuseLimit_ > 0 ? reuseLimit_ : std::max(10, static_cast<int>(0.5 * mumps_->iterationsWorth()));
    if (shortcuts && reuse_ && mumps_->factored() && sinceFactorization_ < limit && mumps_->fits(A)) {
      Stage stage(*this, "Krylov Iterations");
      const int iterations = gmres(space, bv.getRawPtr(), xv.getRawPtr(), limit - sinceFactorization_, reuseTarget_,
                                   A.getFrobeniusNorm());
      if (iterations >= 0) {
        shortcut_ = true;
        sinceFactorization_ += iterations;
        return iterations;
      }
    }
    if (reuse_ && regularizeOverRanks(A) > 0) {
      bool failed = false;
      {
        {
          Stage analysis(*this, "Analysis");
          mumps_->analyseIfNew(A);
        }
        Stage stage(*this, "Factorization");
        sinceFactorization_ = 0;
        mumps_->preferDiagonalPivots(true);
        try {
          mumps_->factor(A, regularized_.data());
        } catch (const std::runtime_error&) {
          failed = true;  // (a singular regularized matrix, on every rank): A as it is, below
        }
        mumps_->preferDiagonalPivots(false);
      }
      if (!failed) {
        Stage stage(*this, "Krylov Iterations");
        const int iterations =
            gmres(space, bv.getRawPtr(), xv.getRawPtr(), kMaxKrylov, reuseTarget_, A.getFrobeniusNorm());
        if (iterations >= 0) {
          sinceFactorization_ = iterations;
          return iterations;
        }
      }
    }
    {
      Stage analysis(*this, "Analysis");
      mumps_->analyseIfNew(A);
    }
    {
      Stage stage(*this, "Factorization");
      sinceFactorization_ = 0;
      mumps_->factor(A);
    }
    Stage stage(*this, "Triangular Solves");
    mumps_->solve(bv.getRawPtr(), xv.getRawPtr());
    return 0;
  }

  // shortcut_: the last solve refactored with old pivots or reused an old factorization; fresh_:
  // the next one is to do neither.
  bool shortcut_ = false, fresh_ = false;
  bool redoWithoutShortcut() override {
    fresh_ = shortcut_;
    return shortcut_;
  }

  // Solves A x = b on one process (A: all rows here); returns the Krylov iterations (0: direct).
  // With `shortcuts`: GMRES preconditioned with the last factorization when reuse is on (of any
  // pattern), and a refactorization with the last pivot order when A is the last matrix with new
  // values (`sameGraph`). After a graph change the pivots are chosen afresh: the old order, chosen
  // for another active set, made the factorizations of the 32 x 32 layers with Lagrange multipliers
  // 80 % slower (11.0 s against 6.1 s for 19).
  int factorAndSolve(const Matrix& A, bool shortcuts, bool sameGraph, const Vector& b, Vector& x) {
    auto xv = x.getDataNonConst();
    const auto bv = b.getData();
    // Rent or buy: GMRES iterations with the last factorization, summed over the solves since it,
    // are spent up to the limit (about what one factorization costs); then the matrix is factored.
    // Automatic: the flop count puts a factorization at 8 to 48 iterations from 10^2 to 10^4 contact
    // points, where timings put it at 17 to 26 (triangular solves are slower per flop at scale); half
    // the count, at least 10, keeps within a factor of two of the time where it matters.
    const int limit = reuseLimit_ > 0 ? reuseLimit_ : std::max(10, static_cast<int>(0.5 * lu_->iterationsWorth()));
    if (shortcuts && reuse_ && lu_->factored() && sinceFactorization_ < limit) {
      Stage stage(*this, "Krylov Iterations");
      const int iterations = lu_->solvePreconditioned(A, bv.getRawPtr(), xv.getRawPtr(),
                                                      limit - sinceFactorization_, reuseTarget_);
      if (iterations >= 0) {
        shortcut_ = true;
        sinceFactorization_ += iterations;
        return iterations;
      }
    }
    // A saddle point (Lagrange multipliers) is factored with its zero diagonal regularized, and GMRES
    // preconditioned with that factorization solves A itself; when GMRES does not get there, A is
    // factored as it is.
    bool regularizedFailed = false;
    if (reuse_ && regularize(A) > 0) {
      const bool refactor = shortcuts && sameGraph && lu_->factored();
      {
        Stage stage(*this, "Factorization");
        sinceFactorization_ = 0;
        shortcut_ = refactor && lu_->refactorKeepsPivots();
        lu_->preferDiagonalPivots(true);
        try {
          lu_->factor(A, refactor, regularized_.data());
        } catch (const std::runtime_error&) {
          regularizedFailed = true;  // (a singular regularized matrix): A as it is, below
        }
        lu_->preferDiagonalPivots(false);
      }
      if (!regularizedFailed) {
        Stage stage(*this, "Krylov Iterations");
        const int iterations = lu_->solvePreconditioned(A, bv.getRawPtr(), xv.getRawPtr(), kMaxKrylov,
                                                        reuseTarget_);
        if (iterations >= 0) {
          sinceFactorization_ = iterations;
          return iterations;
        }
        regularizedFailed = true;
      }
    }
    {
      Stage stage(*this, "Factorization");
      const bool refactor = !regularizedFailed && shortcuts && sameGraph && lu_->factored();
      shortcut_ = refactor && lu_->refactorKeepsPivots();
      sinceFactorization_ = 0;
      lu_->factor(A, refactor);
    }
    Stage stage(*this, "Triangular Solves");
    lu_->solve(bv.getRawPtr(), xv.getRawPtr());
    return 0;
  }
};

class GmresSolver : public LinearSolver {
 public:
  explicit GmresSolver(const Teuchos::ParameterList& p)
      : LinearSolver(p.get<double>("Residual Check Tolerance"), p.get<double>("Condition Limit")),
        precType_(p.get<std::string>("Preconditioner")),
        overlap_(p.get<int>("Overlap")),
        fill_(p.get<double>("Fill Level")),
        tol_(p.get<double>("Tolerance")),
        maxIt_(p.get<int>("Maximum Iterations")),
        restart_(p.get<int>("Restart")) {}
  std::string name() const override { return "GMRES (" + precType_ + ")"; }
  bool wantsNearNullSpace() const override { return precType_ == "MueLu"; }

 protected:
  int doSolve(const Teuchos::RCP<const Matrix>& A, const Vector& b, Vector& x) override {
    Teuchos::RCP<Operator> prec;
    auto setup = std::make_unique<Stage>(*this, "Preconditioner Setup");
    if (precType_ == "MueLu") {
      if (nearNull_.is_null() || !nearNull_->getMap()->isSameAs(*A->getRowMap()))
        throw LinearSolveError("GMRES (MueLu): no near-null space for this matrix");
      MultigridSettings m;
      m.sweeps = std::max(1, static_cast<int>(fill_));
      prec = makeMultigrid(A, nearNull_, m);
    } else {
      using RowMatrix = Tpetra::RowMatrix<Scalar, LO, GO, Node>;
      Ifpack2::Factory factory;
      auto schwarz = factory.create<RowMatrix>("SCHWARZ", A);
      Teuchos::ParameterList pp;
      pp.set("schwarz: overlap level", overlap_);
      pp.set("inner preconditioner name", precType_);
      Teuchos::ParameterList& inner = pp.sublist("inner preconditioner parameters");
      if (precType_ == "ILUT") {
        inner.set("fact: ilut level-of-fill", fill_);
        inner.set("fact: drop tolerance", 0.0);
      } else {
        inner.set("fact: iluk level-of-fill", static_cast<int>(fill_));
      }
      schwarz->setParameters(pp);
      schwarz->initialize();
      schwarz->compute();
      prec = schwarz;
    }
    setup.reset();

    x.putScalar(0.0);
    auto problem = Teuchos::rcp(new Belos::LinearProblem<Scalar, MultiVector, Operator>(
        A, Teuchos::rcpFromRef(x), Teuchos::rcpFromRef(b)));
    problem->setRightPrec(prec);
    problem->setProblem();
    auto params = Teuchos::rcp(new Teuchos::ParameterList);
    params->set("Convergence Tolerance", tol_);
    params->set("Maximum Iterations", maxIt_);
    params->set("Num Blocks", restart_);
    Belos::SolverFactory<Scalar, MultiVector, Operator> belos;
    auto solver = belos.create("GMRES", params);
    solver->setProblem(problem);
    Stage stage(*this, "Krylov Iterations");
    solver->solve();
    return solver->getNumIters();
  }

 private:
  std::string precType_;
  int overlap_;
  double fill_, tol_;
  int maxIt_, restart_;
};

}  // namespace

const ParameterSpec& linearSolverSpec() {
  static const ParameterSpec spec = [] {
    ParameterSpec s;
    s.addChoice("Type", "Direct", {"Direct", "GMRES"},
                "Direct: sparse LU (Direct Solver); GMRES: Belos GMRES with an Ifpack2 or MueLu preconditioner");
    s.addChoice("Direct Solver", "KLU2", {"KLU2", "UMFPACK", "MUMPS"},
                "Direct only: the sparse LU factorization. KLU2: no dense kernels, a matrix of the last one's "
                "pattern refactored with its pivot order (the faster up to about 10^4 rows); UMFPACK: "
                "multifrontal with dense (BLAS) kernels, 3 to 6 times faster factorizations at 10^5 rows (most "
                "on Lagrange multiplier saddle points), the faster from about 10^4 rows with Reuse "
                "Factorization; MUMPS: multifrontal with dense kernels, the matrix factored where its rows are by "
                "all ranks together (the others gather it to rank 0)");
    s.add("Residual Check Tolerance", 1e-10,
          "largest accepted backward error ||b - A x|| / (||A||_F ||x|| + ||b||) of a solve; above it the solve "
          "is an error",
          positive(), "> 0");
    s.add("Condition Limit", 1e14,
          "largest accepted ||A||_F ||x|| / ||b|| of a solve (a lower bound of the matrix's condition number); "
          "above it the matrix is taken as singular and the solve is an error",
          positive(), "> 0");
    s.addChoice("Preconditioner", "ILUT", {"ILUT", "RILUK", "MueLu"},
                "GMRES only: ILUT or RILUK: additive Schwarz with incomplete factorizations of the subdomains; "
                "MueLu: smoothed-aggregation multigrid with the nodes' rigid-body modes as near-null space "
                "(Penalty and Augmented Lagrange only: no multiplier rows)");
    s.add("Fill Level", 2.0,
          "GMRES only: ILUT level of fill, RILUK level k, or MueLu's Gauss-Seidel sweeps per level (at least 1)",
          nonNegative(), ">= 0");
    s.add("Overlap", 1, "GMRES only: overlap of the additive Schwarz subdomains", atLeast(0), ">= 0");
    s.add("Reuse Factorization", false,
          "Direct only: solve by GMRES preconditioned with the last LU factorization (of an earlier Newton "
          "matrix of the same size), and factor the matrix again only when the GMRES iterations since the "
          "last factorization reach Reuse Iteration Limit; a saddle point (Lagrange multipliers' zero "
          "diagonal) is factored with that diagonal regularized (a millionth of its Schur complement "
          "estimate), which keeps the fill-reducing order's pivots; the solution is held to the same "
          "residual check",
          {}, "");
    s.addOptional("Reuse Iteration Limit", 25,
                  "Direct with Reuse Factorization: GMRES iterations, summed over the solves since the last "
                  "factorization, after which the matrix is factored again (one solve takes at most 100); "
                  "absent or \"Automatic\": half the iterations whose floating-point operations equal the "
                  "last full factorization's (the Direct Solver's count), at least 10",
                  atLeast(1), ">= 1");
    s.allowWord("Reuse Iteration Limit", "Automatic");
    s.add("Tolerance", 1e-12, "GMRES only: relative residual at which GMRES stops", positive(), "> 0");
    s.add("Maximum Iterations", 1000, "GMRES only: iteration limit", atLeast(1), ">= 1");
    s.add("Restart", 200, "GMRES only: Krylov vectors kept before a restart", atLeast(1), ">= 1");
    return s;
  }();
  return spec;
}

std::unique_ptr<LinearSolver> makeLinearSolver(const Teuchos::ParameterList& p) {
  const std::string type = p.get<std::string>("Type");
  if (type != "Direct" && p.get<bool>("Reuse Factorization"))
    throw InputError("parameter \"Linear Solver/Reuse Factorization\" reuses the Direct solver's LU factorization; "
                     "with Type \"" + type + "\" give Preconditioner instead");
  if (type == "Direct") return std::make_unique<DirectSolver>(p);
  return std::make_unique<GmresSolver>(p);
}

}  // namespace bc::core
