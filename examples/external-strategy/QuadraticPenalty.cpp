#include "QuadraticPenalty.hpp"

#include <algorithm>

#include <constraints/Plugin.hpp>
#include <constraints/RegularizedContactLaw.hpp>

namespace quadratic {

using namespace bc::constraints;

const bc::core::ParameterSpec& QuadraticPenalty::spec() {
  static const bc::core::ParameterSpec s = [] {
    bc::core::ParameterSpec p;
    p.addRequired("Quadratic Penalty Parameter", 1e6, "eps_Q: normal force eps_Q g_N^2 [force/length^2]",
                  bc::core::positive(), "> 0");
    p.addRequired("Tangential Penalty Parameter", 1e3, "eps_T: stick stiffness [force/length]", bc::core::positive(),
                  "> 0");
    return p;
  }();
  return s;
}

QuadraticPenalty::QuadraticPenalty(const Teuchos::ParameterList& v)
    : quadratic_(v.get<double>("Quadratic Penalty Parameter")),
      tangential_(v.get<double>("Tangential Penalty Parameter")) {}

namespace {
// The normal law as a function of g_N; its derivatives (the tangent) come by automatic differentiation.
NormalLaw quadraticLaw(double eps) {
  return [eps](const LawScalar& g) -> LawScalar { return -eps * g * g; };
}
FrictionRegularization friction(const QuadraticPenalty::State& s, double eps) {
  FrictionRegularization t;
  t.lambdaHat[0] = s.lambdaT[0];
  t.lambdaHat[1] = s.lambdaT[1];
  t.penalty = eps;
  return t;
}
}  // namespace

PointResult QuadraticPenalty::evaluate(const ContactPoint& p, const PointState& s, double* f, double* K) const {
  return regularizedEvaluate(p, quadraticLaw(quadratic_), friction(stateOf<State>(s), tangential_), f, K);
}

bool QuadraticPenalty::acceptPoint(const ContactPoint& p, PointState&, double& worstViolation) const {
  worstViolation = std::max(worstViolation, std::max(0.0, -p.kinematics.normal.value));
  return true;
}

void QuadraticPenalty::commitPoint(const ContactPoint& p, PointState& s) const {
  State& state = stateOf<State>(s);
  const PointResult r = regularizedForces(p, quadraticLaw(quadratic_), friction(state, tangential_));
  state.lambdaT[0] = r.lambdaT[0];
  state.lambdaT[1] = r.lambdaT[1];
}

}  // namespace quadratic

BEAMCONTACT_PLUGIN(bc::constraints::registerEnforcer<quadratic::QuadraticPenalty>();)
