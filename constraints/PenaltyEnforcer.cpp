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
    p.addChoice("Line Springs", "Gauss Points", {"Gauss Points", "Nodes"},
                "where line contact's springs act: Gauss Points: a spring at every Gauss point of the line "
                "(Contact/Line Gauss Points per element); Nodes: a spring per node of beam A on the gap weighted "
                "over the node's elements (Lagrange Multiplier's field, with a multiplier row per node regularized "
                "by 1 / eps_N): for beams lying on each other along elements longer than the penalty's bending "
                "wavelength (4 E I / eps_N)^(1/4), where springs at every Gauss point over-constrain them and the "
                "active set cycles; the lines' friction is then springs eps_T on the nodes' weighted slips "
                "(Isotropic Coulomb only)");
    return p;
  }();
  return s;
}

namespace {
// The line nodes' Lagrange rows (Line Springs = Nodes): Lagrange's defaults, with Penalty's passes.
Teuchos::ParameterList fieldParameters(int passes) {
  Teuchos::ParameterList l = LagrangeMultiplierEnforcer::spec().reference();
  l.set("Maximum Active Set Iterations", passes);
  return l;
}
}  // namespace

PenaltyEnforcer::PenaltyEnforcer(const Teuchos::ParameterList& v)
    : choice_(v),
      regularization_(v.get<double>("Regularization Gap")),
      betweenSolves_(v.get<std::string>("Active Set") == "Between Solves"),
      nodal_(v.get<std::string>("Line Springs") == "Nodes"),
      field_(fieldParameters(kPassesBetweenSolves)) {
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

std::unique_ptr<PointState> PenaltyEnforcer::newLineNodeState() const {
  auto s = std::make_unique<State>();
  s->lineNode = true;
  return s;
}

int PenaltyEnforcer::multipliers(const PointState& s) const {
  const State& h = stateOf<State>(s);
  return h.lineNode ? field_.multipliers(h.field) : 0;
}

LagrangeMultiplierEnforcer::Compliance PenaltyEnforcer::lineCompliance(const ContactPoint& p, const State& h) const {
  LagrangeMultiplierEnforcer::Compliance c;
  const double epsN = lineEpsN(p);
  // (Automatic: eps_T as the line's eps_N, the Normal Target Error on the same field mode.)
  const double epsT = choice_.automatic() ? epsN : choice_.given()[1];
  c.normal = epsN > 0.0 ? 1.0 / epsN : 0.0;
  c.tangential = epsT > 0.0 ? 1.0 / epsT : 0.0;
  for (int i = 0; i < 2; ++i) c.committedT[i] = h.committedT[i];
  return c;
}

double PenaltyEnforcer::lineEpsN(const ContactPoint& p) const {
  if (!choice_.automatic()) return choice_.given()[0];
  const double e = choice_.target(0);
  return p.fieldCompliance > 0.0 ? (1.0 - e) / (e * p.fieldCompliance) : 0.0;
}

bool PenaltyEnforcer::contributes(double gapN, const PointState& s) const {
  const State& h = stateOf<State>(s);
  if (h.lineNode) return field_.contributes(gapN, h.field);
  return betweenSolves() ? h.engaged : gapN <= 0.0;
}

double PenaltyEnforcer::activationGap(const PointState& s) const {
  const State& h = stateOf<State>(s);
  if (h.lineNode) return field_.activationGap(h.field);
  return betweenSolves() ? ConstraintEnforcer::activationGap(s) : 0.0;
}

PointResult PenaltyEnforcer::reportedForces(const ContactPoint& p, const PointState& s) const {
  const State& h = stateOf<State>(s);
  if (h.lineNode) return field_.reportedForces(p, h.field);
  return ConstraintEnforcer::reportedForces(p, s);
}

void PenaltyEnforcer::setCompliance(PointState& s, const double compliance[3]) const {
  choice_.choose(compliance, stateOf<State>(s).penalties.eps);
}

void PenaltyEnforcer::relaxTangential(PointState& s, const double compliance[3], int relaxations) const {
  choice_.choose(compliance, stateOf<State>(s).penalties.eps, relaxations);
}

PointResult PenaltyEnforcer::evaluate(const ContactPoint& p, const PointState& s, double* f, double* K) const {
  const State& h = stateOf<State>(s);
  // A Gauss point of a line, acting through its field nodes' multipliers: Lagrange's rows with the
  // springs' compliances in them.
  if (h.lineNode) return field_.evaluate(p, h.field, f, K, lineCompliance(p, h));
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
  State& h = stateOf<State>(s);
  if (h.lineNode) return field_.acceptNormal(p, h.field);
  if (!betweenSolves()) return true;
  // Joins where it penetrates, leaves where its spring is in tension (the gap open).
  return settleEngaged(h.engaged, p.kinematics.normal.value);
}

std::vector<double> PenaltyEnforcer::outputValues(const ContactPoint& p, const PointState& s) const {
  if (stateOf<State>(s).lineNode) return {lineEpsN(p), 0.0};
  if (!contributes(p.kinematics.normal.value, s)) return {0.0, 0.0};
  return choice_.outputValues(stateOf<State>(s).penalties);
}

bool PenaltyEnforcer::acceptPoint(const ContactPoint& p, PointState& s, double& worstViolation) const {
  State& h = stateOf<State>(s);
  if (h.lineNode) {
    // The field's stick/slip; the node's penetration (its spring's, not a violation to meet).
    double violation = 0.0;
    const bool settled = field_.acceptPoint(p, h.field, violation);
    worstViolation = std::max(worstViolation, std::max(0.0, -p.kinematics.normal.value));
    return settled;
  }
  worstViolation = std::max(worstViolation, std::max(0.0, -p.kinematics.normal.value));
  return true;
}

void PenaltyEnforcer::commitPoint(const ContactPoint& p, PointState& s) const {
  State& state = stateOf<State>(s);
  if (state.lineNode) {
    // (A released node's friction springs start again from 0.)
    for (int i = 0; i < 2; ++i) state.committedT[i] = state.field.active && p.lambda ? p.lambda[1 + i] : 0.0;
    return;
  }
  state.penalties.require();
  const double* eps = choice_.at(state.penalties);
  const FrictionRegularization friction{{state.lambdaT[0], state.lambdaT[1]}, eps[1]};
  const PointResult r = betweenSolves() && !state.engaged
                            ? PointResult{}
                            : regularizedForces(p, normalLaw(eps[0]), friction, betweenSolves());
  for (int i = 0; i < 2; ++i) state.lambdaT[i] = r.lambdaT[i];
}

}  // namespace bc::constraints
