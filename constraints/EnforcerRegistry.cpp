#include "EnforcerRegistry.hpp"

#include "AugmentedLagrangeEnforcer.hpp"
#include "core/Faults.hpp"
#include "LagrangeMultiplierEnforcer.hpp"
#include "PenaltyEnforcer.hpp"

namespace bc::constraints {

namespace {
std::vector<EnforcerEntry>& registry() {
  static std::vector<EnforcerEntry> r;
  return r;
}
std::string& currentOrigin() {
  static std::string origin = "the program";
  return origin;
}
}  // namespace

RegistrationOrigin::RegistrationOrigin(std::string origin) : previous_(std::move(origin)) {
  std::swap(previous_, currentOrigin());
}
RegistrationOrigin::~RegistrationOrigin() { std::swap(previous_, currentOrigin()); }

void registerEnforcer(EnforcerEntry entry) {
  entry.origin = currentOrigin();
  for (const auto& e : registry())
    if (e.name == entry.name)
      throw core::InputError("the strategy name \"" + entry.name + "\" is registered twice: by " + e.origin +
                             " and by " + entry.origin + "; a strategy of your own needs a name of its own");
  registry().push_back(std::move(entry));
}

void registerBuiltinEnforcers() {
  static bool done = false;
  if (done) return;
  done = true;
  const RegistrationOrigin origin("built-in");
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

namespace {
core::ParameterSpec enforcementSpec() {
  core::ParameterSpec spec;
  spec.addRequired("Type", std::string("Penalty"),
                   "the enforcement strategy; its parameters go in the sublist of "
                   "the same name",
                   {}, "one of " + core::joinNames(enforcerNames()));
  for (const auto& entry : registry())
    spec.addSublist(entry.name, entry.spec->reference(),
                    "used when Type is \"" + entry.name + "\": " + entry.description);
  return spec;
}
}  // namespace

std::unique_ptr<ConstraintEnforcer> enforcerFromDeck(Teuchos::ParameterList& e, const std::string& path) {
  if (!e.isParameter("Type"))
    throw core::InputError("missing required parameter \"" + path + "/Type\"; valid strategies are " +
                           core::joinNames(enforcerNames()));
  if (!e.isType<std::string>("Type"))
    throw core::InputError("parameter \"" + path + "/Type\" has type " + e.getEntry("Type").getAny().typeName() +
                           ", expected string");
  const EnforcerEntry& chosen = findEnforcer(e.get<std::string>("Type"), path + "/Type");
  enforcementSpec().apply(e, path);
  e.sublist(chosen.name);
  for (const auto& other : registry())
    if (e.isSublist(other.name)) other.spec->apply(e.sublist(other.name), path + "/" + other.name);
  const Teuchos::ParameterList& own = e.sublist(chosen.name);
  if (chosen.origin == "built-in") return chosen.create(own);
  std::unique_ptr<ConstraintEnforcer> enforcer;
  core::runForeignCode("strategy \"" + chosen.name + "\" (" + chosen.origin + ")", "failed to start",
                       [&] { enforcer = chosen.create(own); });
  return enforcer;
}

Teuchos::ParameterList enforcementReference() { return enforcementSpec().reference(); }

}  // namespace bc::constraints
