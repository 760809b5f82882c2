// What a study reads from its cases' results and writes from them (drivers/Study.hpp): the table
// cases.csv, study.json for the report script, and report.md with its figures.
#pragma once
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "StudyDeck.hpp"
#include "core/OutputDirectory.hpp"
#include "core/Provenance.hpp"

namespace bc::drivers::study {

// A case's summary.csv as column name -> value text; empty when it has none.
std::map<std::string, std::string> readSummary(const std::filesystem::path& dir);

// A run's status: the first line of its status.txt (warnings and notes follow it).
std::string runStatusLine(const std::filesystem::path& dir);

// The last non-empty line of a file that starts with `prefix` (any line when empty).
std::string lastLine(const std::filesystem::path& file, const std::string& prefix = "");

// A file's whole text; empty when it cannot be read.
std::string readText(const std::filesystem::path& file);

// What the table takes from a case's results directory: its outputs at "At T", its summary.csv, and
// the version and commit that ran it (status.txt).
struct CaseFigures {
  std::map<std::string, std::string> outputs, summary;
  std::string version, commit;
};

// The study's cases and the directory the table and the report go to.
struct StudyResults {
  const StudyDeck& deck;
  const std::vector<Case>& all;
  const Case* reference;  // the reference case, or null
  int timing;  // --timing: runs of each case
  std::filesystem::path dir;
  core::OutputDirectory& out;
  core::Fields provenance;  // the study's (when it started; it runs no MPI, each case one rank)
  // The figures of each recorded case (by index), read once: the table is rewritten after every
  // finished case, and reading every case's results each time grew as the square of the cases.
  mutable std::map<int, CaseFigures> figures = {};
};

// (Re)writes cases.csv (atomically): one row per case with its status, outputs, errors against the
// reference and run figures.
void writeCaseTable(const StudyResults& r);

// Writes study.json: what the report script needs to know (with a few facts of the base deck), and how
// the cases ran (`caseProcesses`: "worker pool" or "process per case", with the processes started).
void writeStudyJson(const StudyResults& r, int parallel, const std::string& caseProcesses, int processesStarted);

// Runs the report script (report.md and the figures), recording every file it writes in the
// manifest. Returns the script's exit code: 0 written, 4 a Python module is missing (the script said
// which, in one line), else it failed.
int writeReport(const StudyResults& r, bool quiet = false);  // quiet: the script prints nothing on stdout
// Whether the report script finds the Python modules it needs (study_report.py --check-modules); when
// not, the script has printed one line naming the missing one and its Debian package.
bool reportModulesPresent();

}  // namespace bc::drivers::study
