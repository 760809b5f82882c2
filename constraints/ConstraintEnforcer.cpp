#include "ConstraintEnforcer.hpp"

#include <vector>

namespace bc::constraints {

PointResult ConstraintEnforcer::reportedForces(const ContactPoint& p, const PointState& s) const {
  if (!contributes(p.kinematics.normal.value, s)) return PointResult{};
  std::vector<double> f(kPairDofs + multipliers(s), 0.0);
  return evaluate(p, s, f.data(), nullptr);
}

}  // namespace bc::constraints
