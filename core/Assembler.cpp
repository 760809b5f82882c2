#include "Assembler.hpp"

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include <Tpetra_Assembly_Helpers.hpp>

#include "Faults.hpp"
#include "ScopedTimer.hpp"

namespace bc::core {

namespace {

// Sums element blocks into the overlapped matrix and residual. The matrix skips constrained rows (the
// owner puts a unit diagonal there); the residual keeps them so reactions can be read off. A block's
// dofs are turned into local rows and columns once (with global indices Tpetra looks each column up
// again for every row: 24 x 24 lookups for a contact point's block).
class TpetraSink : public AssemblySink {
 public:
  TpetraSink(Matrix* K, Vector& r, const std::set<GlobalDof>& constrained) : K_(K), r_(r) {
    if (!K_) return;
    const auto& rowMap = *K_->getRowMap();
    // The overlapped matrix's rows are the residual's entries (both the overlap map): one lookup
    // serves both.
    sameRows_ = rowMap.locallySameAs(*r_.getMap());
    constrainedRow_.assign(rowMap.getNodeNumElements(), 0);
    for (GlobalDof g : constrained) {
      const LO l = rowMap.getLocalElement(g);
      if (l != Teuchos::OrdinalTraits<LO>::invalid()) constrainedRow_[l] = 1;
    }
  }
  void add(const GlobalDof* dofs, int n, const double* f, const double* Ke) override {
    const auto& vectorMap = *r_.getMap();
    rows_.resize(n);
    for (int i = 0; i < n; ++i) {
      rows_[i] = local(vectorMap, dofs[i]);
      r_.sumIntoLocalValue(rows_[i], f[i]);
    }
    if (!K_ || !Ke) return;
    const auto& rowMap = *K_->getRowMap();
    const auto& colMap = *K_->getColMap();
    cols_.resize(n);
    for (int i = 0; i < n; ++i) {
      if (!sameRows_) rows_[i] = local(rowMap, dofs[i]);
      cols_[i] = local(colMap, dofs[i]);
    }
    for (int i = 0; i < n; ++i) {
      if (constrainedRow_[rows_[i]]) continue;
      const LO changed = K_->sumIntoLocalValues(rows_[i], n, Ke + std::size_t(n) * i, cols_.data());
      if (changed != n) throw std::logic_error("assembly: element entry outside the matrix graph");
    }
  }

 private:
  static LO local(const Map& map, GlobalDof g) {
    const LO l = map.getLocalElement(g);
    if (l == Teuchos::OrdinalTraits<LO>::invalid())
      throw std::logic_error("assembly: dof " + std::to_string(g) + " outside this rank's overlapped rows");
    return l;
  }
  Matrix* K_;
  Vector& r_;
  bool sameRows_ = false;
  std::vector<char> constrainedRow_;  // by local row of K
  std::vector<LO> rows_, cols_;
};

}  // namespace

Assembler::Assembler(Teuchos::RCP<const Comm> comm, const Model& model) : comm_(comm), model_(model) {
  for (const Support& s : model_.supports)
    for (int n : s.nodes)
      for (int k = 0; k < 6; ++k)
        if (s.fixed[k]) constrained_.insert(GlobalDof(kDofsPerNode) * n + k);
}

bool Assembler::ownsDof(GlobalDof g) const { return owns_(g); }

namespace {

// Recursive coordinate bisection: the nodes `ids` go to ranks [r0, r1). The box's longest side is cut
// where the ranks on either side get their share of the nodes (ties in the coordinate broken by node
// number, so every rank computes the same split).
void bisect(const std::vector<Vec3d>& X, std::vector<int>& ids, std::size_t begin, std::size_t end, int r0, int r1,
            std::vector<int>& owner) {
  if (r1 - r0 <= 1 || end - begin <= 1) {
    for (std::size_t k = begin; k < end; ++k) owner[ids[k]] = r0;
    return;
  }
  Vec3d lo = X[ids[begin]], hi = lo;
  for (std::size_t k = begin; k < end; ++k)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], X[ids[k]][a]);
      hi[a] = std::max(hi[a], X[ids[k]][a]);
    }
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
  const int rm = r0 + (r1 - r0) / 2;
  const std::size_t mid = begin + (end - begin) * std::size_t(rm - r0) / std::size_t(r1 - r0);
  std::nth_element(ids.begin() + begin, ids.begin() + mid, ids.begin() + end,
                   [&](int a, int b) { return X[a][axis] < X[b][axis] || (X[a][axis] == X[b][axis] && a < b); });
  bisect(X, ids, begin, mid, r0, rm, owner);
  bisect(X, ids, mid, end, rm, r1, owner);
}

}  // namespace

std::vector<int> coordinatePartition(const std::vector<Vec3d>& X, int ranks) {
  std::vector<int> owner(X.size(), 0), ids(X.size());
  for (std::size_t k = 0; k < ids.size(); ++k) ids[k] = static_cast<int>(k);
  bisect(X, ids, 0, ids.size(), 0, std::max(1, ranks), owner);
  return owner;
}

// The rows of the graph being built: this rank's owned dofs, the overlapped rows (the owned ones, then
// the others ascending), and each row's columns (rowColumns[rowIndex[g]] for row g; rowIds in the
// order the rows were met).
struct Assembler::RowPattern {
  std::vector<GO> owned, overlap, rowIds;
  std::unordered_map<GO, std::size_t> rowIndex;
  std::vector<std::vector<GO>> rowColumns;
};

void Assembler::rebuild(const State& state) {
  ++generation_;
  RowPattern rows;
  {
    ScopedTimer timer(timer_, "Rows");
    rows = rowPattern(assignOwners(state));
  }
  {
    ScopedTimer timer(timer_, "Maps and Transfers");
    makeMaps(rows);
  }
  ScopedTimer timer(timer_, "Graph");
  makeGraph(rows);
}

std::vector<std::vector<GlobalDof>> Assembler::assignOwners(const State& state) {
  const int P = comm_->getSize(), r = comm_->getRank();
  const int N = state.numNodes();
  // The nodes are split in space once, from their reference positions: crossing beams near each
  // other then sit on one rank, and so do the contact points between them.
  if (!nodeOwner_ || static_cast<int>(nodeOwner_->size()) != N)
    nodeOwner_ = std::make_shared<const std::vector<int>>(coordinatePartition(state.reference, P));
  const GlobalDof nodeDofs = GlobalDof(kDofsPerNode) * N;
  numDofs_ = state.numDofs();
  // The contributions choose the rank that evaluates a block by its node dofs (a contact point: by
  // one of its elements' first nodes), so the blocks are known before the extra unknowns
  // (multipliers) have owners.
  const auto nodeOwner = nodeOwner_;
  owns_ = [nodeOwner, nodeDofs, r](GlobalDof g) {
    if (g >= nodeDofs) return r == 0;
    return (*nodeOwner)[g / kDofsPerNode] == r;
  };
  std::vector<std::vector<GlobalDof>> blocks;
  for (const auto& c : model_.contributions) c->connectivity(owns_, blocks);

  // An extra unknown goes to the rank whose blocks hold it (a contact point's multipliers to the rank
  // that evaluates the point), the lowest of several, rank 0 when none does: its row and the rows it
  // couples to are then mostly on one rank. (All on rank 0, its rows made the graph rebuild and the
  // solver's Schur sums serial: at 10^4 points with Lagrange multipliers a rebuild took as long on 2
  // ranks as on 1.)
  const GlobalDof extras = numDofs_ - nodeDofs;
  auto extraOwner = std::make_shared<std::vector<int>>(extras, 0);
  if (P > 1 && extras > 0) {
    std::vector<int> claim(extras, P);
    for (const auto& blk : blocks)
      for (GlobalDof g : blk)
        if (g >= nodeDofs) claim[g - nodeDofs] = r;
    Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MIN, static_cast<int>(extras), claim.data(), extraOwner->data());
    for (int& o : *extraOwner)
      if (o == P) o = 0;
  }
  owns_ = [nodeOwner, extraOwner, nodeDofs, r](GlobalDof g) {
    if (g >= nodeDofs) return (*extraOwner)[g - nodeDofs] == r;
    return (*nodeOwner)[g / kDofsPerNode] == r;
  };
  return blocks;
}

Assembler::RowPattern Assembler::rowPattern(const std::vector<std::vector<GlobalDof>>& blocks) const {
  RowPattern p;
  for (GlobalDof g = 0; g < numDofs_; ++g)
    if (owns_(g)) p.owned.push_back(g);
  // Row -> columns over the overlapped rows; owned rows always hold their diagonal. (A set per row
  // took 1.4 s at 10^4 contact points and 23 s at 10^5, allocating a node per entry.)
  const auto rowOf = [&](GO g) -> std::size_t {
    const auto [it, inserted] = p.rowIndex.try_emplace(g, p.rowColumns.size());
    if (inserted) {
      p.rowIds.push_back(g);
      p.rowColumns.emplace_back();
    }
    return it->second;
  };
  for (GO g : p.owned) p.rowColumns[rowOf(g)].push_back(g);
  // Many blocks couple the same dofs (the Gauss points of one element pair): each distinct set once.
  std::vector<std::vector<GlobalDof>> distinct(blocks);
  for (auto& blk : distinct) {
    std::sort(blk.begin(), blk.end());
    blk.erase(std::unique(blk.begin(), blk.end()), blk.end());
  }
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  // Each row's blocks, then its columns gathered once each (a mark per dof: the row last given it);
  // sorting the columns with their repeats took a quarter of a strand's run.
  std::vector<std::vector<std::size_t>> rowBlocks;
  for (std::size_t b = 0; b < distinct.size(); ++b)
    for (GlobalDof i : distinct[b]) {
      const std::size_t row = rowOf(i);
      if (rowBlocks.size() <= row) rowBlocks.resize(row + 1);
      rowBlocks[row].push_back(b);
    }
  std::vector<std::size_t> mark(static_cast<std::size_t>(numDofs_), static_cast<std::size_t>(-1));
  for (std::size_t row = 0; row < p.rowColumns.size(); ++row) {
    auto& columns = p.rowColumns[row];
    for (GO g : columns) mark[static_cast<std::size_t>(g)] = row;
    if (row < rowBlocks.size())
      for (std::size_t b : rowBlocks[row])
        for (GlobalDof j : distinct[b])
          if (mark[static_cast<std::size_t>(j)] != row) {
            mark[static_cast<std::size_t>(j)] = row;
            columns.push_back(j);
          }
    std::sort(columns.begin(), columns.end());
  }
  // The overlapped rows: the owned ones, then the others ascending.
  std::vector<GO> ghosts;
  for (GO g : p.rowIds)
    if (!owns_(g)) ghosts.push_back(g);
  std::sort(ghosts.begin(), ghosts.end());
  p.overlap = p.owned;
  p.overlap.insert(p.overlap.end(), ghosts.begin(), ghosts.end());
  return p;
}

void Assembler::makeMaps(const RowPattern& rows) {
  const auto invalid = Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid();
  ownedMap_ = Teuchos::rcp(new Map(invalid, Teuchos::ArrayView<const GO>(rows.owned), 0, comm_));
  overlapMap_ = Teuchos::rcp(new Map(invalid, Teuchos::ArrayView<const GO>(rows.overlap), 0, comm_));
  std::vector<GO> all(numDofs_);
  for (GlobalDof g = 0; g < numDofs_; ++g) all[g] = g;
  replicatedMap_ = Teuchos::rcp(new Map(invalid, Teuchos::ArrayView<const GO>(all), 0, comm_));
  overlapToOwned_ = Teuchos::rcp(new Tpetra::Export<LO, GO, Node>(overlapMap_, ownedMap_));
  ownedToReplicated_ = Teuchos::rcp(new Tpetra::Import<LO, GO, Node>(ownedMap_, replicatedMap_));
}

void Assembler::makeGraph(const RowPattern& rows) {
  const auto& overlap = rows.overlap;
  // Each overlapped row's own entry count. One bound for all rows (the longest row's, at a node
  // where many contact points meet) allocated that many entries for each of them: at 10^5 contact
  // points with Lagrange multipliers on 2 ranks the graph fill took 7.2 s over two rebuilds, 5.1 s
  // with the counts.
  Kokkos::DualView<std::size_t*, FEGraph::device_type> counts("row entry counts", overlap.size());
  for (std::size_t l = 0; l < overlap.size(); ++l)
    counts.h_view(l) = rows.rowColumns[rows.rowIndex.at(overlap[l])].size();
  counts.modify_host();
  counts.sync_device();
  graph_ = Teuchos::rcp(
      new FEGraph(ownedMap_, overlapMap_, Kokkos::DualView<const std::size_t*, FEGraph::device_type>(counts)));
  Tpetra::beginAssembly(*graph_);
  for (std::size_t k = 0; k < rows.rowIds.size(); ++k)
    graph_->insertGlobalIndices(rows.rowIds[k], Teuchos::ArrayView<const GO>(rows.rowColumns[k]));
  Tpetra::endAssembly(*graph_);
  matrix_ = Teuchos::rcp(new FEMatrix(graph_));

  overlapResidual_ = Teuchos::rcp(new Vector(overlapMap_));
  residual_ = Teuchos::rcp(new Vector(ownedMap_));
  externalLoad_ = Teuchos::rcp(new Vector(ownedMap_));
}

void Assembler::assemble(const State& state, double loadFactor, bool tangent) {
  if (state.numDofs() != numDofs_) throw std::logic_error("assembly: dof count changed without rebuild()");
  overlapResidual_->putScalar(0.0);
  if (tangent) {
    Tpetra::beginAssembly(*matrix_);
    matrix_->setAllToScalar(0.0);
  }
  TpetraSink sink(tangent ? matrix_.get() : nullptr, *overlapResidual_, constrained_);
  // The evaluations are local; an error in one rank's share is agreed before the collective
  // completion of the matrix, so every rank stops with it instead of waiting in the export.
  collectively(*comm_, [&] {
    injectFault("assembly");
    for (const auto& c : model_.contributions) {
      ScopedTimer timer(timer_, "Evaluate " + c->name());
      c->evaluate(state, owns_, sink, tangent);
    }
  });
  if (tangent) {
    const double one = 1.0;
    for (GlobalDof g : constrained_)
      if (owns_(g)) {
        const GO col = g;
        matrix_->sumIntoGlobalValues(g, 1, &one, &col);
      }
    Tpetra::endAssembly(*matrix_);
  }
  residual_->putScalar(0.0);
  residual_->doExport(*overlapResidual_, *overlapToOwned_, Tpetra::ADD);
  // External loads at this load factor (each scaled by its load curve).
  externalLoad_->putScalar(0.0);
  for (const NodalLoad& l : model_.loads)
    for (int k = 0; k < 6; ++k) {
      const GlobalDof g = GlobalDof(kDofsPerNode) * l.node + k;
      if (owns_(g) && l.value[k] != 0.0) externalLoad_->sumIntoGlobalValue(g, l.value[k] * l.curve(loadFactor));
    }
  residual_->update(-1.0, *externalLoad_, 1.0);
  fullResidual_ = gatherToAll(*residual_);
  for (GlobalDof g : constrained_)
    if (owns_(g)) residual_->replaceGlobalValue(g, 0.0);
}

std::vector<double> Assembler::gatherToAll(const Vector& v) {
  Vector rep(replicatedMap_);
  rep.doImport(v, *ownedToReplicated_, Tpetra::INSERT);
  auto data = rep.getData();
  return std::vector<double>(data.begin(), data.end());
}

}  // namespace bc::core
