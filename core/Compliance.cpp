#include "Compliance.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include <Teuchos_DefaultSerialComm.hpp>

#include "Assembler.hpp"
#include "LinearSolver.hpp"
#include "linalg/SerialKlu.hpp"

namespace bc::core {

std::vector<double> structureCompliance(const Model& model, const Physics& without, const State& state,
                                        const std::vector<SparseLoad>& loads) {
  // The assembler reads the contributions and the supports (held, at load factor 0).
  Model structure;
  structure.supports = model.supports;
  for (const auto& c : model.contributions)
    if (static_cast<const Physics*>(c.get()) != &without) structure.contributions.push_back(c);
  Assembler assembler(Teuchos::rcp(new Teuchos::SerialComm<int>()), structure);
  assembler.rebuild(state);
  assembler.assemble(state, 0.0, true);
  const Matrix& K = *assembler.matrix();
  const auto& map = *K.getRowMap();
  SerialKlu klu;
  try {
    klu.factor(K, false);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("the structure without ") + without.name() +
                             " is singular (a beam held only by " + without.name() + "?): " + e.what());
  }
  std::vector<double> result;
  Vector b(K.getRowMap()), x(K.getRowMap());
  for (const SparseLoad& load : loads) {
    b.putScalar(0.0);
    {
      auto bv = b.getDataNonConst();
      for (std::size_t k = 0; k < load.dofs.size(); ++k)
        if (!assembler.constrainedDofs().count(load.dofs[k])) bv[map.getLocalElement(load.dofs[k])] += load.values[k];
    }
    if (b.norm2() == 0.0) {  // a load on held dofs only: the structure does not give there
      result.push_back(0.0);
      continue;
    }
    {
      const auto bv = b.getData();
      auto xv = x.getDataNonConst();
      klu.solve(bv.getRawPtr(), xv.getRawPtr());
    }
    // The linear solver's checks: backward error, and ||K|| ||x|| / ||b||, a lower bound of K's
    // condition number.
    const SolveReport check = residualReport(K, b, x);
    const double c = b.dot(x);
    if (c > 0.0 && std::isfinite(c) && check.backwardError <= 1e-8 && check.conditionBound <= 1e14) {
      result.push_back(c);
      continue;
    }
    if (c > 0.0 || !std::isfinite(c))
      throw std::runtime_error("the structure without " + without.name() + " is singular (a beam held only by " +
                               without.name() + "?)");
    std::ostringstream s;
    s << "the structure without " << without.name() << " is not stable where " << without.name()
      << " acts (v^T K^-1 v = " << c << ")";
    throw std::runtime_error(s.str());
  }
  return result;
}

}  // namespace bc::core
