// The structure's compliance at given loads: for a load vector v, c = v^T K^-1 v, with K the tangent
// of the model's contributions other than one (e.g. every contribution but contact) at a state, the
// supports held. For a unit load along a constraint's gradient it is the constraint's diagonal
// Delassus entry: how far the structure gives per unit of force there [length/force]. Automatic
// penalty parameters are chosen from it (docs/contact.md, "Automatic penalty parameters").
//
// Every rank assembles and factors K in full on its own (the state is replicated), so the answer is
// the same everywhere and no communication is needed; meant for the few calls of a run (new contact
// points), not for every Newton iteration. modelResponse is asked at Newton iterations near the
// solution for a few constraints (ContactManager::coupleStep) on several ranks; on one rank the
// solver answers from its own tangent (factoredResponse).
#pragma once
#include <set>
#include <vector>

#include "Contribution.hpp"
#include "Model.hpp"
#include "linalg/SerialLu.hpp"

namespace bc::core {

// v^T K^-1 v for each load of `loads`; K from the contributions of `model` except `without`, at
// `state`. Throws std::runtime_error when K is singular (a free motion without `without`: a beam held
// only by contact) or not positive for a load (the structure buckled there).
std::vector<double> structureCompliance(const Model& model, const Physics& without, const State& state,
                                        const std::vector<SparseLoad>& loads);

// The model's response to loads: for each column load c_j the motion x_j = K^-1 c_j (on every dof, in
// the order of the global dofs) and D_ij = r_i^T x_j for the rows r_i (row-major, rows x columns), K
// the tangent of all the model's contributions at `state` (supports held): how far the model moves
// along r_i under a unit load c_j. Throws std::runtime_error when K is singular.
ModelResponse modelResponse(const Model& model, const State& state, const std::vector<SparseLoad>& rows,
                            const std::vector<SparseLoad>& columns);
// The same from a one-process matrix K already factored by `lu`, the entries of the loads on the
// `held` dofs dropped (Newton's own tangent on one rank: no assembly).
ModelResponse factoredResponse(const Matrix& K, const std::set<GlobalDof>& held, const SerialLu& lu,
                               const std::vector<SparseLoad>& rows, const std::vector<SparseLoad>& columns);

}  // namespace bc::core
