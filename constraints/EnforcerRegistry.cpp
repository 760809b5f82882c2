#include "EnforcerRegistry.hpp"

#include "AugmentedLagrangeEnforcer.hpp"
#include "LagrangeMultiplierEnforcer.hpp"
#include "PenaltyEnforcer.hpp"

namespace bc::constraints {

namespace {
std::vector<EnforcerEntry>& registry() {
  static std::vector<EnforcerEntry> r;
  return r;
}
}  // namespace

void registerEnforcer(EnforcerEntry entry) {
  for (auto& e : registry())
    if (e.name == entry.name) {
      e = std::move(entry);
      return;
    }
  registry().push_back(std::move(entry));
}

void registerBuiltinEnforcers() {
  registerEnforcer<PenaltyEnforcer>();
  registerEnforcer<LagrangeMultiplierEnforcer>();
  registerEnforcer<AugmentedLagrangeEnforcer>();
}

const std::vector<EnforcerEntry>& enforcers() { return registry(); }

std::vector<std::string> enforcerNames() {
  std::vector<std::string> names;
  for (const auto& e : registry()) names.push_back(e.name);
  return names;
}

const EnforcerEntry& findEnforcer(const std::string& name, const std::string& path) {
  for (const auto& e : registry())
    if (e.name == name) return e;
  throw core::InputError("parameter \"" + path + "\": unknown enforcement strategy \"" + name +
                         "\"; valid strategies are " + core::joinNames(enforcerNames()));
}

}  // namespace bc::constraints
