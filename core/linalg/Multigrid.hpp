// Smoothed-aggregation algebraic multigrid (MueLu) as a preconditioner of the beam tangent, in its own
// translation unit (MueLu's headers are heavy). The beams' near-null space is the six rigid-body
// modes per node (three translations, three rotations about the model's centre), given by the
// caller; aggregation groups whole nodes (6 dofs). Only for matrices of nodal dofs: no multiplier rows.
#pragma once
#include "core/TpetraTypes.hpp"

namespace bc::core {

struct MultigridSettings {
  int sweeps = 2;  // symmetric Gauss-Seidel sweeps per level, before and after
  int coarseSize = 2000;  // rows below which the coarsest level is solved directly (KLU2)
};

// The preconditioner for A. `nearNull` holds 6 vectors on A's row map.
Teuchos::RCP<Operator> makeMultigrid(const Teuchos::RCP<const Matrix>& A, const Teuchos::RCP<MultiVector>& nearNull,
                                     const MultigridSettings& settings);

}  // namespace bc::core
