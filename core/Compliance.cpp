#include "Compliance.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include <Teuchos_DefaultSerialComm.hpp>

#include "Assembler.hpp"
#include "LinearSolver.hpp"
#include "linalg/SerialKlu.hpp"

namespace bc::core {

namespace {
// b from a load on K's rows, its entries on the `held` dofs dropped; false when nothing is left (the
// structure does not give there).
bool loadVector(const SparseLoad& load, const std::set<GlobalDof>& held, Vector& b) {
  const auto& map = *b.getMap();
  b.putScalar(0.0);
  auto bv = b.getDataNonConst();
  for (std::size_t k = 0; k < load.dofs.size(); ++k)
    if (!held.count(load.dofs[k])) bv[map.getLocalElement(load.dofs[k])] += load.values[k];
  bool any = false;
  for (double v : bv) any = any || v != 0.0;
  return any;
}

// x = K^-1 b with the factorization `lu` of K; whether the solve passes the linear solver's checks:
// backward error, and ||K|| ||x|| / ||b||, a lower bound of K's condition number.
bool checkedSolve(const Matrix& K, const SerialLu& lu, const Vector& b, Vector& x) {
  {
    const auto bv = b.getData();
    auto xv = x.getDataNonConst();
    lu.solve(bv.getRawPtr(), xv.getRawPtr());
  }
  const SolveReport check = residualReport(K, b, x);
  return check.backwardError <= 1e-8 && check.conditionBound <= 1e14;
}

// K of the model's contributions other than `without` (null: all of them) at `state` (supports held),
// factored on this rank alone; loads are solved against it with the linear solver's checks.
class StructureSolve {
 public:
  StructureSolve(const Model& model, const Physics* without, const State& state)
      : singular_(without ? "the structure without " + without->name() + " is singular (a beam held only by " +
                                without->name() + "?)"
                          : std::string("the model's tangent is singular")),
        structure_(heldStructure(model, without)),
        assembler_(Teuchos::rcp(new Teuchos::SerialComm<int>()), structure_) {
    assembler_.rebuild(state);
    assembler_.assemble(state, 0.0, true);
    try {
      klu_.factor(K(), false);
    } catch (const std::exception& e) {
      throw std::runtime_error(singular_ + ": " + e.what());
    }
  }
  const Matrix& K() const { return *assembler_.matrix(); }
  const std::set<GlobalDof>& held() const { return assembler_.constrainedDofs(); }
  const SerialLu& lu() const { return klu_; }
  [[noreturn]] void singular() const { throw std::runtime_error(singular_); }

 private:
  static Model heldStructure(const Model& model, const Physics* without) {
    Model structure;
    structure.supports = model.supports;
    for (const auto& c : model.contributions)
      if (static_cast<const Physics*>(c.get()) != without) structure.contributions.push_back(c);
    return structure;
  }
  std::string singular_;  // what a singular K means
  Model structure_;
  Assembler assembler_;
  SerialKlu klu_;
};

// r . x over a load's entries.
double dotLoad(const SparseLoad& r, const Vector& x) {
  const auto& map = *x.getMap();
  const auto xv = x.getData();
  double d = 0.0;
  for (std::size_t k = 0; k < r.dofs.size(); ++k) {
    const LO l = map.getLocalElement(r.dofs[k]);
    if (l != Teuchos::OrdinalTraits<LO>::invalid()) d += r.values[k] * xv[l];
  }
  return d;
}
}  // namespace

std::vector<double> structureCompliance(const Model& model, const Physics& without, const State& state,
                                        const std::vector<SparseLoad>& loads) {
  const StructureSolve structure(model, &without, state);
  std::vector<double> result;
  Vector b(structure.K().getRowMap()), x(structure.K().getRowMap());
  for (const SparseLoad& load : loads) {
    if (!loadVector(load, structure.held(), b)) {  // a load on held dofs only: the structure does not give there
      result.push_back(0.0);
      continue;
    }
    const bool solved = checkedSolve(structure.K(), structure.lu(), b, x);
    const double c = b.dot(x);
    if (solved && c > 0.0 && std::isfinite(c)) {
      result.push_back(c);
      continue;
    }
    if (c > 0.0 || !std::isfinite(c)) structure.singular();
    std::ostringstream s;
    s << "the structure without " << without.name() << " is not stable where " << without.name()
      << " acts (v^T K^-1 v = " << c << ")";
    throw std::runtime_error(s.str());
  }
  return result;
}

ModelResponse modelResponse(const Model& model, const State& state, const std::vector<SparseLoad>& rows,
                            const std::vector<SparseLoad>& columns) {
  StructureSolve structure(model, nullptr, state);
  return factoredResponse(structure.K(), structure.held(), structure.lu(), rows, columns);
}

ModelResponse factoredResponse(const Matrix& K, const std::set<GlobalDof>& held, const SerialLu& lu,
                               const std::vector<SparseLoad>& rows, const std::vector<SparseLoad>& columns) {
  const auto& map = *K.getRowMap();
  const std::size_t n = map.getGlobalNumElements();
  ModelResponse r;
  r.D.assign(rows.size() * columns.size(), 0.0);
  Vector b(K.getRowMap()), x(K.getRowMap());
  for (std::size_t j = 0; j < columns.size(); ++j) {
    r.motion.emplace_back(n, 0.0);
    if (!loadVector(columns[j], held, b)) continue;  // a load on held dofs only: the model does not move
    if (!checkedSolve(K, lu, b, x)) throw std::runtime_error("the model's tangent is singular");
    for (std::size_t i = 0; i < rows.size(); ++i) r.D[i * columns.size() + j] = dotLoad(rows[i], x);
    const auto xv = x.getData();
    for (LO l = 0; l < static_cast<LO>(xv.size()); ++l) r.motion[j][map.getGlobalElement(l)] = xv[l];
  }
  return r;
}

}  // namespace bc::core
