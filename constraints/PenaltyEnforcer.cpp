#include "PenaltyEnforcer.hpp"

#include <algorithm>

#include "RegularizedContactLaw.hpp"

namespace bc::constraints {

const core::ParameterSpec& PenaltyEnforcer::spec() {
  static const core::ParameterSpec s = [] {
    core::ParameterSpec p;
    PenaltyChoice::addTo(p, "stiffness");
    p.add("Regularization Gap", 0.0,
          "g0: the normal force grows as eps_N g^2 / (2 g0) over the first g0 of penetration, then linearly "
          "(eps_N (|g| - g0 / 2)); a smooth onset for contacts that close many points at once (line contact, "
          "dense grids); 0: linear from the first touch [length]",
          core::nonNegative(), ">= 0");
    p.addChoice("Active Set", "Each Iteration", {"Each Iteration", "Between Solves"},
                "Each Iteration: a point acts while it penetrates, judged at every Newton iterate; Between "
                "Solves: the points that act are fixed for a Newton solve (their springs hold in tension too) "
                "and changed after it (penetrating points join, points in tension leave, and Newton solves "
                "again), as Lagrange multipliers' are: for many points closing at once on soft beams, where "
                "the active set changing within Newton's iterations makes it cycle");
    return p;
  }();
  return s;
}

PenaltyEnforcer::PenaltyEnforcer(const Teuchos::ParameterList& v)
    : choice_(v),
      regularization_(v.get<double>("Regularization Gap")),
      betweenSolves_(v.get<std::string>("Active Set") == "Between Solves") {
  if (betweenSolves_ && regularization_ > 0.0)
    throw core::InputError(
        "parameter \"Contact/Enforcement/Penalty/Regularization Gap\" smooths the onset of contact judged at every "
        "Newton iterate, and \"Contact/Enforcement/Penalty/Active Set\" is \"Between Solves\" (whose springs are "
        "linear and hold in tension while the solve lasts): give one of them");
}

std::unique_ptr<PointState> PenaltyEnforcer::newPointState() const {
  auto s = std::make_unique<State>();
  s->penalties.start(choice_);
  return s;
}

void PenaltyEnforcer::setCompliance(PointState& s, const double compliance[3]) const {
  choice_.choose(compliance, stateOf<State>(s).penalties.eps);
}

void PenaltyEnforcer::relaxTangential(PointState& s, const double compliance[3], int relaxations) const {
  choice_.choose(compliance, stateOf<State>(s).penalties.eps, relaxations);
}

PointResult PenaltyEnforcer::evaluate(const ContactPoint& p, const PointState& s, double* f, double* K) const {
  const State& h = stateOf<State>(s);
  h.penalties.require();
  const double* eps = choice_.at(h.penalties);
  const FrictionRegularization friction{{h.lambdaT[0], h.lambdaT[1]}, eps[1]};
  if (betweenSolves() && !h.engaged) return PointResult{};
  return regularizedEvaluate(p, normalLaw(eps[0]), friction, f, K, betweenSolves());
}

NormalLaw PenaltyEnforcer::normalLaw(double epsN) const {
  return betweenSolves() ? linearNormalLaw(0.0, epsN) : smoothedPenaltyLaw(epsN, regularization_);
}

bool PenaltyEnforcer::acceptNormal(const ContactPoint& p, PointState& s) const {
  if (!betweenSolves()) return true;
  State& h = stateOf<State>(s);
  // Joins where it penetrates, leaves where its spring is in tension (the gap open).
  return settleEngaged(h.engaged, p.kinematics.normal.value);
}

std::vector<double> PenaltyEnforcer::outputValues(const ContactPoint& p, const PointState& s) const {
  if (!contributes(p.kinematics.normal.value, s)) return {0.0, 0.0};
  return choice_.outputValues(stateOf<State>(s).penalties);
}

bool PenaltyEnforcer::acceptPoint(const ContactPoint& p, PointState&, double& worstViolation) const {
  worstViolation = std::max(worstViolation, std::max(0.0, -p.kinematics.normal.value));
  return true;
}

void PenaltyEnforcer::commitPoint(const ContactPoint& p, PointState& s) const {
  State& state = stateOf<State>(s);
  state.penalties.require();
  const double* eps = choice_.at(state.penalties);
  const FrictionRegularization friction{{state.lambdaT[0], state.lambdaT[1]}, eps[1]};
  const PointResult r = betweenSolves() && !state.engaged
                            ? PointResult{}
                            : regularizedForces(p, normalLaw(eps[0]), friction, betweenSolves());
  for (int i = 0; i < 2; ++i) state.lambdaT[i] = r.lambdaT[i];
}

}  // namespace bc::constraints
