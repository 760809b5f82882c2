// Every registered enforcement strategy (iterated from the registry, no names here): it constructs
// from its parameter specification (defaults, and the documented example of each required value), it
// acts on a penetrating point, and its tangent matches central differences of its residual for both
// friction laws, frictionless, slipping and sticking (StrategyCheck.hpp). No Tpetra, no MPI.
#include <gtest/gtest.h>

#include <cstdio>

#include "constraints/EnforcerRegistry.hpp"
#include "constraints/StrategyCheck.hpp"

using namespace bc;

TEST(Strategies, EveryRegisteredStrategyHasATangentMatchingCentralDifferences) {
  constraints::registerBuiltinEnforcers();
  ASSERT_GE(constraints::enforcers().size(), 3u);
  for (const auto& entry : constraints::enforcers()) {
    Teuchos::ParameterList params = entry.spec->example();
    entry.spec->apply(params, entry.name);  // the example list is a valid one
    const auto strategy = entry.create(params);
    EXPECT_EQ(strategy->type(), entry.name);
    int slipping = 0, sticking = 0;
    for (const auto& c : constraints::checkTangent(*strategy)) {
      std::printf(
          "%-20s %-28s size %2d, slipping lines %d: max |K| %.3e, max |K - central differences| / max |K| = %.2e\n",
          entry.name.c_str(), c.situation.c_str(), c.size, c.slipping, c.maxEntry, c.relativeError());
      EXPECT_TRUE(c.acts) << entry.name << ", " << c.situation << ": does not act on a penetrating point";
      EXPECT_GT(c.maxEntry, 0.0) << entry.name << ", " << c.situation;
      EXPECT_LT(c.relativeError(), 1e-6) << entry.name << ", " << c.situation;
      if (c.situation.find("mu = 0.01") != std::string::npos) slipping += c.slipping;
      if (c.situation.find("mu = 50") != std::string::npos) sticking += 2 - c.slipping;
    }
    // The situations reach both branches of the return mapping.
    EXPECT_GT(slipping, 0) << entry.name;
    EXPECT_GT(sticking, 0) << entry.name;
  }
}
