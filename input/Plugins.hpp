// Run-time plug-ins: shared libraries that register enforcement strategies (or anything else with a
// registry) when loaded. A plug-in defines
//   extern "C" void beamcontact_plugin_register() { bc::constraints::registerEnforcer<MyStrategy>(); }
// (BEAMCONTACT_PLUGIN in constraints/Plugin.hpp writes it) and is linked against the installed
// BeamContact libraries (find_package(BeamContact), target BeamContact::constraints). It is named on
// the command line (`beamcontact run|check|study ... --plugin lib.so`) or in the deck's top-level
// "Plugins" (Array(string), paths relative to the deck's folder).
#pragma once
#include <string>
#include <vector>

#include <Teuchos_ParameterList.hpp>

namespace bc::input {

// Loads the library at `path` (once; later calls with the same file do nothing) and calls its
// registration function. An InputError names the file and the cause (not found, not a shared
// library, undefined symbols, no beamcontact_plugin_register).
void loadPlugin(const std::string& path);
// Loads the deck's "Plugins" (relative paths taken from the folder of `deckPath`) and writes them
// back as absolute paths, so a copy of the deck (a study case, effective_parameters.xml) finds them.
void loadDeckPlugins(Teuchos::ParameterList& deck, const std::string& deckPath);
// The plug-ins loaded so far (absolute paths), in order.
const std::vector<std::string>& loadedPlugins();

}  // namespace bc::input
