// Linear solvers chosen in the deck's "Linear Solver" sublist:
//  - "Direct": Amesos2 KLU2. On more than one rank the system is gathered to rank 0 and solved there
//    on a one-process communicator, because KLU2 on several ranks returned wrong solutions without an
//    error in this Trilinos build (see docs/toolchain.md).
//  - "GMRES": Belos GMRES, right-preconditioned by Ifpack2 (additive Schwarz with ILUT or RILUK
//    subdomain solves).
// Every solve is checked: the relative residual ||b - A x|| / ||b|| of the returned x is computed on
// the distributed system, and a value above "Residual Check Tolerance" raises LinearSolveError.
#pragma once
#include <memory>
#include <stdexcept>
#include <string>

#include "Parameters.hpp"
#include "TpetraTypes.hpp"

namespace bc::core {

class LinearSolveError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct SolveReport {
  int iterations = 0;          // Krylov iterations (0 for direct)
  double relativeResidual = 0; // ||b - A x|| / ||b|| of the returned solution
};

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  virtual std::string name() const = 0;
  SolveReport solve(const Teuchos::RCP<const Matrix>& A, const Vector& b, Vector& x);

 protected:
  explicit LinearSolver(double checkTolerance) : checkTolerance_(checkTolerance) {}
  virtual int doSolve(const Teuchos::RCP<const Matrix>& A, const Vector& b, Vector& x) = 0;

 private:
  double checkTolerance_;
};

const ParameterSpec& linearSolverSpec();
// `params` must have passed linearSolverSpec().apply().
std::unique_ptr<LinearSolver> makeLinearSolver(const Teuchos::ParameterList& params);

}  // namespace bc::core
