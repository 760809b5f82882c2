// The deck's "Linear Solver" sublist: its parameters (linearSolverSpec) and the solver they make.
// The solvers themselves are the linear algebra library's (core/linalg: linalg/LinearSolver.hpp):
//  - "Direct": a sparse LU, "Direct Solver" one of linalg/DirectMethod.hpp's registry (KLU2,
//    UMFPACK, MUMPS; the accepted values and their documentation come from it). With "Reuse
//    Factorization", GMRES preconditioned with the last factorization solves first.
//  - "GMRES": Belos GMRES with an Ifpack2 or MueLu preconditioner.
// Every solve is checked by its backward error ("Residual Check Tolerance") and a lower bound of the
// matrix's condition number ("Condition Limit"): LinearSolveError.
#pragma once
#include <memory>

#include "Faults.hpp"
#include "Parameters.hpp"
#include "linalg/LinearSolver.hpp"

namespace bc::core {

const ParameterSpec& linearSolverSpec();
// `params` must have passed linearSolverSpec().apply().
std::unique_ptr<LinearSolver> makeLinearSolver(const Teuchos::ParameterList& params);

}  // namespace bc::core
