// The results directory of a run, written by rank 0 as steps converge, so nothing of a converged step
// is lost when a later step fails:
//   status.txt               "running (pid N)", then "complete: ...", "incomplete: <cause>",
//                            "interrupted: <signal> ..." or "failed: <cause>"; then the warnings, the
//                            notes (loaded plug-ins) and the provenance ("key: value", Provenance.hpp)
//   steps.csv                step, T, cut level, Newton iterations, final residual, linear iterations
//   tracked_points.csv       displacements and unwrapped rotation vectors of the named points
//   reactions.csv            force and moment sums (f_int - f_ext) over each support's nodes, at the
//                            components the support fixes (a component several supports fix: the last)
//   <table>.csv              per-step tables of contributions (contact_points.csv: every contact point)
//   vtk/step_NNNNN.vtu       the beams with their real cross-sections (point data: displacement, triads;
//                            cell data: section forces), zlib-compressed unless Output/VTK Compression
//                            is false; the steps of Output/VTK Every and VTK At, T = 0 and the last
//   vtk/contact_NNNNN.vtu    the active contact points of the same steps, vertex cells (their own series:
//                            Output::vtkSeries)
//   results.pvd, contact.pvd ParaView collections of those .vtu files with their T (rewritten with each)
//   timers.txt               StackedTimer summary
//   summary.csv              one row: completed, last T, steps, Newton iterations (total and largest per
//                            step), passes, solve wall time [s], peak memory [MB]; for studies and scripts;
//                            after the row, the provenance as "# key: value" lines
//   checkpoint.txt           the state after a converged step (Output/Checkpoint Every, and when a
//                            signal stops the run), for --restart (Checkpoint.hpp)
//   effective_parameters.xml the deck with every default filled in, the provenance in a
//                            <?beamcontact ...?> processing instruction before it (a valid deck)
// Every write is checked (Faults.hpp): a failure is an OutputError naming the file, raised on every
// rank. Whole files (status, summary, results.pvd, checkpoint) are replaced atomically, CSV rows are
// appended and flushed per step. The directory's manifest (OutputDirectory.hpp) names every file a
// run wrote there: a directory holding anything else is refused (unless --overwrite), a fresh run
// removes only an earlier run's files named there, and a directory in which a live run is writing is
// refused. A restarted run keeps the rows up to its checkpoint's step and appends after them.
#pragma once
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Teuchos_ParameterList.hpp>

#include "Faults.hpp"
#include "Model.hpp"
#include "OutputDirectory.hpp"
#include "Provenance.hpp"
#include "StaticSolver.hpp"
#include "TpetraTypes.hpp"

namespace bc::core {

struct RunSummary {
  RunReport run;
  int maxIterationsPerStep = 0;
  int passes = 0;
  double solveSeconds = 0.0;
  std::vector<std::pair<std::string, double>> stages;  // column name, seconds (timers.txt's main stages)
};

class ResultsWriter {
 public:
  // Every member function is collective (call it on all ranks). `resumeStep` >= 0 continues the run
  // in `directory` after that step, reached at load factor `resumeT` (restart: steps.csv must hold
  // the rows of steps 1 to resumeStep, the last at resumeT, or nothing is changed); otherwise the
  // directory is prepared for a fresh run.
  struct Where {
    std::string directory;
    bool fromDeck = false;  // the deck's Output/Directory: relative, no "..", no symbolic links
    bool overwrite = false;  // write beside files beamcontact did not write (--overwrite)
    std::vector<std::string> notes;  // lines status.txt carries after its first (e.g. the loaded plug-ins)
    Fields provenance;  // what produced the results (Provenance.hpp), in status, summary and effective deck
    int vtkEvery = 1;  // Output/VTK Every: steps whose number it divides (0: none of them)
    std::vector<double> vtkAt;  // Output/VTK At: the first converged step at or beyond each of these T
    bool vtkCompression = true;  // Output/VTK Compression: zlib-compressed appended data
  };
  ResultsWriter(const Where& where, const Model& model, Teuchos::RCP<const Comm> comm, bool writeVtk = true,
                int resumeStep = -1, double resumeT = 0.0);
  void writeEffective(const Teuchos::ParameterList& effective);
  void writeInitial(const State& state);
  void writeStep(const StepReport& step, const State& state, const std::vector<double>& fullResidual);
  void writeCheckpoint(const std::string& text);
  void writeSummary(const RunSummary& summary);
  void finish(const RunReport& run, const std::string& timerReport);
  // Best effort after an error: status "failed: <cause>" (never throws).
  void fail(const std::string& cause) noexcept;
  const std::string& directory() const { return dir_; }
  // The results files a run writes in its directory (besides vtk/step_*.vtu).
  std::vector<std::string> fileNames() const;

 private:
  void open(const Where& where);
  void prepareFresh();
  void prepareResume(int step, double T);
  // prepareResume's parts: steps.csv checked against the checkpoint (step, T); the tables cut to the
  // rows up to `step`; the VTK files' entries of results.pvd kept up to `step`.
  void checkStepsFitCheckpoint(int step, double T) const;
  void truncateTablesAfter(int step);
  void keepVtkEntriesUpTo(int step);
  // A file of a run's own (one of fileNames(), or vtk/step_N.vtu).
  bool ownResult(const std::string& relative) const;
  // Records `name` in the manifest (before it is created) and returns its path.
  std::filesystem::path own(const std::string& name);
  void openTables(bool append);
  void writeStepFiles(const StepReport& step, const State& state, const std::vector<double>& fullResidual);
  bool vtkSelected(int step, double T) const;
  void writeVtk(int step, double T, const State& state);
  void writePvds();
  void writeStatus(const std::string& text);
  bool root() const { return rank_ == 0; }

  std::string dir_;
  std::vector<std::string> notes_;
  Fields provenance_;
  OutputDirectory out_;  // rank 0: the directory and its manifest
  const Model& model_;
  Teuchos::RCP<const Comm> comm_;
  int rank_ = 0;
  bool vtk_ = true;
  OutputFile steps_, newton_, tracked_, reactions_;
  std::vector<std::unique_ptr<OutputFile>> tables_;  // one per contribution with a table
  int vtkEvery_ = 1;
  std::vector<double> vtkAt_;
  bool vtkCompression_ = true;
  double lastT_ = 0.0;  // the last converged step's load factor (VTK At)
  // Each VTK series (Output::vtkSeries; "" the beams') with its files' load factors and names.
  std::map<std::string, std::vector<std::pair<double, std::string>>> vtkFiles_;
  // rank 0: the last converged step when its VTK files were not written (finish writes them).
  struct Unwritten {
    int step;
    double T;
    State state;
  };
  std::optional<Unwritten> unwritten_;
};

}  // namespace bc::core
