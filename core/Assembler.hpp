// Distributed assembly on Tpetra. Nodes are split in space over the ranks (coordinatePartition); a rank owns
// the 6 dofs of its nodes (and, later, extra unknowns assigned to it) and evaluates every block whose
// first dof it owns. Blocks are summed with the FE classes (FECrsGraph / FECrsMatrix over the owned
// and owned+shared maps, beginAssembly/endAssembly), the residual through an overlapped vector and an
// Export with ADD. The graph is rebuilt by rebuild() whenever the coupling changes.
#pragma once
#include <memory>
#include <set>
#include <vector>

#include <Teuchos_StackedTimer.hpp>
#include <Tpetra_Export.hpp>
#include <Tpetra_FECrsGraph.hpp>
#include <Tpetra_FECrsMatrix.hpp>
#include <Tpetra_Import.hpp>

#include "Model.hpp"
#include "TpetraTypes.hpp"

namespace bc::core {

// Each node's rank: recursive coordinate bisection of the positions X into `ranks` parts of equal
// counts (every rank gets the same answer).
std::vector<int> coordinatePartition(const std::vector<Vec3d>& X, int ranks);

class Assembler {
 public:
  Assembler(Teuchos::RCP<const Comm> comm, const Model& model);

  // (Re)builds maps and matrix graph from the contributions' current connectivity.
  void rebuild(const State& state);
  // Residual r = f_int(state) - T f_ext (owned rows; constrained rows are set to zero, their
  // unconstrained values kept as reactions) and, if `tangent`, the tangent matrix with identity rows
  // for constrained dofs.
  void assemble(const State& state, double loadFactor, bool tangent);

  // With a timer, each contribution's evaluation is timed ("Evaluate <name>", within the caller's
  // running timer).
  void setTimer(Teuchos::RCP<Teuchos::StackedTimer> timer) { timer_ = timer; }
  bool ownsDof(GlobalDof g) const;
  const Contribution::OwnsDof& ownsPredicate() const { return owns_; }
  Teuchos::RCP<const Map> ownedMap() const { return ownedMap_; }
  Teuchos::RCP<Matrix> matrix() const { return matrix_; }
  Teuchos::RCP<Vector> residual() const { return residual_; }
  const std::set<GlobalDof>& constrainedDofs() const { return constrained_; }
  // How many times the graph was built: a matrix of the same generation has the same pattern.
  int generation() const { return generation_; }
  Teuchos::RCP<const Comm> comm() const { return comm_; }

  // Every entry of an owned-map vector on every rank (for the replicated state and output).
  std::vector<double> gatherToAll(const Vector& v);
  // Reactions of the last assembly: unconstrained residual at each constrained dof (all ranks).
  const std::vector<double>& fullResidual() const { return fullResidual_; }

 private:
  int generation_ = 0;
  using FEGraph = Tpetra::FECrsGraph<LO, GO, Node>;
  using FEMatrix = Tpetra::FECrsMatrix<Scalar, LO, GO, Node>;
  struct RowPattern;
  // rebuild's parts: each dof's rank (owns_; the nodes split in space, an extra unknown with the
  // blocks that hold it), returning the contributions' blocks; the rows and their columns; the maps
  // and transfers; the graph, matrix and vectors.
  std::vector<std::vector<GlobalDof>> assignOwners(const State& state);
  RowPattern rowPattern(const std::vector<std::vector<GlobalDof>>& blocks) const;
  void makeMaps(const RowPattern& rows);
  void makeGraph(const RowPattern& rows);

  Teuchos::RCP<const Comm> comm_;
  const Model& model_;
  Teuchos::RCP<Teuchos::StackedTimer> timer_;
  std::shared_ptr<const std::vector<int>> nodeOwner_;  // each node's rank
  Contribution::OwnsDof owns_;
  std::set<GlobalDof> constrained_;
  GlobalDof numDofs_ = 0;

  Teuchos::RCP<const Map> ownedMap_, overlapMap_, replicatedMap_;
  Teuchos::RCP<Tpetra::Export<LO, GO, Node>> overlapToOwned_;
  Teuchos::RCP<Tpetra::Import<LO, GO, Node>> ownedToReplicated_;
  Teuchos::RCP<FEGraph> graph_;
  Teuchos::RCP<FEMatrix> matrix_;
  Teuchos::RCP<Vector> overlapResidual_, residual_, externalLoad_;
  std::vector<double> fullResidual_;
};

}  // namespace bc::core
