#include "Multigrid.hpp"

#include <MueLu_CreateTpetraPreconditioner.hpp>

namespace bc::core {

Teuchos::RCP<Operator> makeMultigrid(const Teuchos::RCP<const Matrix>& A, const Teuchos::RCP<MultiVector>& nearNull,
                                     const MultigridSettings& settings) {
  Teuchos::ParameterList p;
  p.set("verbosity", "none");
  p.set("multigrid algorithm", "sa");
  p.set("number of equations", 6);
  p.set("problem: symmetric", false);
  p.set("aggregation: type", "uncoupled");
  p.set("coarse: max size", settings.coarseSize);
  p.set("coarse: type", "KLU2");
  p.set("smoother: type", "RELAXATION");
  p.sublist("smoother: params").set("relaxation: type", "Symmetric Gauss-Seidel");
  p.sublist("smoother: params").set("relaxation: sweeps", settings.sweeps);
  p.set("repartition: enable", false);
  p.sublist("user data").set("Nullspace", nearNull);
  Teuchos::RCP<Operator> op = Teuchos::rcp_const_cast<Matrix>(A);
  return MueLu::CreateTpetraPreconditioner<Scalar, LO, GO, Node>(op, p);
}

}  // namespace bc::core
