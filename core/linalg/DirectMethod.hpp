// The Direct linear solver's sparse LU factorizations, peers behind one registry (directMethods()):
//  - "KLU2" (SerialKlu: a matrix of the last one's pattern is refactored with its pivot order) and
//    "UMFPACK" (SerialUmfpack: multifrontal, BLAS kernels) factor a matrix on one process. On more
//    than one rank the system is gathered to rank 0 and solved there on a one-process communicator
//    (gatheredToRank0, a wrapper around any of them), because KLU2 on several ranks returned wrong
//    solutions without an error in this Trilinos build (see docs/toolchain.md).
//  - "MUMPS" (MumpsLu) factors the matrix where its rows are, by every rank.
// With Reuse Factorization each one solves first by GMRES (Krylov.hpp) preconditioned with its last
// factorization; a saddle point (Lagrange multipliers: rows with a zero diagonal) is then factored
// with that diagonal regularized (Regularization.hpp), and GMRES solves the saddle point itself.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Teuchos_StackedTimer.hpp>

#include "core/TpetraTypes.hpp"

namespace bc::core {

class SerialLu;

// Reuse Factorization's settings (LinearSolver.hpp's "Linear Solver" parameters).
struct ReuseSettings {
  bool on = false;
  int iterationLimit = 0;  // GMRES iterations summed since the last factorization; 0: automatic
  double target = 0.0;  // the backward error GMRES stops at
};

class DirectMethod {
 public:
  virtual ~DirectMethod() = default;
  // The registry's name ("KLU2", "UMFPACK", "MUMPS").
  virtual std::string name() const = 0;
  // Solves A x = b (every rank of A's communicator calls it together); returns the Krylov iterations
  // (0: direct). With `shortcuts`: GMRES preconditioned with the last factorization when reuse is on,
  // and (KLU2) a refactorization with the last pivot order when A is the last matrix with new values
  // (`sameGraph`). Throws LinearSolveError, OutOfMemory, or std::runtime_error for a failed
  // factorization.
  virtual int solve(const Matrix& A, bool shortcuts, bool sameGraph, const Vector& b, Vector& x) = 0;
  // Whether the last solve refactored with old pivots or reused an old factorization (the same
  // answer on every rank).
  bool tookShortcut() const { return shortcut_; }
  // With a timer, the stages of a solve are timed within the caller's running timer.
  void setTimer(Teuchos::RCP<Teuchos::StackedTimer> timer) { timer_ = timer; }

 protected:
  bool shortcut_ = false;
  Teuchos::RCP<Teuchos::StackedTimer> timer_;
};

// A factorization on one process (A: all rows on this one), around a SerialLu.
std::unique_ptr<DirectMethod> oneProcessLu(std::unique_ptr<SerialLu> lu, const ReuseSettings& reuse);
// `onOneProcess` (a oneProcessLu) for a matrix over the ranks: the system gathered to rank 0 and
// solved there; its failures are agreed, so that every rank throws the same error.
std::unique_ptr<DirectMethod> gatheredToRank0(std::unique_ptr<DirectMethod> onOneProcess);
// MUMPS over the ranks of `comm`.
std::unique_ptr<DirectMethod> makeMumpsMethod(const Comm& comm, const ReuseSettings& reuse);

// The registry of the "Direct Solver" values: each factorization's name, what the deck's reference
// says of it, and how it is made for a communicator (one that works on one process is gathered to
// rank 0 on more).
struct DirectMethodEntry {
  std::string name;
  std::string doc;
  bool distributed;  // factors the matrix where its rows are (else on one process)
  std::function<std::unique_ptr<DirectMethod>(const Comm& comm, const ReuseSettings& reuse)> make;
};
const std::vector<DirectMethodEntry>& directMethods();
// The names, in the registry's order (the deck's accepted "Direct Solver" values).
std::vector<std::string> directMethodNames();
// "<name>: <doc>; <name>: <doc>; ..." (the deck reference's text of "Direct Solver").
std::string directMethodsDoc();
// The named factorization for a matrix on `comm` (gathered to rank 0 when it works on one process and
// `comm` has more than one rank). Throws std::invalid_argument for a name not in the registry.
std::unique_ptr<DirectMethod> makeDirectMethod(const std::string& name, const Comm& comm, const ReuseSettings& reuse);

}  // namespace bc::core
