// The quadratic penalty's tangent against central differences of its residual, with BeamContact's
// own check (the same one every built-in strategy passes). Exit 0 when every situation agrees to 1e-6.
#include <cstdio>

#include <constraints/StrategyCheck.hpp>

#include "QuadraticPenalty.hpp"

int main() {
  const quadratic::QuadraticPenalty strategy(quadratic::QuadraticPenalty::spec().example());
  int bad = 0;
  for (const auto& c : bc::constraints::checkTangent(strategy)) {
    std::printf("%-28s slipping lines %d: max |K| %.3e, max |K - central differences| / max |K| = %.2e\n",
                c.situation.c_str(), c.slipping, c.maxEntry, c.relativeError());
    if (!c.acts || !(c.maxEntry > 0.0) || !(c.relativeError() < 1e-6)) ++bad;
  }
  return bad == 0 ? 0 : 1;
}
