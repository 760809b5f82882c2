// The one list of enforcement strategies. The deck's "Enforcement/Type" choices, the validation of
// each strategy's own sublist (named like the strategy) and the "unknown type" error all come from
// here. A new strategy is one file pair (a ConstraintEnforcer with a static spec()) plus one line in
// registerBuiltinEnforcers(), or a call to registerEnforcer() from a program or test.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "ConstraintEnforcer.hpp"
#include "core/Parameters.hpp"

namespace bc::constraints {

struct EnforcerEntry {
  std::string name;
  const core::ParameterSpec* spec = nullptr;  // parameters of the strategy's sublist
  std::function<std::unique_ptr<ConstraintEnforcer>(const Teuchos::ParameterList&)> create;
};

void registerEnforcer(EnforcerEntry entry);
// Registers the built-in strategies: Penalty, Lagrange Multiplier, Augmented Lagrange (idempotent).
void registerBuiltinEnforcers();
const std::vector<EnforcerEntry>& enforcers();
std::vector<std::string> enforcerNames();
const EnforcerEntry& findEnforcer(const std::string& name, const std::string& path);

template <class T> void registerEnforcer() {
  registerEnforcer({T::name(), &T::spec(), [](const Teuchos::ParameterList& p) { return std::make_unique<T>(p); }});
}

}  // namespace bc::constraints
