#include "Provenance.hpp"

#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <sstream>

#include <Trilinos_version.h>

namespace bc::core {

namespace {
const char* const kKeys[] = {"version", "compiler", "commit", "build_type", "trilinos",   "mpi",
                             "date",    "host",     "ranks",  "command",    "deck_sha256"};
}

std::string mpiLibraryVersion() {
  char text[MPI_MAX_LIBRARY_VERSION_STRING] = {0};
  int length = 0;
  if (MPI_Get_library_version(text, &length) != MPI_SUCCESS) return "unknown";
  std::string s(text, static_cast<std::size_t>(std::max(length, 0)));
  // "Open MPI v4.1.4, package: Debian OpenMPI, ident: ..." / "MPICH Version:\t4.0.2\n...": the first part.
  s = s.substr(0, s.find_first_of(",\n"));
  std::replace(s.begin(), s.end(), '\t', ' ');
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s.empty() ? "unknown" : s;
}

std::string trilinosVersion() {
  const int v = TRILINOS_MAJOR_MINOR_VERSION;  // 130200: 13.2.0
  return std::to_string(v / 10000) + "." + std::to_string(v / 100 % 100) + "." + std::to_string(v % 100);
}

Fields runProvenance(const Fields& build, int ranks, const std::string& command) {
  Fields f = build;
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", &utc);
  char host[256] = {0};
  if (gethostname(host, sizeof host - 1) != 0) host[0] = '\0';
  f.emplace_back("date", date);
  f.emplace_back("host", host[0] ? host : "unknown");
  f.emplace_back("ranks", std::to_string(ranks));
  f.emplace_back("command", command);
  return f;
}

std::string commandLine(int argc, const char* const* argv) {
  std::string line;
  for (int i = 0; i < argc; ++i) {
    const std::string a = argv[i];
    const bool plain =
        !a.empty() && a.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-+=.,/:@%") ==
                          std::string::npos;
    if (i) line += ' ';
    if (plain) {
      line += a;
      continue;
    }
    line += '\'';
    for (char c : a) line += c == '\'' ? std::string("'\\''") : std::string(1, c == '\n' ? ' ' : c);
    line += '\'';
  }
  return line;
}

std::string field(const Fields& fields, const std::string& key) {
  for (const auto& [k, v] : fields)
    if (k == key) return v;
  return "";
}

std::string fieldLines(const Fields& fields, const std::string& prefix) {
  std::string s;
  for (const auto& [k, v] : fields) s += prefix + k + ": " + v + "\n";
  return s;
}

Fields readFieldLines(const std::string& text, const std::string& prefix) {
  Fields f;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(prefix, 0) != 0) continue;
    line = line.substr(prefix.size());
    const auto colon = line.find(": ");
    if (colon == std::string::npos) continue;
    const std::string key = line.substr(0, colon);
    if (std::find(std::begin(kKeys), std::end(kKeys), key) != std::end(kKeys))
      f.emplace_back(key, line.substr(colon + 2));
  }
  return f;
}

namespace {
std::string& documentation() {
  static std::string directory = "docs";
  return directory;
}
}  // namespace

void setDocumentationDirectory(const std::string& directory) { documentation() = directory; }
const std::string& documentationDirectory() { return documentation(); }
std::string documentationPage(const std::string& page) { return documentation() + "/" + page; }

}  // namespace bc::core
