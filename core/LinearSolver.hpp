// Linear solvers chosen in the deck's "Linear Solver" sublist:
//  - "Direct": a sparse LU, "Direct Solver" KLU2 (core/SerialKlu: a matrix of the last one's pattern is
//    refactored with its pivot order) or UMFPACK (core/SerialUmfpack: multifrontal, BLAS kernels).
//    On more than one rank the system is gathered to rank 0 and solved there on a one-process
//    communicator, because KLU2 on several ranks returned wrong solutions without an error in this
//    Trilinos build (see docs/toolchain.md). "Direct Solver" MUMPS (core/MumpsLu) is factored where
//    the rows are, by every rank. With "Reuse Factorization", GMRES preconditioned with
//    the last factorization solves first; a saddle point (Lagrange multipliers: rows with a zero
//    diagonal) is then factored with that diagonal regularized, and GMRES solves the saddle point
//    itself.
//  - "GMRES": Belos GMRES, right-preconditioned by Ifpack2 (additive Schwarz with ILUT or RILUK
//    subdomain solves) or by smoothed-aggregation multigrid (MueLu, with the nodes' rigid-body modes
//    as near-null space; for matrices without multiplier rows).
// Every solve is checked: the residual b - A x of the returned x is computed on the distributed
// system, and its normwise backward error ||b - A x|| / (||A||_F ||x|| + ||b||) above "Residual Check
// Tolerance" raises LinearSolveError. (The backward error is scale-invariant: a backward-stable solve
// gives ~1e-16 even when ||b|| is small against the terms of A x that cancel, where ||b - A x|| / ||b||
// can be 1e-8 for a perfectly good solve.) A singular matrix can pass that test with a huge x, so
// ||A||_F ||x|| / ||b||, a lower bound of the condition number, above "Condition Limit" is an error too.
#pragma once
#include <memory>
#include <new>
#include <stdexcept>
#include <string>

#include <Teuchos_StackedTimer.hpp>

#include "Faults.hpp"
#include "Parameters.hpp"
#include "TpetraTypes.hpp"

namespace bc::core {

class LinearSolveError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A factorization that needs more memory than it can have. Not a failure of the step (a smaller step
// needs the same): it ends the run, its message in status.txt, exit code 3 (out of memory).
using LinearSolverOutOfMemory = OutOfMemory;  // (Faults.hpp: a std::bad_alloc with a one-line message)

struct SolveReport {
  int iterations = 0;          // Krylov iterations (0 for direct)
  double relativeResidual = 0; // ||b - A x|| / ||b|| of the returned solution
  double backwardError = 0;    // ||b - A x|| / (||A||_F ||x|| + ||b||), checked
  double conditionBound = 0;   // ||A||_F ||x|| / ||b||, a lower bound of cond(A), checked
  double solutionNorm = 0;     // ||x||
};

// The residual measures of x as a solution of A x = b (iterations 0): what every solve is checked by.
SolveReport residualReport(const Matrix& A, const Vector& b, const Vector& x);

// ||v||_2 without underflow or overflow: Tpetra's norm2 squares the entries, so entries below about
// 1e-154 square to 0 (forces of a model that is very soft in its units: a residual of 1e-298 had the
// norm 0). Scaled by the largest entry when that lies outside 1e-150 .. 1e150; else the plain norm.
double scaledNorm2(const Vector& v);

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  virtual std::string name() const = 0;
  SolveReport solve(const Teuchos::RCP<const Matrix>& A, const Vector& b, Vector& x);
  // Whether the solver wants the matrix's near-null space (the rigid-body modes of the nodes) with
  // every solve (the multigrid preconditioner does), and where it is given.
  virtual bool wantsNearNullSpace() const { return false; }
  void setNearNullSpace(const Teuchos::RCP<MultiVector>& modes) { nearNull_ = modes; }
  // With a timer, the stages of a solve are timed within the caller's running timer.
  void setTimer(Teuchos::RCP<Teuchos::StackedTimer> timer) { timer_ = timer; }

 protected:
  LinearSolver(double checkTolerance, double conditionLimit)
      : checkTolerance_(checkTolerance), conditionLimit_(conditionLimit) {}
  virtual int doSolve(const Teuchos::RCP<const Matrix>& A, const Vector& b, Vector& x) = 0;
  // The last doSolve took a shortcut (Direct: a refactorization with old pivots): the next one is to
  // do without it; return false when there was none. The same answer on every rank.
  virtual bool redoWithoutShortcut() { return false; }
  Teuchos::RCP<MultiVector> nearNull_;
  Teuchos::RCP<Teuchos::StackedTimer> timer_;
  // Times a stage of a solve from construction to the end of its scope (also when it throws).
  class Stage {
   public:
    Stage(const LinearSolver& solver, const char* name) : timer_(solver.timer_), name_(name) {
      if (!timer_.is_null()) timer_->start(name_);
    }
    ~Stage() {
      if (!timer_.is_null()) timer_->stop(name_);
    }
    Stage(const Stage&) = delete;
    Stage& operator=(const Stage&) = delete;

   private:
    Teuchos::RCP<Teuchos::StackedTimer> timer_;
    const char* name_;
  };

 private:
  // doSolve and the residual of its x (the report, unchecked).
  SolveReport attempt(const Teuchos::RCP<const Matrix>& A, const Vector& b, Vector& x);
  double checkTolerance_, conditionLimit_;
};

const ParameterSpec& linearSolverSpec();
// `params` must have passed linearSolverSpec().apply().
std::unique_ptr<LinearSolver> makeLinearSolver(const Teuchos::ParameterList& params);

}  // namespace bc::core
