// Run-time plug-ins: shared libraries that register enforcement strategies (or anything else with a
// registry) when loaded. A plug-in writes BEAMCONTACT_PLUGIN(...) (constraints/Plugin.hpp), which
// defines its registration function and records the BeamContact version it was built against, and is
// linked against the installed BeamContact libraries (find_package(BeamContact), target
// BeamContact::constraints).
//
// A plug-in runs code in this process, so it is loaded only when the user names it on the command
// line (`beamcontact run|check|study ... --plugin lib.so`). A deck's top-level "Plugins" (paths
// relative to the deck's folder) says which libraries the deck needs: each must also be given with
// --plugin, otherwise the deck is refused, before anything is loaded, with a line saying how to allow
// it. The path and SHA-256 of every loaded library go into effective_parameters.xml ("Plugins",
// "Plugin SHA-256") and status.txt; a deck that gives "Plugin SHA-256" is refused when a library's
// digest differs.
#pragma once
#include <string>
#include <vector>

#include <Teuchos_ParameterList.hpp>

namespace bc::input {

struct LoadedPlugin {
  std::string path;  // canonical
  std::string sha256;  // of the file's bytes when it was loaded
};

// Loads the library at `path` (once; later calls with the same file do nothing), checks the version
// it was built against, and calls its registration function. An InputError names the file and the
// cause (not found, not a shared library, undefined symbols, no entry point, another version, a name
// registered twice, anything thrown while registering).
void loadPlugin(const std::string& path);
// Checks the deck's "Plugins" against the libraries given with --plugin (`commandLine`), without
// loading anything, and writes them back as absolute paths with their digests ("Plugin SHA-256"), so
// a copy of the deck (a study case, effective_parameters.xml) names exactly what ran.
void checkDeckPlugins(Teuchos::ParameterList& deck, const std::string& deckPath,
                      const std::vector<std::string>& commandLine);
// The plug-ins loaded so far, in order.
const std::vector<LoadedPlugin>& loadedPlugins();

}  // namespace bc::input
