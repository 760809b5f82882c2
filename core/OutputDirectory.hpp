// Directories the program writes into (a run's results, a study's folder and its cases), kept so that
// nothing of the user's is removed or overwritten:
//  - every such directory holds a manifest, beamcontact-manifest.txt, naming each file and folder the
//    program wrote there (a name is added before its file is created) and the version that wrote it;
//  - a directory that holds anything the manifest does not name is refused with one line naming the
//    foreign file, unless the user allows it (--overwrite); even then only the program's own names
//    are written, never over a foreign file that has one of them, and only files the manifest names
//    are removed;
//  - a path that comes from a deck stays where the deck's user ran it: relative, without "..", and
//    through no symbolic link (a path given on the command line is the user's own choice);
//  - files are created without following a symbolic link in their last component (Faults.cpp).
#pragma once
#include <filesystem>
#include <functional>
#include <set>
#include <string>

namespace bc::core {

// The manifest's file name.
inline constexpr const char* kManifestName = "beamcontact-manifest.txt";

// An output path read from a deck (`parameter` names it in messages): refuses an absolute path, a ".."
// component and (relative to the working directory) any existing component that is a symbolic link.
// Throws InputError.
void checkDeckOutputPath(const std::string& path, const std::string& parameter);

class OutputDirectory {
 public:
  struct Options {
    bool overwrite = false;  // --overwrite: foreign files are left in place instead of refused
    bool pathFromDeck = false;  // the path came from a deck (checkDeckOutputPath applies)
    std::string what = "results directory";  // for messages: "results directory", "study directory"
    std::string parameter;  // the deck parameter the path came from (when pathFromDeck)
  };
  OutputDirectory() = default;
  // Creates `dir` when missing, else checks it: a regular directory (a symbolic link only when the
  // path came from the command line), holding nothing but what its manifest names (nested folders
  // with a manifest of their own are checked by theirs). Writes the manifest when there is none.
  // Throws InputError naming the first foreign file.
  OutputDirectory(const std::filesystem::path& dir, const Options& options);
  const std::filesystem::path& path() const { return dir_; }
  // Records `relative` (a file, with the "<name>.tmp" it is written through, or a folder when it ends in
  // '/') before it is created. Throws OutputError; InputError when a file of that name is there that
  // the manifest does not name (the user's, left in place by --overwrite: it would be replaced).
  void add(const std::string& relative);
  // Records `relative`, a file the program has just written there through another process (the
  // study report's figures, named by the script), without add's check.
  void adopt(const std::string& relative);
  // A sub-folder of the program's own: recorded and created; one that is a symbolic link or a file is
  // refused (InputError), even with --overwrite, so nothing is written through it.
  std::filesystem::path folder(const std::string& relative);
  bool lists(const std::string& relative) const { return names_.count(relative) > 0; }
  // Removes the files the manifest names for which `which` is true (and their ".tmp"), and then the
  // listed folders that became empty. Never removes anything the manifest does not name.
  void removeOwn(const std::function<bool(const std::string&)>& which);
  // Removes a listed sub-folder with a manifest of its own: its own files, then the folder when empty.
  // Returns false when something foreign stayed (allowed by --overwrite) and the folder was kept.
  bool removeOwnFolder(const std::string& relative);
  // Removes the listed "<name>.tmp" files an interrupted write left (they are created exclusively, so
  // one left over would stop the next write of <name>).
  void removeLeftovers();

 private:
  std::filesystem::path dir_;
  std::set<std::string> names_;
};

}  // namespace bc::core
