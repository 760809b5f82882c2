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
}  // namespace

PointResult QuadraticPenalty::evaluate(const ContactPoint& p, const PointState& s, double* f, double* K) const {
  const State& h = stateOf<State>(s);
  const FrictionRegularization friction{{h.lambdaT[0], h.lambdaT[1]}, tangential_};
  return regularizedEvaluate(p, quadraticLaw(quadratic_), friction, f, K);
}

bool QuadraticPenalty::acceptPoint(const ContactPoint& p, PointState&, double& worstViolation) const {
  worstViolation = std::max(worstViolation, std::max(0.0, -p.kinematics.normal.value));
  return true;
}

void QuadraticPenalty::commitPoint(const ContactPoint& p, PointState& s) const {
  State& state = stateOf<State>(s);
  const FrictionRegularization friction{{state.lambdaT[0], state.lambdaT[1]}, tangential_};
  const PointResult r = regularizedForces(p, quadraticLaw(quadratic_), friction);
  state.lambdaT[0] = r.lambdaT[0];
  state.lambdaT[1] = r.lambdaT[1];
}

}  // namespace quadratic

BEAMCONTACT_PLUGIN(bc::constraints::registerEnforcer<quadratic::QuadraticPenalty>();)
