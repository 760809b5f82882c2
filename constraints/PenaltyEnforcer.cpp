#include "PenaltyEnforcer.hpp"

#include <algorithm>
#include <cmath>

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

PenaltyEnforcer::PenaltyEnforcer(const Teuchos::ParameterList& v) {
  p_.normalPenalty = v.get<double>("Normal Penalty Parameter");
  p_.tangentialPenalty = v.get<double>("Tangential Penalty Parameter");
}

bool PenaltyEnforcer::contributes(const ContactKinematics& k, const PointHistory&) const {
  return k.normal.value < 0.0;
}

PointResult PenaltyEnforcer::evaluate(const ContactKinematics& k, const PointHistory& h, double mu, const double*,
                                      double* f, double* K) const {
  PointHistory penalty = h;
  penalty.lambdaN = 0.0;  // no normal multiplier estimate in the penalty method
  return regularizedEvaluate(k, penalty, mu, parameters(), f, K);
}

bool PenaltyEnforcer::acceptPoint(const ContactKinematics& k, PointHistory&, double, const double*,
                                  double& worstViolation) const {
  worstViolation = std::max(worstViolation, std::max(0.0, -k.normal.value));
  return true;
}

void PenaltyEnforcer::commitPoint(const ContactKinematics& k, PointHistory& h, double mu, const double*) const {
  PointHistory penalty = h;
  penalty.lambdaN = 0.0;
  const PointResult r = regularizedForces(k, penalty, mu, parameters());
  h.lambdaN = r.lambdaN;
  for (int i = 0; i < 2; ++i) h.lambdaT[i] = r.lambdaT[i];
}

}  // namespace bc::constraints
