#include "ConstraintEnforcer.hpp"

#include <cmath>
#include <vector>

namespace bc::constraints {

PointResult ConstraintEnforcer::reportedForces(const ContactPoint& p, const PointState& s) const {
  if (!contributes(p.kinematics.normal.value, s)) return PointResult{};
  std::vector<double> f(kPairDofs + multipliers(s), 0.0);
  return evaluate(p, s, f.data(), nullptr);
}

double tangentialRelaxationFactor(int relaxations) {
  double factor = 1.0;
  for (int k = 0; k < relaxations && std::isfinite(factor); ++k) factor *= 10.0;
  return factor;
}

void ConstraintEnforcer::relaxTangential(PointState& s, const double compliance[3], int relaxations) const {
  const double factor = tangentialRelaxationFactor(relaxations);
  const double c[3] = {compliance[0], factor * compliance[1], factor * compliance[2]};
  setCompliance(s, c);
}

}  // namespace bc::constraints
