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
    return p;
  }();
  return s;
}

PenaltyEnforcer::PenaltyEnforcer(const Teuchos::ParameterList& v)
    : normalPenalty_(v.get<double>("Normal Penalty Parameter")),
      tangentialPenalty_(v.get<double>("Tangential Penalty Parameter")) {}

namespace {
FrictionRegularization friction(const PenaltyEnforcer::State& s, double eps) {
  FrictionRegularization t;
  t.lambdaHat[0] = s.lambdaT[0];
  t.lambdaHat[1] = s.lambdaT[1];
  t.penalty = eps;
  return t;
}
}  // namespace

PointResult PenaltyEnforcer::evaluate(const ContactPoint& p, const PointState& s, double* f, double* K) const {
  return regularizedEvaluate(p, linearNormalLaw(0.0, normalPenalty_), friction(stateOf<State>(s), tangentialPenalty_),
                             f, K);
}

bool PenaltyEnforcer::acceptPoint(const ContactPoint& p, PointState&, double& worstViolation) const {
  worstViolation = std::max(worstViolation, std::max(0.0, -p.kinematics.normal.value));
  return true;
}

void PenaltyEnforcer::commitPoint(const ContactPoint& p, PointState& s) const {
  State& state = stateOf<State>(s);
  const PointResult r =
      regularizedForces(p, linearNormalLaw(0.0, normalPenalty_), friction(state, tangentialPenalty_));
  for (int i = 0; i < 2; ++i) state.lambdaT[i] = r.lambdaT[i];
}

}  // namespace bc::constraints
