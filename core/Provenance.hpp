// What produced a result: the BeamContact version and git commit, how it was built (build type,
// Trilinos, MPI library, compiler), and for a run its date, host, rank count and command line.
// `beamcontact --version` prints the build's part; every results directory carries all of it, as
// "key: value" lines in status.txt, "# key: value" lines after the data row of summary.csv and a
// <?beamcontact ...?> processing instruction in effective_parameters.xml (which the deck reader skips,
// so the file still runs as a deck); a study's cases.csv, study.json and report.md name it too.
// The commit is captured at build time (cmake/BuildInfo.cmake, drivers/BuildInfo.hpp): 12 hex digits,
// "-dirty" when tracked files differed from it, "unknown" outside a git checkout.
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace bc::core {

// Key and value, in the order they are written; keys are single words (version, commit, build_type,
// trilinos, mpi, compiler; for a run also date, host, ranks, command and deck_sha256, the digest of
// the deck file the run read).
using Fields = std::vector<std::pair<std::string, std::string>>;

// The MPI library's own version line, shortened to its name and version ("Open MPI v4.1.4"); may be
// called before MPI is initialized.
std::string mpiLibraryVersion();
// The Trilinos version the program was compiled against ("13.2.0").
std::string trilinosVersion();
// `build` (the program's: drivers/BuildInfo.hpp) and the run's date (now, UTC, ISO 8601), host, ranks
// and command line.
Fields runProvenance(const Fields& build, int ranks, const std::string& command);
// argv as one line a shell would split back into the same words (words quoted where needed).
std::string commandLine(int argc, const char* const* argv);
// The value of `key` in `fields`, else "".
std::string field(const Fields& fields, const std::string& key);
// "key: value" lines (one per field), each prefixed by `prefix`, each ending in a newline.
std::string fieldLines(const Fields& fields, const std::string& prefix = "");
// The fields of "key: value" lines of `text` whose key is one of the provenance keys (others are skipped).
Fields readFieldLines(const std::string& text, const std::string& prefix = "");

// The documentation the messages cite (docs/*.md): "docs" until the program sets where it is (its
// installed share/beamcontact/docs, or the source tree's docs in a build tree).
void setDocumentationDirectory(const std::string& directory);
const std::string& documentationDirectory();
// `page` ("beam-element.md") in the documentation directory.
std::string documentationPage(const std::string& page);

}  // namespace bc::core
