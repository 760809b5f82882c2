// Comparative method studies: `beamcontact study STUDY.xml`.
//
// A study deck names a base deck and groups of cases. Each group varies parameters of the base deck
// (any parameter path, e.g. "Contact/Enforcement/Penalty/Normal Penalty Parameter") over lists of
// values; a group's cases are all combinations of its lists. Every case is written as a deck of its
// own and run as `beamcontact run` would run it, several at once: by a pool of worker processes that
// each start MPI and Kokkos once and run case after case, or (--process-per-case) each in a process
// of its own (StudyPool.hpp). A case that fails, even by crashing its process, is recorded with its
// cause and the others go on. The study directory receives
//   cases/NNN/          each case's deck.xml, log.txt and its full results directory
//   cases.csv           one row per case: group, the varied parameters, status and cause, outputs
//                       at "At T" (with their error against the "Reference Group"), Newton
//                       iterations (total, largest per step), passes, solve time (with --timing:
//                       the median and spread of several runs)
//                       and the version and commit that ran each case (its status.txt)
//   study.json          what the report script needs, and the study's provenance (core/Provenance.hpp)
//   report.md, *.png    the table and the plots (drivers/study_report.py, matplotlib), the provenance
// The study deck format is in docs/studies.md. StudyDeck.hpp reads the study deck and expands its
// cases; StudyReport.hpp writes the table, study.json and the report; Study.cpp runs the cases.
#pragma once
#include <string>
#include <vector>

namespace bc::drivers {

struct StudyOptions {
  std::string output;  // study directory; default results/<study name>
  int parallel = 0;  // cases run at once; 0: the deck's "Parallel Cases", else the core count
  bool report = true;  // write report.md and the plots
  bool quiet = false;  // --quiet: nothing on stdout when every case completes (errors and warnings on stderr)
  int timing = 0;  // > 0: fair timing: one case at a time, VTK off, each run this many times
  std::vector<std::string> plugins;  // --plugin libraries, passed on to every case
  bool processPerCase = false;  // --process-per-case: each case a `beamcontact run` process (else a pool of workers)
  bool overwrite = false;  // --overwrite: write beside files beamcontact did not write (passed on to every case)
  std::string command;  // the study's command line, for its provenance (study.json, report.md)
};

// The installed helper script `name` (share/beamcontact beside the program's bin folder; in the
// build tree, build/share/beamcontact). Throws when it is missing.
std::string scriptPath(const std::string& name);

// The documentation's folder: share/beamcontact/docs beside the program's bin folder when installed
// (wherever the install went), else the source tree's docs (a build tree), else the configured
// install prefix's; what --help and the messages cite (core::setDocumentationDirectory).
std::string findDocumentation();

// Runs `command` (program path and arguments, no shell) and returns its exit code (128 + signal
// when killed); throws when it cannot be started.
int runProgram(const std::vector<std::string>& command);

// Runs the study; returns 0 when every case completed, 2 when some did not (all are recorded), 4 when
// every case completed but the report could not be written (cases.csv is), throws core::InputError on
// a bad study deck.
int runStudy(const std::string& studyFile, const StudyOptions& options);

}  // namespace bc::drivers
