#include "Plugins.hpp"

#include <dlfcn.h>

#include <filesystem>

#include <Teuchos_Array.hpp>

#include "core/Parameters.hpp"

namespace bc::input {

namespace fs = std::filesystem;

namespace {
std::vector<std::string>& loaded() {
  static std::vector<std::string> l;
  return l;
}
}  // namespace

const std::vector<std::string>& loadedPlugins() { return loaded(); }

void loadPlugin(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw core::InputError("plug-in \"" + path + "\" does not exist (or is not a file)");
  const std::string absolute = fs::canonical(path, ec).string();
  for (const auto& l : loaded())
    if (l == absolute) return;
  void* handle = dlopen(absolute.c_str(), RTLD_NOW | RTLD_GLOBAL);
  if (!handle) {
    const char* why = dlerror();
    throw core::InputError("plug-in \"" + path + "\" cannot be loaded: " + (why ? why : "unknown reason"));
  }
  dlerror();
  void* symbol = dlsym(handle, "beamcontact_plugin_register");
  if (!symbol)
    throw core::InputError("plug-in \"" + path +
                           "\" has no beamcontact_plugin_register() (write BEAMCONTACT_PLUGIN(...) in one of its files)");
  reinterpret_cast<void (*)()>(symbol)();
  loaded().push_back(absolute);
}

void loadDeckPlugins(Teuchos::ParameterList& deck, const std::string& deckPath) {
  if (!deck.isParameter("Plugins")) return;
  const std::string where = "parameter \"" + deck.name() + "/Plugins\"";
  if (!deck.isType<Teuchos::Array<std::string>>("Plugins"))
    throw core::InputError(where + " has type " + deck.getEntry("Plugins").getAny().typeName() +
                           ", expected Array(string)");
  Teuchos::Array<std::string> paths = deck.get<Teuchos::Array<std::string>>("Plugins");
  const fs::path folder = fs::absolute(fs::path(deckPath)).parent_path();
  for (auto& p : paths) {
    if (p.empty()) throw core::InputError(where + ": an empty plug-in path");
    const fs::path full = fs::path(p).is_absolute() ? fs::path(p) : folder / p;
    try {
      loadPlugin(full.string());
    } catch (const core::InputError& e) {
      throw core::InputError(where + ": " + e.what());
    }
    p = fs::canonical(full).string();
  }
  deck.set("Plugins", paths, deck.getEntry("Plugins").docString());
}

}  // namespace bc::input
