#include "Assembler.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include <Tpetra_Assembly_Helpers.hpp>

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

void Assembler::rebuild(const State& state) {
  const int P = comm_->getSize(), r = comm_->getRank();
  const int N = state.numNodes();
  nodeBegin_ = static_cast<int>((long long)N * r / P);
  nodeEnd_ = static_cast<int>((long long)N * (r + 1) / P);
  const GlobalDof nodeDofs = GlobalDof(kDofsPerNode) * N;
  numDofs_ = state.numDofs();
  const int b = nodeBegin_, e = nodeEnd_;
  // Extra unknowns (multipliers) are owned by rank 0.
  owns_ = [b, e, nodeDofs, r](GlobalDof g) {
    if (g >= nodeDofs) return r == 0;
    const GlobalDof n = g / kDofsPerNode;
    return n >= b && n < e;
  };

  std::vector<GO> owned;
  for (int n = b; n < e; ++n)
    for (int k = 0; k < kDofsPerNode; ++k) owned.push_back(GO(kDofsPerNode) * n + k);
  if (r == 0)
    for (GlobalDof g = nodeDofs; g < numDofs_; ++g) owned.push_back(g);

  std::vector<std::vector<GlobalDof>> blocks;
  for (const auto& c : model_.contributions) c->connectivity(owns_, blocks);

  // Row -> columns over the overlapped rows; owned rows always hold their diagonal. Each row's
  // columns are gathered with repeats, then sorted once (a set per row took 1.4 s at 10^4 contact
  // points and 23 s at 10^5, allocating a node per entry).
  std::unordered_map<GO, std::size_t> rowIndex;
  std::vector<GO> rowIds;
  std::vector<std::vector<GO>> rowColumns;
  const auto rowOf = [&](GO g) -> std::vector<GO>& {
    const auto [it, inserted] = rowIndex.try_emplace(g, rowColumns.size());
    if (inserted) {
      rowIds.push_back(g);
      rowColumns.emplace_back();
    }
    return rowColumns[it->second];
  };
  for (GO g : owned) rowOf(g).push_back(g);
  for (const auto& blk : blocks)
    for (GlobalDof i : blk) {
      auto& row = rowOf(i);
      row.insert(row.end(), blk.begin(), blk.end());
    }
  std::size_t maxPerRow = 1;
  for (auto& row : rowColumns) {
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    maxPerRow = std::max(maxPerRow, row.size());
  }
  // The overlapped rows: the owned ones, then the others ascending.
  std::vector<GO> ghosts;
  for (GO g : rowIds)
    if (!owns_(g)) ghosts.push_back(g);
  std::sort(ghosts.begin(), ghosts.end());
  std::vector<GO> overlap = owned;
  overlap.insert(overlap.end(), ghosts.begin(), ghosts.end());

  const auto invalid = Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid();
  ownedMap_ = Teuchos::rcp(new Map(invalid, Teuchos::ArrayView<const GO>(owned), 0, comm_));
  overlapMap_ = Teuchos::rcp(new Map(invalid, Teuchos::ArrayView<const GO>(overlap), 0, comm_));
  std::vector<GO> all(numDofs_);
  for (GlobalDof g = 0; g < numDofs_; ++g) all[g] = g;
  replicatedMap_ = Teuchos::rcp(new Map(invalid, Teuchos::ArrayView<const GO>(all), 0, comm_));
  overlapToOwned_ = Teuchos::rcp(new Tpetra::Export<LO, GO, Node>(overlapMap_, ownedMap_));
  ownedToReplicated_ = Teuchos::rcp(new Tpetra::Import<LO, GO, Node>(ownedMap_, replicatedMap_));

  graph_ = Teuchos::rcp(new FEGraph(ownedMap_, overlapMap_, maxPerRow));
  Tpetra::beginAssembly(*graph_);
  for (std::size_t k = 0; k < rowIds.size(); ++k)
    graph_->insertGlobalIndices(rowIds[k], Teuchos::ArrayView<const GO>(rowColumns[k]));
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
  for (const auto& c : model_.contributions) {
    if (!timer_.is_null()) timer_->start("Evaluate " + c->name());
    c->evaluate(state, owns_, sink, tangent);
    if (!timer_.is_null()) timer_->stop("Evaluate " + c->name());
  }
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
