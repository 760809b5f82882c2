// Checks a strategy's tangent against central differences of its own residual, without Tpetra or
// MPI: for each friction law and for mu = 0 (frictionless), 0.01 (slip) and 50 (stick), a crossing of
// two beams' edge lines (their chords, and their Hermite curves with the nodes turned so that the
// curves bend) that penetrate and have slid since the last step is activated through the
// strategy's acceptNormal/acceptPoint, given multipliers if it owns any, and its K is compared column
// by column with (f(u + h e_j) - f(u - h e_j)) / 2h over the 24 nodal dofs (translations, and spin
// increments applied as R <- exp(h e_k) R) and its multipliers. A researcher's strategy is checked
// the same way as the built-ins (tests/unit/test_strategies.cpp, examples/external-strategy).
#pragma once
#include <string>
#include <vector>

#include "ConstraintEnforcer.hpp"

namespace bc::constraints {

struct TangentCheck {
  std::string situation;  // friction law and coefficient, chords or Hermite axes
  bool acts = false;  // the strategy acts on the penetrating point
  int size = 0;  // 24 + multipliers
  int slipping = 0;  // lines reported slipping
  double maxEntry = 0.0;  // max |K|
  double maxError = 0.0;  // max |K - central differences|
  double relativeError() const { return maxEntry > 0.0 ? maxError / maxEntry : maxError; }
};

std::vector<TangentCheck> checkTangent(const ConstraintEnforcer& strategy);

}  // namespace bc::constraints
