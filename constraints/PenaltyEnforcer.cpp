#include "PenaltyEnforcer.hpp"

#include <algorithm>

#include "RegularizedContactLaw.hpp"

namespace bc::constraints {

const core::ParameterSpec& PenaltyEnforcer::spec() {
  static const core::ParameterSpec s = [] {
    core::ParameterSpec p;
    p.addRequired("Normal Penalty Parameter", 1e4, "eps_N: stiffness of the normal contact spring [force/length]",
                  core::positive(), "> 0");
    p.addRequired("Tangential Penalty Parameter", 1e3,
                  "eps_T: stiffness of the tangential (stick) spring [force/length]", core::positive(), "> 0");
    p.add("Regularization Gap", 0.0,
          "g0: the normal force grows as eps_N g^2 / (2 g0) over the first g0 of penetration, then linearly "
          "(eps_N (|g| - g0 / 2)); a smooth onset for contacts that close many points at once (line contact, "
          "dense grids); 0: linear from the first touch [length]",
          core::nonNegative(), ">= 0");
    return p;
  }();
  return s;
}

PenaltyEnforcer::PenaltyEnforcer(const Teuchos::ParameterList& v)
    : normalPenalty_(v.get<double>("Normal Penalty Parameter")),
      tangentialPenalty_(v.get<double>("Tangential Penalty Parameter")),
      law_(smoothedPenaltyLaw(normalPenalty_, v.get<double>("Regularization Gap"))) {}

PointResult PenaltyEnforcer::evaluate(const ContactPoint& p, const PointState& s, double* f, double* K) const {
  const State& h = stateOf<State>(s);
  const FrictionRegularization friction{{h.lambdaT[0], h.lambdaT[1]}, tangentialPenalty_};
  return regularizedEvaluate(p, law_, friction, f, K);
}

bool PenaltyEnforcer::acceptPoint(const ContactPoint& p, PointState&, double& worstViolation) const {
  worstViolation = std::max(worstViolation, std::max(0.0, -p.kinematics.normal.value));
  return true;
}

void PenaltyEnforcer::commitPoint(const ContactPoint& p, PointState& s) const {
  State& state = stateOf<State>(s);
  const FrictionRegularization friction{{state.lambdaT[0], state.lambdaT[1]}, tangentialPenalty_};
  const PointResult r = regularizedForces(p, law_, friction);
  for (int i = 0; i < 2; ++i) state.lambdaT[i] = r.lambdaT[i];
}

}  // namespace bc::constraints
