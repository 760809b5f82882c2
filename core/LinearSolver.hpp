// The deck's "Linear Solver" sublist: its parameters (linearSolverSpec) and the solver they make.
// The solvers themselves are the linear algebra library's (core/linalg: linalg/LinearSolver.hpp):
//  - "Direct": a sparse LU, "Direct Solver" one of linalg/DirectMethod.hpp's registry (KLU2,
//    UMFPACK, MUMPS; the accepted values and their documentation come from it). With "Reuse
//    Factorization", GMRES preconditioned with the last factorization solves first.
//  - "GMRES": Belos GMRES with an Ifpack2 or MueLu preconditioner.
// Every solve is checked by its backward error ("Residual Check Tolerance") and a lower bound of the
// matrix's condition number ("Condition Limit"): LinearSolveError.
#pragma once
#include <functional>
#include <memory>
#include <string>

#include "Faults.hpp"
#include "Parameters.hpp"
#include "linalg/LinearSolver.hpp"

namespace bc::core {

const ParameterSpec& linearSolverSpec();
// Validates the deck's Linear Solver list `user` at `path` (linearSolverSpec().apply) and refuses a
// parameter of the other Type's family that the deck gives (Direct Solver or Reuse Iteration Limit with
// GMRES; Preconditioner, Fill Level, Overlap, Tolerance, Maximum Iterations or Restart with Direct) set
// away from its default: it would be ignored, and the run would use a solver the deck does not describe.
void applyLinearSolverParameters(Teuchos::ParameterList& user, const std::string& path);

// Direct Solver = Automatic (the default): the sparse LU by the model's size, its contact points and
// the rank count. UMFPACK with Reuse Factorization when the model has at least kAutomaticLuUnknowns
// unknowns and at least one contact point at the start per kAutomaticUnknownsPerPoint unknowns; on
// several ranks MUMPS with it instead from kAutomaticMumpsUnknowns unknowns (it factors on every rank;
// UMFPACK on rank 0 after a gather); KLU2 without reuse otherwise. The contact couplings between beams
// are what fills the LU factors: a few points on many unknowns (a weave meshed finely along its yarns)
// leave the matrix nearly banded, where KLU2 (which refactors with its old pivots) is the fastest, as
// it is on small matrices, which have no dense fronts for UMFPACK's BLAS. The numbers come from
// bench/bench_default_solver.py (docs/scale.md, "The default solver").
constexpr long long kAutomaticLuUnknowns = 3000;
constexpr long long kAutomaticUnknownsPerPoint = 40;
constexpr long long kAutomaticMumpsUnknowns = 60000;
struct SystemSize {
  long long unknowns = 0;  // 6 per node and the extra unknowns
  long long contactPoints = 0;
  int ranks = 1;
};
struct DirectChoice {
  std::string method;
  bool reuse = false;
  std::string reason;  // e.g. "122400 unknowns, 10000 contact points on 1 rank"
};
DirectChoice chooseDirectSolver(const SystemSize& size);
// The rule above in words (the reference's documentation of Direct Solver).
std::string automaticRule();
// Resolves Direct Solver = Automatic in `params` (validated by linearSolverSpec) for `size`: sets
// Direct Solver, and Reuse Factorization unless the deck gives it, each with the reason as its doc
// string (effective_parameters.xml shows it); with a Direct Solver named, Reuse Factorization false
// unless given. Returns the choice in one line for the run's header, or "" when the deck names the
// solver or Type is GMRES.
std::string resolveLinearSolver(Teuchos::ParameterList& params, const SystemSize& size);
// `params` must have passed linearSolverSpec().apply() and resolveLinearSolver().
std::unique_ptr<LinearSolver> makeLinearSolver(const Teuchos::ParameterList& params);
// The same with Direct Solver = Automatic resolved first (on a copy of `params`).
std::unique_ptr<LinearSolver> makeLinearSolver(const Teuchos::ParameterList& params, const SystemSize& size);

// Direct Solver = Automatic through a run: contact points that appear after the start (beams that
// start apart) make the matrix's LU fill as those at the start do, so a run that starts on KLU2 takes
// the rule again before every solve, with the matrix's rows as its unknowns and `contactPoints()` (the
// largest over the ranks) as its points, and changes to the rule's LU once (never back: a point
// that opens still holds its place in the graph's pattern for a while). `onChange` is called on
// every rank with the new choice.
struct AutomaticChange {
  std::string line;  // as resolveLinearSolver's, for the run's output
  Teuchos::ParameterList resolved;  // `params` resolved for the new size
};
// `params`: validated (linearSolverSpec), not resolved. Without Automatic, or when the choice at
// `start` is not KLU2 already, the solver of makeLinearSolver(params, start).
std::unique_ptr<LinearSolver> makeLinearSolver(const Teuchos::ParameterList& params, const SystemSize& start,
                                               std::function<long long()> contactPoints,
                                               std::function<void(const AutomaticChange&)> onChange);

}  // namespace bc::core
