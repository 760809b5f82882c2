#include "Compliance.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include <Teuchos_DefaultSerialComm.hpp>

#include "Assembler.hpp"
#include "SerialKlu.hpp"

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
  const double normK = K.getFrobeniusNorm();
  std::vector<double> result;
  Vector b(K.getRowMap()), x(K.getRowMap()), r(K.getRowMap());
  for (const SparseLoad& load : loads) {
    b.putScalar(0.0);
    {
      auto bv = b.getDataNonConst();
      for (std::size_t k = 0; k < load.dofs.size(); ++k)
        if (!assembler.constrainedDofs().count(load.dofs[k])) bv[map.getLocalElement(load.dofs[k])] += load.values[k];
    }
    {
      const auto bv = b.getData();
      auto xv = x.getDataNonConst();
      klu.solve(bv.getRawPtr(), xv.getRawPtr());
    }
    K.apply(x, r);
    r.update(1.0, b, -1.0);
    const double bn = b.norm2(), xn = x.norm2(), c = b.dot(x);
    if (bn == 0.0) {  // a load on held dofs only: the structure does not give there
      result.push_back(0.0);
      continue;
    }
    // ||K|| ||x|| / ||b|| bounds K's condition number from below (LinearSolver's check).
    if (!std::isfinite(c) || r.norm2() > 1e-8 * (normK * xn + bn) || normK * xn / bn > 1e14 || !(c > 0.0)) {
      std::ostringstream s;
      s << "the structure without " << without.name() << " is "
        << (c > 0.0 || !std::isfinite(c) ? "singular (a beam held only by " + without.name() + "?)"
                                         : "not stable where " + without.name() + " acts (v^T K^-1 v = ")
        << (c > 0.0 || !std::isfinite(c) ? "" : std::to_string(c) + ")");
      throw std::runtime_error(s.str());
    }
    result.push_back(c);
  }
  return result;
}

}  // namespace bc::core
