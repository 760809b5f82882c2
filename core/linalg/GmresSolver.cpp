// The GMRES linear solver: Belos GMRES, right-preconditioned by Ifpack2 or MueLu.
#include <BelosSolverFactory.hpp>
#include <BelosTpetraAdapter.hpp>
#include <Ifpack2_Factory.hpp>

#include "core/ScopedTimer.hpp"
#include "LinearSolver.hpp"
#include "Multigrid.hpp"

namespace bc::core {

namespace {

class GmresSolver : public LinearSolver {
 public:
  explicit GmresSolver(const GmresSettings& s) : LinearSolver(s.checks), s_(s) {}
  std::string name() const override { return "GMRES (" + s_.preconditioner + ")"; }
  bool wantsNearNullSpace() const override { return s_.preconditioner == "MueLu"; }

 protected:
  int doSolve(const Teuchos::RCP<const Matrix>& A, const Vector& b, Vector& x) override {
    const Teuchos::RCP<Operator> prec = preconditioner(A);
    x.putScalar(0.0);
    auto problem = Teuchos::rcp(
        new Belos::LinearProblem<Scalar, MultiVector, Operator>(A, Teuchos::rcpFromRef(x), Teuchos::rcpFromRef(b)));
    problem->setRightPrec(prec);
    problem->setProblem();
    auto params = Teuchos::rcp(new Teuchos::ParameterList);
    params->set("Convergence Tolerance", s_.tolerance);
    params->set("Maximum Iterations", s_.maxIterations);
    params->set("Num Blocks", s_.restart);
    Belos::SolverFactory<Scalar, MultiVector, Operator> belos;
    auto solver = belos.create("GMRES", params);
    solver->setProblem(problem);
    ScopedTimer stage(timer_, "Krylov Iterations");
    solver->solve();
    return solver->getNumIters();
  }

 private:
  Teuchos::RCP<Operator> preconditioner(const Teuchos::RCP<const Matrix>& A) {
    ScopedTimer setup(timer_, "Preconditioner Setup");
    if (s_.preconditioner == "MueLu") {
      if (nearNull_.is_null() || !nearNull_->getMap()->isSameAs(*A->getRowMap()))
        throw LinearSolveError("GMRES (MueLu): no near-null space for this matrix");
      MultigridSettings m;
      m.sweeps = std::max(1, static_cast<int>(s_.fill));
      return makeMultigrid(A, nearNull_, m);
    }
    using RowMatrix = Tpetra::RowMatrix<Scalar, LO, GO, Node>;
    Ifpack2::Factory factory;
    auto schwarz = factory.create<RowMatrix>("SCHWARZ", A);
    Teuchos::ParameterList pp;
    pp.set("schwarz: overlap level", s_.overlap);
    pp.set("inner preconditioner name", s_.preconditioner);
    Teuchos::ParameterList& inner = pp.sublist("inner preconditioner parameters");
    if (s_.preconditioner == "ILUT") {
      inner.set("fact: ilut level-of-fill", s_.fill);
      inner.set("fact: drop tolerance", 0.0);
    } else {
      inner.set("fact: iluk level-of-fill", static_cast<int>(s_.fill));
    }
    schwarz->setParameters(pp);
    schwarz->initialize();
    schwarz->compute();
    return schwarz;
  }

  GmresSettings s_;
};

}  // namespace

std::unique_ptr<LinearSolver> makeGmresSolver(const GmresSettings& settings) {
  return std::make_unique<GmresSolver>(settings);
}

}  // namespace bc::core
