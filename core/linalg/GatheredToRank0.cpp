// A one-process factorization for a matrix over the ranks: the system gathered to rank 0 and solved
// there (DirectMethod.hpp's gatheredToRank0).
#include <algorithm>
#include <chrono>
#include <thread>

#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsGraph.hpp>
#include <Tpetra_Export.hpp>
#include <Tpetra_Import.hpp>

#include "core/ScopedTimer.hpp"
#include "DirectMethod.hpp"
#include "Errors.hpp"

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

// Each rank's rows as they travel to rank 0: global indices, lengths, and each row's columns by
// global index.
struct TravellingRows {
  std::vector<long long> rowIds, cols;
  std::vector<int> lengths;
};

// Every rank's rows, as rank 0 receives them (rank after rank; empty on the other ranks).
struct GatheredRows {
  std::vector<long long> rows, cols;
  std::vector<int> lengths;
  long long totalRows = 0, total = 0;
};

class GatheredToRank0 : public DirectMethod {
 public:
  explicit GatheredToRank0(std::unique_ptr<DirectMethod> onOneProcess) : inner_(std::move(onOneProcess)) {}
  std::string name() const override { return inner_->name(); }

  int solve(const Matrix& A, bool shortcuts, bool sameGraph, const Vector& b, Vector& x) override {
    const auto comm = A.getRowMap()->getComm();
    // After a failure the next matrix is taken as a new one.
    sameGraph = sameGraph && !failed_;
    failed_ = false;
    gather(A, *comm, sameGraph);
    Vector b0(rootMap_), x0(rootMap_);
    b0.doExport(b, *toRoot_, Tpetra::INSERT);
    int local[3] = {0, 0, 0}, global[3] = {0, 0, 0};  // failed, iterations, shortcut taken
    std::string what;
    if (comm->getRank() == 0) solveOnRank0(shortcuts, sameGraph, b0, x0, local, what);
    {
      // The other ranks wait for rank 0 without spinning on a core that rank 0's factorization
      // shares (on two cores a busy wait slowed it by 40 %).
      ScopedTimer wait(timer_, "Wait for Rank 0");
      quietMaxAll(*comm, 3, local, global);
    }
    shortcut_ = global[2] != 0;
    if (global[0]) {
      gathered_ = Teuchos::null;
      failed_ = true;
      if (global[0] == 2)
        throw LinearSolverOutOfMemory(comm->getRank() == 0 ? what : name() + " ran out of memory on rank 0");
      throw LinearSolveError(name() + " failed on rank 0: " + what);
    }
    x.doImport(x0, *fromRoot_, Tpetra::INSERT);
    return global[1];
  }

 private:
  // The gathered matrix with A's values (its graph and maps made again for a new graph).
  void gather(const Matrix& A, const Comm& comm, bool sameGraph) {
    ScopedTimer gather(timer_, "Gather to Rank 0");
    if (!sameGraph || gathered_.is_null()) {
      ScopedTimer setup(timer_, "New Graph");
      makeMaps(A.getRowMap());
      gatherGraph(A, comm);
    }
    ScopedTimer values(timer_, "Values");
    gatherValues(A, comm);
  }

  // The inner solve on rank 0; a failure is noted in local[0] (1; 2: out of memory) and `what`.
  void solveOnRank0(bool shortcuts, bool sameGraph, const Vector& b0, Vector& x0, int* local, std::string& what) {
    inner_->setTimer(timer_);
    try {
      local[1] = inner_->solve(*gathered_, shortcuts, sameGraph, b0, x0);
      local[2] = inner_->tookShortcut();
    } catch (const std::bad_alloc& e) {
      local[0] = 2;
      what = e.what();
    } catch (const std::exception& e) {
      local[0] = isOutOfMemory(e) ? 2 : 1;
      what = isOutOfMemory(e) ? outOfMemoryText(e) : e.what();
    }
  }

  // A new matrix (graph): rank 0's map holds every row, in global order, so the gathered matrix's
  // local rows and vectors are in global order too. The maps and the vectors' export and import stay
  // while the rows do (a new active set with as many multipliers: 0.3 s of a new graph's 0.84 s at
  // 10^4 points, Lagrange, 2 ranks).
  void makeMaps(const Teuchos::RCP<const Map>& owned) {
    if (!ownedRows_.is_null() && owned->isSameAs(*ownedRows_)) return;
    const auto comm = owned->getComm();
    const GO n = static_cast<GO>(owned->getGlobalNumElements());
    std::vector<GO> mine;
    if (comm->getRank() == 0)
      for (GO g = 0; g < n; ++g) mine.push_back(g);
    rootMap_ = Teuchos::rcp(new Map(n, Teuchos::ArrayView<const GO>(mine), 0, comm));
    toRoot_ = Teuchos::rcp(new Tpetra::Export<LO, GO, Node>(owned, rootMap_));
    fromRoot_ = Teuchos::rcp(new Tpetra::Import<LO, GO, Node>(rootMap_, owned));
    ownedRows_ = owned;
  }

  // Each rank's rows (global indices, lengths, columns by global index) to rank 0, which builds the
  // gathered graph from them (rows and columns in global order) and notes where each entry went.
  // Once per graph: later matrices of the graph travel as their values alone (gatherValues: 4 ms per
  // solve at 4096 contact points, where a Tpetra export with ADD into the gathered matrix took 90 ms).
  void gatherGraph(const Matrix& A, const Comm& comm) { buildGraph(gatherRows(comm, sortedRows(A)), comm.getRank()); }

  // Each rank sorts its own rows' columns by global index (all ranks at once, where rank 0 sorted
  // every row before); sendOrder_ keeps the order in which its values are to travel.
  TravellingRows sortedRows(const Matrix& A) {
    const auto local = A.getLocalMatrixHost();
    const auto& rowPtr = local.graph.row_map;
    const auto& entries = local.graph.entries;
    const auto& rowMap = *A.getRowMap();
    const auto& colMap = *A.getColMap();
    const int rows = static_cast<int>(rowMap.getNodeNumElements());
    TravellingRows t;
    t.rowIds.resize(rows);
    t.cols.resize(entries.extent(0));
    t.lengths.resize(rows);
    sendOrder_.resize(entries.extent(0));
    std::vector<std::pair<long long, int>> row;
    for (int i = 0; i < rows; ++i) {
      row.clear();
      for (auto k = rowPtr(i); k < rowPtr(i + 1); ++k)
        row.emplace_back(colMap.getGlobalElement(entries(k)), static_cast<int>(k));
      std::sort(row.begin(), row.end());
      for (std::size_t j = 0; j < row.size(); ++j) {
        t.cols[rowPtr(i) + j] = row[j].first;
        sendOrder_[rowPtr(i) + j] = row[j].second;
      }
      t.rowIds[i] = rowMap.getGlobalElement(i);
      t.lengths[i] = static_cast<int>(row.size());
    }
    return t;
  }

  // Every rank's rows to rank 0 (with entryCounts_ and entryOffsets_, each rank's share of the values).
  GatheredRows gatherRows(const Comm& comm, const TravellingRows& t) {
    static_assert(sizeof(GO) == sizeof(long long), "global indices travel as MPI_LONG_LONG");
    const MPI_Comm mpi = rawMpiComm(comm);  // more than one rank: an MPI communicator
    const int ranks = comm.getSize(), rows = static_cast<int>(t.rowIds.size());
    int counts[2] = {rows, static_cast<int>(t.cols.size())};
    std::vector<int> allCounts(2 * ranks);
    MPI_Gather(counts, 2, MPI_INT, allCounts.data(), 2, MPI_INT, 0, mpi);
    std::vector<int> rowCounts(ranks), rowOffsets(ranks);
    entryCounts_.assign(ranks, 0);
    entryOffsets_.assign(ranks, 0);
    GatheredRows g;
    for (int r = 0; r < ranks; ++r) {
      rowCounts[r] = allCounts[2 * r];
      rowOffsets[r] = static_cast<int>(g.totalRows);
      entryCounts_[r] = allCounts[2 * r + 1];
      entryOffsets_[r] = static_cast<int>(g.total);
      g.totalRows += rowCounts[r];
      g.total += entryCounts_[r];
    }
    if (comm.getRank() != 0) g.totalRows = g.total = 0;
    g.rows.resize(g.totalRows);
    g.cols.resize(g.total);
    g.lengths.resize(g.totalRows);
    MPI_Gatherv(t.rowIds.data(), rows, MPI_LONG_LONG, g.rows.data(), rowCounts.data(), rowOffsets.data(), MPI_LONG_LONG,
                0, mpi);
    MPI_Gatherv(t.lengths.data(), rows, MPI_INT, g.lengths.data(), rowCounts.data(), rowOffsets.data(), MPI_INT, 0,
                mpi);
    MPI_Gatherv(t.cols.data(), counts[1], MPI_LONG_LONG, g.cols.data(), entryCounts_.data(), entryOffsets_.data(),
                MPI_LONG_LONG, 0, mpi);
    return g;
  }

  // Rank 0: the compressed rows in global order (rootMap_'s local index of a global index is the
  // global index itself); each row comes whole from the rank that owns it. slots_[e]: where the e-th
  // value to arrive goes. (The other ranks make their empty share of the gathered matrix.)
  void buildGraph(const GatheredRows& g, int rank) {
    const std::size_t n = rootMap_->getNodeNumElements();
    Teuchos::ArrayRCP<std::size_t> start(n + 1, 0);
    Teuchos::ArrayRCP<LO> columns(g.total);
    for (long long r = 0; r < g.totalRows; ++r) {
      if (g.rows[r] < 0 || g.rows[r] >= static_cast<long long>(n) || start[g.rows[r] + 1] != 0)
        throw std::logic_error("Direct solver: a gathered row outside the matrix, or sent twice");
      start[g.rows[r] + 1] = g.lengths[r];
    }
    for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
    if (rank == 0 && static_cast<long long>(start[n]) != g.total)
      throw std::logic_error("Direct solver: the gathered rows do not hold every entry");
    slots_.assign(g.total, 0);
    long long e = 0;
    for (long long r = 0; r < g.totalRows; ++r)
      for (int j = 0; j < g.lengths[r]; ++j, ++e) {
        const std::size_t k = start[g.rows[r]] + j;
        if (g.cols[e] < 0 || g.cols[e] >= static_cast<long long>(n))
          throw std::logic_error("Direct solver: a matrix entry outside the gathered rows");
        columns[k] = static_cast<LO>(g.cols[e]);
        slots_[e] = static_cast<int>(k);
      }
    gatheredValues_.assign(g.total, 0.0);
    auto graph = Teuchos::rcp(new Tpetra::CrsGraph<LO, GO, Node>(rootMap_, rootMap_, start, columns));
    graph->expertStaticFillComplete(rootMap_, rootMap_);
    gathered_ = Teuchos::rcp(new Matrix(graph));
    gathered_->fillComplete(rootMap_, rootMap_);
  }

  // The matrix's values, every rank's in one message, summed into the gathered matrix's entries.
  void gatherValues(const Matrix& A, const Comm& comm) {
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

  std::unique_ptr<DirectMethod> inner_;
  bool failed_ = false;  // the last solve failed (its gathered matrix is gone)
  // The system gathered to rank 0, kept while the graph stands.
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
};

}  // namespace

std::unique_ptr<DirectMethod> gatheredToRank0(std::unique_ptr<DirectMethod> onOneProcess) {
  return std::make_unique<GatheredToRank0>(std::move(onOneProcess));
}

}  // namespace bc::core
