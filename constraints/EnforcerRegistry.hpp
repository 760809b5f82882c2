// The one list of enforcement strategies. The deck's "Contact/Enforcement" sublist (its Type choices,
// the validation of each strategy's own sublist, the "unknown strategy" error) and its reference in
// `beamcontact --print-valid-parameters` all come from here.
//
// A built-in strategy is one file pair in constraints/ (picked up by CMake without editing it) plus
// one line in registerBuiltinEnforcers(). A strategy elsewhere calls registerEnforcer<T>() from a
// program, a test, or a plug-in library's entry point (Plugins.hpp).
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
  std::string description;  // one line for the reference
  const core::ParameterSpec* spec = nullptr;  // parameters of the strategy's sublist
  std::function<std::unique_ptr<ConstraintEnforcer>(const Teuchos::ParameterList&)> create;
  std::string origin;  // who registered it: "built-in", "plug-in \"<path>\"" or "the program" (set by registerEnforcer)
};

// While one lives, strategies are registered as coming from `origin` (the plug-in loader sets it).
class RegistrationOrigin {
 public:
  explicit RegistrationOrigin(std::string origin);
  ~RegistrationOrigin();
  RegistrationOrigin(const RegistrationOrigin&) = delete;
  RegistrationOrigin& operator=(const RegistrationOrigin&) = delete;

 private:
  std::string previous_;
};

// Adds a strategy. A name that is registered already (built-in or by a plug-in) is an InputError
// naming both origins: nothing replaces a strategy silently.
void registerEnforcer(EnforcerEntry entry);
// T has static name(), description() and spec(), and a constructor from its validated sublist.
template <class T> void registerEnforcer() {
  registerEnforcer({T::name(),
                    T::description(),
                    &T::spec(),
                    [](const Teuchos::ParameterList& p) { return std::make_unique<T>(p); },
                    {}});
}
// Registers the built-in strategies: Penalty, Lagrange Multiplier, Augmented Lagrange (once; later
// calls do nothing).
void registerBuiltinEnforcers();
const std::vector<EnforcerEntry>& enforcers();
std::vector<std::string> enforcerNames();
// The strategy named `name`; an input error naming `path` and the valid names if there is none.
const EnforcerEntry& findEnforcer(const std::string& name, const std::string& path);

// The strategy a deck's Enforcement sublist `e` (at `path`) chooses, checked and constructed in one
// call. Type is required; the chosen strategy's sublist is created when absent (so its defaults apply
// and each missing required value is named) and filled in with its defaults; the sublists of other
// registered strategies may stay (switching Type is one edit) and are validated too. Anything a
// plug-in's constructor throws, of any type, becomes an InputError naming the strategy and its plug-in.
std::unique_ptr<ConstraintEnforcer> enforcerFromDeck(Teuchos::ParameterList& e, const std::string& path);
// The documented reference of the Enforcement sublist.
Teuchos::ParameterList enforcementReference();

}  // namespace bc::constraints
