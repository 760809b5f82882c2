#include "PenaltyChoice.hpp"

#include <stdexcept>

namespace bc::constraints {

namespace {
std::string openUnitInterval(const Teuchos::ParameterEntry& e) {
  const double v = Teuchos::any_cast<double>(e.getAny());
  return v > 0.0 && v < 1.0 ? "" : "must be in (0, 1)";
}
}  // namespace

void PenaltyChoice::addTo(core::ParameterSpec& spec, const std::string& role) {
  spec.addRequired("Normal Penalty Parameter", 1e4,
                   "eps_N: " + role +
                       " of the normal contact spring [force/length]; \"Automatic\": chosen per "
                       "contact point from the beams' compliance there and Normal Target Error",
                   core::positive(), "> 0");
  spec.allowWord("Normal Penalty Parameter", kAutomatic);
  spec.addRequired("Tangential Penalty Parameter", 1e3,
                   "eps_T: " + role +
                       " of the tangential (stick) spring [force/length]; \"Automatic\": chosen per "
                       "contact point from the beams' compliance there and Tangential Target Error",
                   core::positive(), "> 0");
  spec.allowWord("Tangential Penalty Parameter", kAutomatic);
  spec.add("Normal Target Error", 1e-3,
           "with an Automatic Normal Penalty Parameter: the relative error e of a contact force (and of the "
           "displacement it causes) that eps_N = (1 - e) / (e c_N) gives at one contact point, c_N the "
           "beams' compliance along the gap's gradient [-]",
           openUnitInterval, "in (0, 1)");
  spec.add("Tangential Target Error", 1e-2,
           "with an Automatic Tangential Penalty Parameter: the relative error of a sticking friction force, "
           "eps_T = (1 - e) / (e c_T) with c_T the smaller compliance along the two slips [-]",
           openUnitInterval, "in (0, 1)");
}

PenaltyChoice::PenaltyChoice(const Teuchos::ParameterList& v) {
  const char* names[2] = {"Normal Penalty Parameter", "Tangential Penalty Parameter"};
  const char* targets[2] = {"Normal Target Error", "Tangential Target Error"};
  for (int i = 0; i < 2; ++i) {
    automatic_[i] = core::ParameterSpec::isWord(v, names[i], kAutomatic);
    if (!automatic_[i]) given_[i] = v.get<double>(names[i]);
    target_[i] = v.get<double>(targets[i]);
  }
}

void PenaltyChoice::choose(const double compliance[3], double eps[2], int relaxations) const {
  const double factor = tangentialRelaxationFactor(relaxations);
  const double c[3] = {compliance[0], factor * compliance[1], factor * compliance[2]};
  // Tangential: the stiffer slip direction (smaller compliance) that is measured at all.
  double cT = 0.0;
  for (int i : {1, 2})
    if (c[i] > 0.0 && (cT == 0.0 || c[i] < cT)) cT = c[i];
  const double cs[2] = {c[0], cT > 0.0 ? cT : c[0]};
  for (int i = 0; i < 2; ++i) {
    if (!automatic_[i]) {
      eps[i] = given_[i];
      continue;
    }
    if (!(cs[i] > 0.0))
      throw std::runtime_error(
          "automatic penalty parameters: the beams do not give at a contact point (zero "
          "compliance: both beams held there); give the penalty parameters");
    eps[i] = (1.0 - target_[i]) / (target_[i] * cs[i]);
  }
}

std::vector<double> PenaltyChoice::outputValues(const PointPenalties& point) const {
  const double* eps = at(point);
  return {eps[0], eps[1]};
}

void PointPenalties::require() const {
  if (waiting())
    throw std::logic_error(
        "a contact point with automatic penalty parameters was evaluated before the "
        "structure's compliance was known (run it through the static solver)");
}

}  // namespace bc::constraints
