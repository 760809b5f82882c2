#include "Plugins.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <filesystem>

#include <Teuchos_Array.hpp>

#include "constraints/EnforcerRegistry.hpp"
#include "core/Faults.hpp"
#include "core/Parameters.hpp"
#include "core/Sha256.hpp"
#include "core/Version.hpp"

namespace bc::input {

namespace fs = std::filesystem;

namespace {
std::vector<LoadedPlugin>& loaded() {
  static std::vector<LoadedPlugin> l;
  return l;
}

std::string canonicalFile(const std::string& path, const std::string& what) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw core::InputError(what + " \"" + path + "\" does not exist (or is not a file)");
  return fs::canonical(path, ec).string();
}
}  // namespace

const std::vector<LoadedPlugin>& loadedPlugins() { return loaded(); }

void loadPlugin(const std::string& path) {
  const std::string absolute = canonicalFile(path, "plug-in");
  for (const auto& l : loaded())
    if (l.path == absolute) return;
  const std::string name = "plug-in \"" + path + "\"";
  std::string digest;
  try {
    digest = core::sha256File(absolute);
  } catch (const std::exception&) {
    throw core::InputError(name + " cannot be read");
  }
  void* handle = dlopen(absolute.c_str(), RTLD_NOW | RTLD_GLOBAL);
  if (!handle) {
    const char* why = dlerror();
    throw core::InputError(name + " cannot be loaded: " + (why ? why : "unknown reason"));
  }
  dlerror();
  void* version = dlsym(handle, "beamcontact_plugin_version");
  void* entry = dlsym(handle, "beamcontact_plugin_register");
  if (!entry)
    throw core::InputError(name +
                           " has no beamcontact_plugin_register() (write BEAMCONTACT_PLUGIN(...) in one of its files)");
  if (!version)
    throw core::InputError(name +
                           " does not record the BeamContact version it was built against; rebuild it against "
                           "BeamContact " +
                           core::kVersion);
  const std::string built = reinterpret_cast<const char* (*)()>(version)();
  if (built != core::kVersion)
    throw core::InputError(name + " was built against BeamContact " + built + "; this is BeamContact " +
                           core::kVersion + ": rebuild it");
  // Whatever the registration throws, of any type, is one input error naming the library.
  core::runForeignCode(name, "failed while registering", [&] {
    const constraints::RegistrationOrigin origin("plug-in \"" + absolute + "\"");
    reinterpret_cast<void (*)()>(entry)();
  });
  loaded().push_back({absolute, digest});
  std::string note = "loaded plug-ins:";
  for (const auto& l : loaded()) note += " " + l.path;
  core::setForeignCodeNote(note);
}

void checkDeckPlugins(Teuchos::ParameterList& deck, const std::string& deckPath,
                      const std::vector<std::string>& commandLine) {
  if (!deck.isParameter("Plugins")) {
    if (deck.isParameter("Plugin SHA-256"))
      throw core::InputError("parameter \"" + deck.name() + "/Plugin SHA-256\" is given without \"Plugins\"");
    return;
  }
  const std::string where = "parameter \"" + deck.name() + "/Plugins\"";
  if (!deck.isType<Teuchos::Array<std::string>>("Plugins"))
    throw core::InputError(where + " has type " + deck.getEntry("Plugins").getAny().typeName() +
                           ", expected Array(string)");
  Teuchos::Array<std::string> paths = deck.get<Teuchos::Array<std::string>>("Plugins");
  std::vector<std::string> allowed;
  for (const auto& c : commandLine) {
    std::error_code ec;
    const auto p = fs::canonical(c, ec);
    if (!ec) allowed.push_back(p.string());
  }
  const fs::path folder = fs::absolute(fs::path(deckPath)).parent_path();
  Teuchos::Array<std::string> digests(paths.size());
  for (int i = 0; i < static_cast<int>(paths.size()); ++i) {
    auto& p = paths[i];
    if (p.empty()) throw core::InputError(where + ": an empty plug-in path");
    const fs::path full = fs::path(p).is_absolute() ? fs::path(p) : folder / p;
    std::string absolute;
    try {
      absolute = canonicalFile(full.string(), "plug-in");
    } catch (const core::InputError& e) {
      throw core::InputError(where + ": " + e.what());
    }
    if (std::find(allowed.begin(), allowed.end(), absolute) == allowed.end())
      throw core::InputError("the deck asks to load the plug-in \"" + absolute + "\" (" + where +
                             "); a plug-in runs code, so it is loaded only when named on the command line too: add "
                             "--plugin " +
                             absolute);
    p = absolute;
    digests[i] = core::sha256File(absolute);
  }
  if (deck.isParameter("Plugin SHA-256")) {
    const std::string dwhere = "parameter \"" + deck.name() + "/Plugin SHA-256\"";
    if (!deck.isType<Teuchos::Array<std::string>>("Plugin SHA-256"))
      throw core::InputError(dwhere + " has type " + deck.getEntry("Plugin SHA-256").getAny().typeName() +
                             ", expected Array(string)");
    const auto given = deck.get<Teuchos::Array<std::string>>("Plugin SHA-256");
    if (given.size() != paths.size())
      throw core::InputError(dwhere + " has " + std::to_string(given.size()) + " digests for " +
                             std::to_string(paths.size()) + " plug-ins");
    for (int i = 0; i < static_cast<int>(paths.size()); ++i)
      if (given[i] != digests[i])
        throw core::InputError("plug-in \"" + paths[i] + "\" has SHA-256 " + digests[i] + ", not the " + given[i] +
                               " that " + dwhere + " records: the library changed");
  }
  deck.set("Plugins", paths, deck.getEntry("Plugins").docString());
  deck.set("Plugin SHA-256", digests,
           "SHA-256 of each of Plugins' libraries (written by beamcontact; a deck that "
           "gives it is refused when a library differs)");
}

}  // namespace bc::input
