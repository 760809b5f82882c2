#include "OutputDirectory.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <optional>
#include <vector>

#include "Faults.hpp"
#include "Parameters.hpp"
#include "Version.hpp"

namespace bc::core {

namespace fs = std::filesystem;

namespace {

const std::string kHeader =
    "# beamcontact-manifest 1: what beamcontact wrote in this folder (a rerun removes only these)";

// The names a folder's manifest lists, or nothing when it has no manifest (or one that is not ours).
std::optional<std::set<std::string>> readManifest(const fs::path& dir) {
  std::error_code ec;
  const fs::path file = dir / kManifestName;
  if (!fs::is_regular_file(fs::symlink_status(file, ec))) return std::nullopt;
  std::ifstream in(file);
  std::string line;
  if (!std::getline(in, line) || line != kHeader) return std::nullopt;
  std::set<std::string> names;
  while (std::getline(in, line))
    if (!line.empty() && line[0] != '#') names.insert(line);
  return names;
}

// Entries of a folder in name order (so the foreign file named is the same on every run).
std::vector<fs::directory_entry> entries(const fs::path& dir) {
  std::vector<fs::directory_entry> all;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) all.push_back(*it);
  std::sort(all.begin(), all.end(),
            [](const auto& a, const auto& b) { return a.path().filename() < b.path().filename(); });
  return all;
}

bool isRealDirectory(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(fs::symlink_status(p, ec));
}

// Whether every folder on the way from `base` to `relative` is a real folder below it (no link, no "..").
bool throughRealFolders(const fs::path& base, const std::string& relative) {
  fs::path at = base;
  const fs::path rel(relative);
  for (auto it = rel.begin(); it != rel.end(); ++it) {
    if (std::next(it) == rel.end()) break;
    if (*it == ".." || it->is_absolute()) return false;
    at /= *it;
    if (!isRealDirectory(at)) return false;
  }
  return true;
}

std::string firstForeign(const fs::path& dir, const std::set<std::string>& names, const std::string& prefix) {
  for (const auto& e : entries(dir)) {
    const std::string name = e.path().filename().string();
    if (prefix.empty() && name == kManifestName) continue;
    const std::string rel = prefix + name;
    if (isRealDirectory(e.path())) {
      if (!names.count(rel + "/")) return rel + "/";
      // A folder with a manifest of its own is checked by it, else by this one's names.
      const auto own = readManifest(e.path());
      const std::string inner = own ? firstForeign(e.path(), *own, "") : firstForeign(e.path(), names, rel + "/");
      if (!inner.empty()) return own ? rel + "/" + inner : inner;
      continue;
    }
    if (names.count(rel)) continue;
    return rel;
  }
  return "";
}

void appendLine(const fs::path& file, const std::string& line) {
  errno = 0;
  const int fd = ::open(file.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
  const std::string text = line + "\n";
  if (fd < 0 || ::write(fd, text.data(), text.size()) != static_cast<ssize_t>(text.size()) || ::close(fd) != 0) {
    const std::string reason = systemReason();
    throw OutputError("cannot write " + file.string() + ": " + reason, reason);
  }
}

}  // namespace

void checkDeckOutputPath(const std::string& path, const std::string& parameter) {
  const fs::path p(path);
  if (p.is_absolute())
    throw InputError("parameter \"" + parameter + "\" is the absolute path \"" + path +
                     "\"; a deck's output path is relative to the folder it is run from (give an absolute path "
                     "with --output)");
  for (const auto& part : p)
    if (part == "..")
      throw InputError("parameter \"" + parameter + "\" (\"" + path +
                       "\") climbs out with \"..\"; a deck's output path stays below the folder it is run from "
                       "(give such a path with --output)");
  fs::path prefix;
  for (const auto& part : p) {
    if (part.empty() || part == ".") continue;
    prefix /= part;
    std::error_code ec;
    const auto status = fs::symlink_status(prefix, ec);
    if (fs::is_symlink(status))
      throw InputError("parameter \"" + parameter + "\" (\"" + path + "\") passes through the symbolic link \"" +
                       prefix.string() +
                       "\"; a deck's output is not written through links (give the linked "
                       "folder with --output)");
    if (!fs::exists(status)) break;
  }
}

OutputDirectory::OutputDirectory(const fs::path& dir, const Options& options) : dir_(dir) {
  const std::string shown = "\"" + dir.string() + "\"";
  if (options.pathFromDeck) checkDeckOutputPath(dir.string(), options.parameter);
  std::error_code ec;
  const auto linkStatus = fs::symlink_status(dir, ec);
  if (!fs::exists(linkStatus)) {
    fs::create_directories(dir, ec);
    if (ec) throw InputError("cannot create the " + options.what + " " + shown + ": " + ec.message());
  } else if (!fs::is_directory(fs::status(dir, ec))) {
    throw InputError("cannot create the " + options.what + " " + shown + ": a file of that name exists");
  }
  if (access(dir.c_str(), W_OK | X_OK) != 0)
    throw InputError("cannot create the " + options.what + " " + shown + " here: " + systemReason());
  const auto listed = readManifest(dir);
  const std::string foreign = firstForeign(dir, listed ? *listed : std::set<std::string>{}, "");
  if (!foreign.empty() && !options.overwrite)
    throw InputError(options.what + " " + shown + " holds \"" + foreign +
                     "\", which beamcontact did not write; choose another directory, or pass --overwrite to "
                     "write beside it (beamcontact then replaces only its own files)");
  if (listed) {
    names_ = *listed;
  } else {
    const fs::path file = dir / kManifestName;
    if (fs::is_symlink(fs::symlink_status(file, ec)))
      throw InputError(options.what + " " + shown + " holds " + kManifestName + " as a symbolic link");
    writeFileAtomically(file, kHeader + "\n# version " + kVersion + "\n");
  }
}

void OutputDirectory::add(const std::string& relative) {
  if (names_.count(relative)) return;
  // Something of the user's under one of the program's names (allowed to stay by --overwrite) would
  // be replaced: refused, naming it.
  std::error_code ec;
  const bool folder = !relative.empty() && relative.back() == '/';
  if (!folder && fs::exists(fs::symlink_status(dir_ / relative, ec)))
    throw InputError("\"" + (dir_ / relative).string() +
                     "\" was not written by beamcontact (its manifest does not name it), and this run would "
                     "replace it: move or rename it, or choose another directory");
  adopt(relative);
}

void OutputDirectory::adopt(const std::string& relative) {
  if (names_.count(relative)) return;
  // A file is written through "<name>.tmp" and a rename (Faults.hpp): both names are the program's.
  const bool folder = !relative.empty() && relative.back() == '/';
  appendLine(dir_ / kManifestName, folder ? relative : relative + "\n" + relative + ".tmp");
  names_.insert(relative);
  if (!folder) names_.insert(relative + ".tmp");
}

fs::path OutputDirectory::folder(const std::string& relative) {
  // Without the trailing '/', which would make the status below follow a link.
  const std::string name =
      !relative.empty() && relative.back() == '/' ? relative.substr(0, relative.size() - 1) : relative;
  const fs::path p = dir_ / name;
  std::error_code ec;
  const auto status = fs::symlink_status(p, ec);
  if (fs::is_symlink(status) || (fs::exists(status) && !fs::is_directory(status)))
    throw InputError("\"" + p.string() + "\" is " + (fs::is_symlink(status) ? "a symbolic link" : "not a folder") +
                     "; beamcontact writes its " + name + "/ only into a folder of its own (remove or rename it)");
  add(name + "/");
  fs::create_directories(p, ec);
  if (ec) throw InputError("cannot create " + p.string() + ": " + ec.message());
  return p;
}

void OutputDirectory::removeOwn(const std::function<bool(const std::string&)>& which) {
  std::error_code ec;
  for (const auto& name : names_) {
    if (name.empty() || name.back() == '/' || !which(name) || !throughRealFolders(dir_, name)) continue;
    const fs::path p = dir_ / name;
    if (!isRealDirectory(p)) fs::remove(p, ec);
  }
}

void OutputDirectory::removeLeftovers() {
  removeOwn([](const std::string& name) { return name.size() > 4 && name.compare(name.size() - 4, 4, ".tmp") == 0; });
}

bool OutputDirectory::removeOwnFolder(const std::string& relative) {
  const fs::path sub = dir_ / relative;
  if (!isRealDirectory(sub)) return true;
  const auto inner = readManifest(sub);
  std::error_code ec;
  if (inner) {
    // Files first, then the listed folders deepest first, then the manifest and the folder itself.
    std::vector<std::string> folders;
    for (const auto& name : *inner) {
      if (name.back() == '/') {
        folders.push_back(name);
        continue;
      }
      if (!isRealDirectory(sub / name) && throughRealFolders(sub, name)) fs::remove(sub / name, ec);
    }
    std::sort(folders.begin(), folders.end(), [](const auto& a, const auto& b) { return a.size() > b.size(); });
    for (const auto& f : folders)
      if (isRealDirectory(sub / f) && fs::is_empty(sub / f, ec)) fs::remove(sub / f, ec);
    if (entries(sub).size() == 1) fs::remove(sub / kManifestName, ec);
  }
  if (fs::is_empty(sub, ec)) fs::remove(sub, ec);
  return !fs::exists(fs::symlink_status(sub, ec));
}

}  // namespace bc::core
