// A Contribution adds terms to the global residual and tangent: the beam elements are one, each
// constraint set (e.g. contact) another. Its three concerns are separate interfaces: Physics (blocks,
// residual, tangent, Newton hooks), StepHistory (commit, restore, checkpoint) and Output (VTK,
// tables, progress line). It works on the replicated State and writes element-level blocks into
// an AssemblySink, so it needs no Tpetra (kernels stay unit-testable without MPI).
//
// Distribution: every rank asks each contribution for the blocks *it* evaluates (those whose first
// global dof it owns, as told by the sink); the Assembler sums blocks across ranks.
#pragma once
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "State.hpp"

namespace Teuchos {
template <typename Ordinal> class Comm;
}  // namespace Teuchos

namespace bc::core {

class CheckpointOut;
class CheckpointIn;

// Receives element-level contributions. `K` is n x n row-major, or null for residual-only assembly.
class AssemblySink {
 public:
  virtual ~AssemblySink() = default;
  virtual void add(const GlobalDof* dofs, int n, const double* f, const double* K) = 0;
};

// A drawable piece of the model for VTK output: points, cells (VTK cell types), the displacement of
// every point and named vector arrays that a contribution sets on its own points (zero elsewhere).
struct VtkMesh {
  std::vector<Vec3d> points;
  std::vector<Vec3d> pointDisplacement;
  std::map<std::string, std::vector<Vec3d>> pointVectors;
  std::map<std::string, std::vector<double>> pointScalars;
  std::vector<int> cellTypes;
  std::vector<std::vector<int>> cells;
  std::vector<int> cellBeam;  // index of the beam a cell belongs to (-1: none)
  std::vector<int> cellElement;  // element index within its beam (-1: none)
  std::map<std::string, std::vector<double>> cellScalars;  // named cell arrays (zero where not set)

  int addPoint(const Vec3d& x, const Vec3d& displacement) {
    points.push_back(x);
    pointDisplacement.push_back(displacement);
    return static_cast<int>(points.size()) - 1;
  }
  void setPointVector(const std::string& name, int point, const Vec3d& v) {
    auto& a = pointVectors[name];
    if (a.size() < points.size()) a.resize(points.size(), Vec3d{});
    a[point] = v;
  }
  void setCellScalar(const std::string& name, int cell, double v) {
    auto& a = cellScalars[name];
    if (a.size() < cellTypes.size()) a.resize(cellTypes.size(), 0.0);
    a[cell] = v;
  }
  void setPointScalar(const std::string& name, int point, double v) {
    auto& a = pointScalars[name];
    if (a.size() < points.size()) a.resize(points.size(), 0.0);
    a[point] = v;
  }
};

// A load vector given by its entries (global dofs and values).
struct SparseLoad {
  std::vector<GlobalDof> dofs;
  std::vector<double> values;
};
// The structure's compliance where a contribution acts (Compliance.hpp): v^T K^-1 v for each load v,
// K the tangent of the other contributions at `state`. Call on every rank with the same arguments.
using ComplianceFunction = std::function<std::vector<double>(const State& state, const std::vector<SparseLoad>& loads)>;
// The model's response to loads (Compliance.hpp, modelResponse): for each column c_j the motion
// K^-1 c_j on every dof, and r_i^T K^-1 c_j for the rows r_i (row-major), K the tangent of every
// contribution (the caller's too) at `state`. Call on every rank with the same arguments.
struct ModelResponse {
  std::vector<double> D;
  std::vector<std::vector<double>> motion;
};
using ResponseFunction = std::function<ModelResponse(const State& state, const std::vector<SparseLoad>& rows,
                                                     const std::vector<SparseLoad>& columns)>;

// The physics: what the contribution couples and adds to the residual and tangent, and its part in
// Newton's iteration.
class Physics {
 public:
  using OwnsDof = std::function<bool(GlobalDof)>;
  virtual ~Physics() = default;
  virtual std::string name() const = 0;
  // Appends the dof blocks this rank evaluates (each block's dofs are coupled in the matrix graph).
  virtual void connectivity(const OwnsDof& owns, std::vector<std::vector<GlobalDof>>& blocks) const = 0;
  // Adds this rank's blocks (those it owns) for the given state; `tangent` false skips the matrix.
  virtual void evaluate(const State& state, const OwnsDof& owns, AssemblySink& sink, bool tangent) const = 0;
  // Strain energy (or constraint potential) of this rank's blocks; used in tests and output.
  virtual double energy(const State& state, const OwnsDof& owns) const { return 0.0; }

  // Nonlinear-solution hooks (all ranks, same replicated state). At the start of every Newton
  // iteration: update what the contribution couples (its own extra unknowns in `state.extra`, e.g.
  // multipliers); return true when the matrix graph or the number of unknowns changed.
  virtual bool prepareIteration(State& state) { return false; }
  // Newton has converged for the increment: return true to accept, false to solve the increment
  // again (e.g. after updating multiplier estimates); throw std::runtime_error when that is no
  // longer allowed.
  virtual bool acceptSolution(State& state) { return true; }
  // Line search: Newton remembers the iterate it is about to leave (markIterate) and may return to it
  // to try a shorter step (returnToIterate); a contribution restores what prepareIteration changed
  // since the mark.
  virtual void markIterate() {}
  virtual void returnToIterate() {}
  // The largest fraction (<= 1) of the Newton step `du` from `state` that the contribution allows
  // (e.g. a constraint that is open now and would close at the full step: the step ends just past
  // its first touch, so the next tangent knows its stiffness).
  virtual double stepBound(const State& state, const std::vector<double>& du) const { return 1.0; }
  // A Newton solve failed to converge: what the contribution saw in its last iterations that may
  // explain it, as a sentence for the failure message (empty: nothing). Called on every rank.
  virtual std::string failureHint(const Teuchos::Comm<int>& comm) const { return ""; }
  // The solver hands every contribution the compliance of the structure without it, for parameters
  // chosen from the structure's stiffness (automatic penalty parameters); kept by those that use it.
  virtual void useCompliance(ComplianceFunction compliance) {}
  // And the whole model's response to loads, for a step coupled over several constraints (coupleStep).
  virtual void useResponse(ResponseFunction response) {}
  // Newton's step `du` from `state` (every dof: nodal and extra unknowns), before it is taken: a
  // contribution that enforces constraints through estimates it keeps between iterations (an
  // augmented Lagrange method) may move them with the step, so that the step is a Newton step on the
  // motion and the estimates together. It changes its estimates and adds to du the motion their
  // change causes; returns whether it did. Asked at every step (`near` false: only to follow the
  // iterates); it may act only when `near`: the residual below 1e-2 of the solve's first, the step
  // not shortened, no backtracking. Called on every rank with the same arguments.
  virtual bool coupleStep(State& state, std::vector<double>& du, bool near) { return false; }
  // The solver hands every contribution the communicator of its ranks: work that every rank would
  // otherwise do alike (a contact search's narrow phase) may be shared out and its results
  // exchanged, in the collective hooks above (prepareIteration). Without it the work is done whole.
  virtual void useCommunicator(const Teuchos::RCP<const Teuchos::Comm<int>>& comm) {}
};

// The load-step life cycle: history committed at a converged step, restored when a step is cut, and
// written to / read from a checkpoint.
class StepHistory {
 public:
  virtual ~StepHistory() = default;
  virtual void commitStep(const State& state) {}
  virtual void restoreStep() {}
  // Write what commitStep kept (the history of the last converged step) exactly, and read it back;
  // `committed` is that step's state, already restored.
  virtual void saveCommitted(CheckpointOut& out) const {}
  virtual void loadCommitted(CheckpointIn& in, const State& committed) {}
};

// Output: drawing for VTK (called on rank 0 with the full state), a per-step table written beside the
// results (file name, header after "step,T", rows of the last committed step) and a short text for
// the progress line.
class Output {
 public:
  virtual ~Output() = default;
  virtual void appendVtk(const State& state, VtkMesh& mesh) const {}
  // The VTK series appendVtk draws into: "" the beams' (vtk/step_N.vtu, results.pvd), else a lower-case
  // word other than "step", its own files vtk/<series>_N.vtu and <series>.pvd (contact: "contact"), so
  // that ParaView shows each on its own. Contributions of one series share its files.
  virtual std::string vtkSeries() const { return ""; }
  virtual std::string tableName() const { return ""; }
  virtual std::string tableHeader() const { return ""; }
  virtual std::vector<std::string> tableRows() const { return {}; }
  virtual std::string progressSummary() const { return ""; }
  // What the run could not model as asked (e.g. friction along a line contact): each a sentence,
  // written to status.txt after "complete" and printed; read when the run ends.
  virtual std::vector<std::string> warnings() const { return {}; }
  // After every converged step at load factor T (on every rank, with the committed state), and at a
  // restart for the checkpoint's step: checks of the converged state that warnings() reports.
  virtual void stepConverged(const State& state, double T) {}
};

// What the model holds: all three concerns of one piece of the model.
class Contribution : public Physics, public StepHistory, public Output {};

}  // namespace bc::core
