#include "ResultsWriter.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

#include <Teuchos_XMLParameterListHelpers.hpp>

#include <zlib.h>

#include "Checkpoint.hpp"
#include "Parameters.hpp"

namespace bc::core {

namespace fs = std::filesystem;

namespace {

std::string fixed12(double v) {
  std::ostringstream s;
  s << std::setprecision(12) << v;
  return s.str();
}

// A VTK file's name: "step_00012.vtu" (the beams' series) or "<series>_00012.vtu" (e.g. contact_00012.vtu)
// -> 12, else -1 (a series name is lower-case letters).
int vtkStep(const std::string& name) {
  const auto under = name.find('_');
  if (under == 0 || under == std::string::npos || name.size() != under + 10 || name.substr(under + 6) != ".vtu")
    return -1;
  for (std::size_t k = 0; k < under; ++k)
    if (!std::islower(static_cast<unsigned char>(name[k]))) return -1;
  for (std::size_t k = under + 1; k < under + 6; ++k)
    if (!std::isdigit(static_cast<unsigned char>(name[k]))) return -1;
  return std::stoi(name.substr(under + 1, 5));
}

// The VTK series a contribution draws into (Output::vtkSeries): its collection file and the name of its
// step files.
std::string pvdName(const std::string& series) { return (series.empty() ? "results" : series) + ".pvd"; }
std::string vtuName(const std::string& series, int step) {
  char name[64];
  std::snprintf(name, sizeof name, "vtk/%s_%05d.vtu", series.empty() ? "step" : series.c_str(), step);
  return name;
}

std::string readAll(const fs::path& p) {
  std::ifstream f(p);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

// Bytes kept allocated for status.txt, so that its final status can be written on a full disk.
constexpr long kStatusReserve = 64 * 1024;

// The pid of a live process other than this one that status.txt says is running, else 0.
long livePid(const fs::path& status) {
  const std::string text = readAll(status);
  const auto at = text.find("running (pid ");
  if (at != 0) return 0;
  const long pid = std::atol(text.c_str() + 13);
  if (pid <= 0 || pid == static_cast<long>(getpid())) return 0;
  if (kill(static_cast<pid_t>(pid), 0) != 0) return 0;
  // A live process of that number that is not a beamcontact (the number was reused) writes nothing here.
  const std::string command = readAll("/proc/" + std::to_string(pid) + "/cmdline");
  return command.empty() || command.find("beamcontact") != std::string::npos ? pid : 0;
}

// The provenance as an XML processing instruction, one pseudo-attribute per line:
//   <?beamcontact version="0.1.0" commit="..." ... command="beamcontact run deck.xml --output out"?>
// (not a comment: XML forbids "--" in comments, and command lines have them). The deck reader skips it.
std::string provenanceInstruction(const Fields& fields) {
  if (fields.empty()) return "";
  std::string s = "<?beamcontact";
  for (const auto& [key, value] : fields) {
    s += "\n  " + key + "=\"";
    for (char c : value) {
      if (c == '&') s += "&amp;";
      else if (c == '<') s += "&lt;";
      else if (c == '>') s += "&gt;";
      else if (c == '"') s += "&quot;";
      else s += c;
    }
    s += '"';
  }
  return s + "?>\n";
}

}  // namespace

ResultsWriter::ResultsWriter(const Where& where, const Model& model, Teuchos::RCP<const Comm> comm, bool writeVtk,
                             int resumeStep, double resumeT)
    : dir_(where.directory),
      notes_(where.notes),
      provenance_(where.provenance),
      model_(model),
      comm_(comm),
      rank_(comm->getRank()),
      vtk_(writeVtk),
      vtkEvery_(where.vtkEvery),
      vtkAt_(where.vtkAt),
      vtkCompression_(where.vtkCompression),
      lastT_(resumeStep >= 0 ? resumeT : 0.0) {
  vtkFiles_[""];  // the beams' series, always
  for (const auto& c : model_.contributions) {
    const std::string series = c->vtkSeries();
    if (series != "step" && !series.empty() &&
        std::all_of(series.begin(), series.end(), [](char ch) { return ch >= 'a' && ch <= 'z'; }))
      vtkFiles_[series];
    else if (!series.empty())
      throw std::logic_error("VTK series \"" + series + "\" is not a lower-case word other than \"step\"");
  }
  collectively(*comm_, [&] {
    if (!root()) return;
    if (dir_.empty()) throw InputError("the results directory is empty; give Output/Directory or --output");
    try {
      OutputDirectory::Options options;
      options.overwrite = where.overwrite;
      options.pathFromDeck = where.fromDeck;
      options.parameter = "Output/Directory";
      out_ = OutputDirectory(dir_, options);
      // A study's folder (its cases.csv and cases/ beside this run's files would read as one result).
      if (out_.lists("study.json") || out_.lists("cases.csv") || out_.lists("cases/"))
        throw InputError("results directory \"" + dir_ +
                         "\" holds a study (its study.json, cases.csv and cases/): give the run a directory of its "
                         "own (--output)");
      if (resumeStep >= 0) prepareResume(resumeStep, resumeT);
      else prepareFresh();
      writeStatus("running (pid " + std::to_string(getpid()) + ")");
      setStatusFile((fs::path(dir_) / "status.txt").string());
    } catch (const OutputError& e) {
      throw InputError(std::string("the results directory cannot be written: ") + e.what());
    } catch (const std::filesystem::filesystem_error& e) {
      throw InputError("the results directory \"" + dir_ + "\" cannot be used: " + e.code().message());
    }
  });
}

std::vector<std::string> ResultsWriter::fileNames() const {
  std::vector<std::string> names = {
      "status.txt",  "steps.csv",  "newton.csv",  "tracked_points.csv", "reactions.csv",
      "summary.csv", "timers.txt", "results.pvd", "checkpoint.txt",     "effective_parameters.xml"};
  for (const auto& c : model_.contributions)
    if (!c->tableName().empty()) names.push_back(c->tableName());
  for (const auto& [series, files] : vtkFiles_)
    if (!series.empty()) names.push_back(pvdName(series));
  return names;
}

fs::path ResultsWriter::own(const std::string& name) {
  out_.add(name);
  return fs::path(dir_) / name;
}

bool ResultsWriter::ownResult(const std::string& relative) const {
  if (relative.rfind("vtk/", 0) == 0) return vtkStep(relative.substr(4)) >= 0;
  // An earlier run's series (e.g. contact.pvd of a run with contact): lower-case letters and ".pvd".
  if (relative.size() > 4 && relative.compare(relative.size() - 4, 4, ".pvd") == 0 &&
      std::all_of(relative.begin(), relative.end() - 4, [](char ch) { return ch >= 'a' && ch <= 'z'; }))
    return true;
  const auto names = fileNames();
  return std::find(names.begin(), names.end(), relative) != names.end();
}

void ResultsWriter::prepareFresh() {
  const fs::path dir(dir_);
  if (out_.lists("status.txt") && fs::exists(dir / "status.txt"))
    if (const long pid = livePid(dir / "status.txt"))
      throw InputError("results directory \"" + dir_ + "\" is in use by a running beamcontact (pid " +
                       std::to_string(pid) + "); choose another --output");
  // An earlier run's results go, so none of them is mistaken for this run's; only files the
  // manifest names are removed.
  out_.removeOwn([&](const std::string& name) {
    const bool tmp = name.size() > 4 && name.compare(name.size() - 4, 4, ".tmp") == 0;
    return ownResult(tmp ? name.substr(0, name.size() - 4) : name);
  });
  out_.folder("vtk/");
  openTables(false);
}

void ResultsWriter::prepareResume(int step, double T) {
  const fs::path dir(dir_);
  if (!out_.lists("status.txt") || !out_.lists("checkpoint.txt") || !fs::exists(dir / "status.txt") ||
      !fs::exists(dir / "checkpoint.txt"))
    throw InputError("\"" + dir_ + "\" holds no run to restart (status.txt and checkpoint.txt are needed)");
  if (const long pid = livePid(dir / "status.txt"))
    throw InputError("results directory \"" + dir_ + "\" is in use by a running beamcontact (pid " +
                     std::to_string(pid) + ")");
  checkStepsFitCheckpoint(step, T);
  out_.removeLeftovers();  // a run killed while writing a file left its "<name>.tmp"
  out_.folder("vtk/");
  // Rows of steps after the checkpoint's were computed by the interrupted run past the state this
  // run continues from: they go, and this run writes them again.
  truncateTablesAfter(step);
  out_.removeOwn([&](const std::string& name) { return name.rfind("vtk/", 0) == 0 && vtkStep(name.substr(4)) > step; });
  keepVtkEntriesUpTo(step);
  if (vtk_) writePvds();  // without the entries of the files just removed, also if no step follows
  out_.removeOwn([](const std::string& name) {
    return name == "summary.csv" || name == "timers.txt" || name == "summary.csv.tmp" || name == "timers.txt.tmp";
  });
  openTables(true);
}

// The checkpoint belongs to this directory's run: steps.csv holds the rows of its steps 1 to `step`
// (each converged step's row is written before its checkpoint), the last at its load factor (to the
// 12 digits written). Checked before anything here changes.
void ResultsWriter::checkStepsFitCheckpoint(int step, double T) const {
  const fs::path dir(dir_);
  const std::string checkpoint = (dir / "checkpoint.txt").string();
  std::ifstream in(dir / "steps.csv");
  std::string line;
  int rows = 0;
  double lastT = 0.0;
  for (bool header = true; std::getline(in, line); header = false) {
    if (header || std::count(line.begin(), line.end(), ',') < 2) continue;  // a row cut short stays out
    char* end = nullptr;
    const long s = std::strtol(line.c_str(), &end, 10);
    if (*end != ',' || s > step) continue;
    if (s != rows + 1)
      throw InputError("checkpoint " + checkpoint + " cannot be used: steps.csv has step " + std::to_string(s) +
                       " where step " + std::to_string(rows + 1) + " belongs (it is not this directory's run)");
    ++rows;
    lastT = std::strtod(end + 1, nullptr);
  }
  if (in.is_open() && rows != step)
    throw InputError("checkpoint " + checkpoint + " cannot be used: it is at step " + std::to_string(step) +
                     ", steps.csv has " + std::to_string(rows) + " steps up to there (it is not this directory's run)");
  if (rows > 0 && !(std::abs(lastT - T) <= 1e-11 * std::max(1.0, std::abs(T))))
    throw InputError("checkpoint " + checkpoint + " cannot be used: its step " + std::to_string(step) + " is at T = " +
                     shortest(T) + ", steps.csv's at T = " + shortest(lastT) + " (it is not this directory's run)");
}

// Each table keeps its header and its whole rows of steps up to `step`. Every table is read before
// any is written: a missing one refuses the restart with every file as it was.
void ResultsWriter::truncateTablesAfter(int step) {
  const fs::path dir(dir_);
  std::vector<std::string> csvs = {"steps.csv", "newton.csv", "tracked_points.csv", "reactions.csv"};
  for (const auto& c : model_.contributions)
    if (!c->tableName().empty()) csvs.push_back(c->tableName());
  std::vector<std::string> keptTables;
  for (const auto& name : csvs) {
    std::ifstream in(dir / name);
    if (!in) throw InputError("cannot restart in \"" + dir_ + "\": " + name + " is missing");
    std::string line, kept;
    bool header = true;
    while (std::getline(in, line)) {
      if (header) {
        kept += line + "\n";
        header = false;
        continue;
      }
      // A row cut short by the interruption has no line end (a table without tracked points has rows
      // of step and T only, so the commas do not tell).
      const bool whole = !in.eof();
      const auto comma = line.find(',');
      if (!whole || comma == std::string::npos) continue;
      char* end = nullptr;
      const long s = std::strtol(line.c_str(), &end, 10);
      if (end == line.c_str() + comma && s <= step) kept += line + "\n";
    }
    keptTables.push_back(std::move(kept));
  }
  for (std::size_t i = 0; i < csvs.size(); ++i) writeFileAtomically(own(csvs[i]), keptTables[i]);
}

// results.pvd: the entries of the kept files.
void ResultsWriter::keepVtkEntriesUpTo(int step) {
  const fs::path dir(dir_);
  for (auto& [series, files] : vtkFiles_) {
    std::istringstream pvd(readAll(dir / pvdName(series)));
    for (std::string line; std::getline(pvd, line);) {
      const auto t = line.find("timestep=\""), f = line.find("file=\"");
      if (t == std::string::npos || f == std::string::npos) continue;
      const std::string file = line.substr(f + 6, line.find('"', f + 6) - f - 6);
      const int s = vtkStep(fs::path(file).filename().string());
      if (s >= 0 && s <= step && file == vtuName(series, s) && fs::exists(dir / file))
        files.emplace_back(std::atof(line.c_str() + t + 10), file);
    }
  }
}

void ResultsWriter::openTables(bool append) {
  // A fresh table is a new file (a file of the same name is unlinked first, so one hard-linked elsewhere
  // keeps its content).
  auto table = [&](OutputFile& f, const std::string& name) {
    const fs::path p = own(name);
    std::error_code ec;
    if (!append) fs::remove(p, ec);
    f.open(p, append);
  };
  table(steps_, "steps.csv");
  table(newton_, "newton.csv");
  table(tracked_, "tracked_points.csv");
  table(reactions_, "reactions.csv");
  for (const auto& c : model_.contributions) {
    if (c->tableName().empty()) {
      tables_.emplace_back();
      continue;
    }
    tables_.push_back(std::make_unique<OutputFile>());
    table(*tables_.back(), c->tableName());
    if (!append) tables_.back()->write("step,T," + c->tableHeader() + "\n");
  }
  if (append) return;
  steps_.write("step,T,cut_level,newton_iterations,passes,final_residual,linear_iterations,backtracks,stalls\n");
  newton_.write("step,T,iteration,residual_norm,increment_norm,linear_iterations,linear_residual\n");
  std::string h = "step,T";
  for (const auto& p : model_.tracked)
    for (const char* c : {"ux", "uy", "uz", "rx", "ry", "rz"}) h += "," + p.name + "_" + c;
  tracked_.write(h + "\n");
  h = "step,T";
  for (const auto& s : model_.supports)
    for (const char* c : {"Fx", "Fy", "Fz", "Mx", "My", "Mz"}) h += "," + s.name + "_" + c;
  reactions_.write(h + "\n");
}

void ResultsWriter::writeStatus(const std::string& text) {
  std::string all = text + "\n";
  for (const auto& n : notes_) all += n + "\n";
  all += fieldLines(provenance_);
  const fs::path path = own("status.txt");
  try {
    writeFileAtomically(path, all);
  } catch (const OutputError&) {
    // A full disk has no room for a new file; the status is then rewritten in place, in the space
    // reserved for it below (a text beyond it could need new blocks).
    if (static_cast<long>(all.size()) > kStatusReserve || !rewriteInPlace(path, all)) throw;
    return;
  }
  // Room for the final status: kStatusReserve bytes allocated beyond the text (the file's length stays).
  const int fd = ::open(path.c_str(), O_WRONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd >= 0) {
    if (fallocate(fd, FALLOC_FL_KEEP_SIZE, 0, kStatusReserve) != 0) {
    }
    ::close(fd);
  }
}

void ResultsWriter::writeEffective(const Teuchos::ParameterList& effective) {
  collectively(*comm_, [&] {
    if (!root()) return;
    std::ostringstream xml;
    Teuchos::writeParameterListToXmlOStream(effective, xml);
    writeFileAtomically(own("effective_parameters.xml"), provenanceInstruction(provenance_) + xml.str());
  });
}

void ResultsWriter::writeInitial(const State& state) {
  collectively(*comm_, [&] {
    if (root() && vtk_) writeVtk(0, 0.0, state);
  });
}

void ResultsWriter::writeStep(const StepReport& step, const State& state, const std::vector<double>& r) {
  collectively(*comm_, [&] {
    injectFault("output");
    if (!root()) return;
    // The step is committed to every file or to none: when a write fails, the rows already written for
    // it are taken back, so the CSVs never disagree by a step.
    std::vector<std::pair<OutputFile*, long>> lengths;
    for (OutputFile* f : {&steps_, &newton_, &tracked_, &reactions_}) lengths.emplace_back(f, f->length());
    for (auto& t : tables_)
      if (t) lengths.emplace_back(t.get(), t->length());
    std::map<std::string, std::size_t> vtkBefore;
    for (const auto& [series, files] : vtkFiles_) vtkBefore[series] = files.size();
    try {
      writeStepFiles(step, state, r);
    } catch (...) {
      for (auto& [file, length] : lengths) file->truncateTo(length);
      for (auto& [series, files] : vtkFiles_) {
        for (std::size_t k = vtkBefore[series]; k < files.size(); ++k) {
          std::error_code ec;
          fs::remove(fs::path(dir_) / files[k].second, ec);
        }
        files.resize(vtkBefore[series]);
      }
      try {
        if (vtk_) writePvds();  // without the files just removed
      } catch (...) {
      }
      throw;
    }
  });
}

void ResultsWriter::writeStepFiles(const StepReport& step, const State& state, const std::vector<double>& r) {
  int linear = 0;
  for (const auto& h : step.history) linear += h.linearIterations;
  std::ostringstream row;
  row << std::setprecision(12);
  row << step.step << "," << step.T << "," << step.cutLevel << "," << step.iterations << "," << step.passes << ","
      << step.history.back().residualNorm << "," << linear << "," << step.backtracks << "," << step.stalls << "\n";
  steps_.write(row.str());
  // Each iterate of the step's Newton solves (all passes): the residual history.
  row.str("");
  for (std::size_t k = 0; k < step.history.size(); ++k) {
    const NewtonIterate& h = step.history[k];
    row << step.step << "," << step.T << "," << k << "," << h.residualNorm << "," << h.incrementNorm << ","
        << h.linearIterations << "," << h.linearResidual << "\n";
  }
  newton_.write(row.str());
  row.str("");
  row << step.step << "," << step.T;
  for (const auto& p : model_.tracked) {
    const Vec3d u = state.displacement(p.node);
    const Vec3d& psi = state.rotationVector[p.node];
    row << "," << u[0] << "," << u[1] << "," << u[2] << "," << psi[0] << "," << psi[1] << "," << psi[2];
  }
  row << "\n";
  tracked_.write(row.str());
  row.str("");
  row << step.step << "," << step.T;
  // Each constrained dof's reaction is reported once, by the support that prescribes it: the last
  // support (in the deck's order) that fixes it, whose motion is the one applied (StaticSolver). A node
  // held by several supports that fix different components (press, then slide) has its reaction split
  // between them by component, so the rows sum to the total reaction. A component no support fixes
  // holds Newton's remainder, no reaction: it is not reported.
  std::map<std::pair<int, int>, std::size_t> owner;
  for (std::size_t i = 0; i < model_.supports.size(); ++i)
    for (int n : model_.supports[i].nodes)
      for (int k = 0; k < 6; ++k)
        if (model_.supports[i].fixed[k]) owner[{n, k}] = i;
  std::vector<std::array<double, 6>> sums(model_.supports.size(), std::array<double, 6>{});
  for (const auto& [dof, support] : owner)
    sums[support][dof.second] += r[std::size_t(kDofsPerNode) * dof.first + dof.second];
  for (const auto& sum : sums)
    for (double v : sum) row << "," << v;
  row << "\n";
  reactions_.write(row.str());
  for (std::size_t i = 0; i < model_.contributions.size(); ++i) {
    if (!tables_[i]) continue;
    std::string rows;
    for (const auto& line : model_.contributions[i]->tableRows())
      rows += std::to_string(step.step) + "," + fixed12(step.T) + "," + line + "\n";
    tables_[i]->write(rows);
  }
  if (vtk_) {
    if (vtkSelected(step.step, step.T)) {
      writeVtk(step.step, step.T, state);
      unwritten_.reset();
    } else {
      unwritten_ = Unwritten{step.step, step.T, state};
    }
  }
  lastT_ = step.T;
}

// Output/VTK Every and VTK At: a step whose number VTK Every divides, or the first converged step at or
// beyond a listed load factor (the previous converged step was below it; 1e-12: T's rounding).
bool ResultsWriter::vtkSelected(int step, double T) const {
  if (vtkEvery_ > 0 && step % vtkEvery_ == 0) return true;
  constexpr double kRound = 1e-12;
  for (double at : vtkAt_)
    if (lastT_ < at - kRound && at <= T + kRound) return true;
  return false;
}

void ResultsWriter::writeCheckpoint(const std::string& text) {
  collectively(*comm_, [&] {
    if (root()) writeFileAtomically(own("checkpoint.txt"), text);
  });
}

namespace {
// VTK XML with every array in one appended block (header_type UInt64). Raw: each array is preceded by
// its size in bytes. Compressed (vtkZLibDataCompressor): each array is cut into blocks of kBlock bytes,
// each compressed with zlib, preceded by the header [number of blocks, kBlock, size of the last block
// (0: full), compressed size of each block]; a reader gets the same bytes back. zlib's fastest level:
// its default one saves another 9 % on a 40 x 40 grid for twice the time (docs/input.md).
class VtkArrays {
 public:
  explicit VtkArrays(bool compress) : compress_(compress) {}
  // The attributes of a DataArray that lives in the appended block, and its bytes appended.
  template <class T>
  std::string add(const std::string& type, const std::string& name, int components, const std::vector<T>& values) {
    std::ostringstream a;
    a << "<DataArray type=\"" << type << "\"";
    if (!name.empty()) a << " Name=\"" << name << "\"";
    if (components > 1) a << " NumberOfComponents=\"" << components << "\"";
    a << " format=\"appended\" offset=\"" << data_.size() << "\"/>\n";
    append(reinterpret_cast<const unsigned char*>(values.data()), values.size() * sizeof(T));
    return a.str();
  }
  std::string vectors(const std::string& name, const std::vector<Vec3d>& v) {
    std::vector<double> flat;
    flat.reserve(3 * v.size());
    for (const auto& x : v) flat.insert(flat.end(), {x[0], x[1], x[2]});
    return add("Float64", name, 3, flat);
  }
  // A field-data array (one tuple per value).
  template <class T> std::string field(const std::string& type, const std::string& name, const std::vector<T>& values) {
    std::string a = add(type, name, 1, values);
    return a.insert(a.find(" format="), " NumberOfTuples=\"" + std::to_string(values.size()) + "\"");
  }
  const std::string& data() const { return data_; }
  // The VTKFile element's attribute naming the compressor ("" when raw).
  std::string compressorAttribute() const { return compress_ ? " compressor=\"vtkZLibDataCompressor\"" : ""; }

 private:
  static constexpr std::uint64_t kBlock = 1 << 16;
  void put(std::uint64_t v) { data_.append(reinterpret_cast<const char*>(&v), sizeof v); }
  void append(const unsigned char* bytes, std::uint64_t size) {
    if (!compress_) {
      put(size);
      data_.append(reinterpret_cast<const char*>(bytes), size);
      return;
    }
    const std::uint64_t blocks = (size + kBlock - 1) / kBlock;
    put(blocks);
    put(kBlock);
    put(size % kBlock);
    const std::size_t sizes = data_.size();
    for (std::uint64_t b = 0; b < blocks; ++b) put(0);
    std::vector<unsigned char> out(compressBound(kBlock));
    for (std::uint64_t b = 0; b < blocks; ++b) {
      const std::uint64_t n = std::min(kBlock, size - b * kBlock);
      uLongf length = out.size();
      if (compress2(out.data(), &length, bytes + b * kBlock, n, Z_BEST_SPEED) != Z_OK)
        throw OutputError("zlib could not compress a VTK array", "zlib failed");
      const std::uint64_t compressed = length;
      std::memcpy(&data_[sizes + 8 * b], &compressed, sizeof compressed);
      data_.append(reinterpret_cast<const char*>(out.data()), length);
    }
  }
  bool compress_;
  std::string data_;
};

// One step's drawing of a series as a VTU file: points at their reference place, with the displacement
// as point data (ParaView's Warp By Vector, scale 1, draws the deformed shape; contact points have no
// reference place: they are drawn where they are, with zero displacement); the load factor and the step
// as field data; the cells' beam and element where a cell has a beam.
std::string vtuText(VtkMesh& mesh, int step, double T, bool compress) {
  const std::size_t n = mesh.points.size();
  std::vector<Vec3d> reference(n);
  for (std::size_t i = 0; i < n; ++i) reference[i] = mesh.points[i] - mesh.pointDisplacement[i];
  VtkArrays a(compress);
  std::ostringstream f;
  f << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
       "header_type=\"UInt64\""
    << a.compressorAttribute() << ">\n<UnstructuredGrid>\n<FieldData>\n"
    << a.field("Float64", "load factor", std::vector<double>{T})
    << a.field("Int32", "step", std::vector<std::int32_t>{step}) << "</FieldData>\n<Piece NumberOfPoints=\"" << n
    << "\" NumberOfCells=\"" << mesh.cells.size() << "\">\n<Points>\n"
    << a.vectors("", reference) << "</Points>\n<Cells>\n";
  std::vector<std::int64_t> connectivity, offsets;
  std::vector<std::uint8_t> types(mesh.cellTypes.begin(), mesh.cellTypes.end());
  for (const auto& c : mesh.cells) {
    connectivity.insert(connectivity.end(), c.begin(), c.end());
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
  }
  f << a.add("Int64", "connectivity", 1, connectivity) << a.add("Int64", "offsets", 1, offsets)
    << a.add("UInt8", "types", 1, types) << "</Cells>\n<PointData Vectors=\"displacement\">\n"
    << a.vectors("displacement", mesh.pointDisplacement);
  for (auto& [arrayName, values] : mesh.pointVectors) {
    values.resize(n, Vec3d{});
    f << a.vectors(arrayName, values);
  }
  for (auto& [arrayName, values] : mesh.pointScalars) {
    values.resize(n, 0.0);
    f << a.add("Float64", arrayName, 1, values);
  }
  f << "</PointData>\n<CellData>\n";
  if (std::any_of(mesh.cellBeam.begin(), mesh.cellBeam.end(), [](int b) { return b >= 0; }))
    f << a.add("Int32", "beam", 1, std::vector<std::int32_t>(mesh.cellBeam.begin(), mesh.cellBeam.end()))
      << a.add("Int32", "element", 1, std::vector<std::int32_t>(mesh.cellElement.begin(), mesh.cellElement.end()));
  for (auto& [arrayName, values] : mesh.cellScalars) {
    values.resize(mesh.cells.size(), 0.0);
    f << a.add("Float64", arrayName, 1, values);
  }
  f << "</CellData>\n</Piece>\n</UnstructuredGrid>\n<AppendedData encoding=\"raw\">\n_" << a.data()
    << "\n</AppendedData>\n</VTKFile>\n";
  return f.str();
}
}  // namespace

// Each series (the beams', and e.g. the contact points') in its own file of the step, listed in its own
// collection.
void ResultsWriter::writeVtk(int step, double T, const State& state) {
  std::map<std::string, VtkMesh> meshes;
  for (const auto& [series, files] : vtkFiles_) meshes[series];
  for (const auto& c : model_.contributions) c->appendVtk(state, meshes[c->vtkSeries()]);
  for (auto& [series, mesh] : meshes) {
    const std::string name = vtuName(series, step);
    writeFileAtomically(own(name), vtuText(mesh, step, T, vtkCompression_));
    vtkFiles_[series].emplace_back(T, name);
  }
  writePvds();
}

void ResultsWriter::writePvds() {
  for (const auto& [series, files] : vtkFiles_) {
    std::ostringstream f;
    f << std::setprecision(12)
      << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n";
    for (const auto& [T, file] : files) f << "<DataSet timestep=\"" << T << "\" part=\"0\" file=\"" << file << "\"/>\n";
    f << "</Collection>\n</VTKFile>\n";
    writeFileAtomically(own(pvdName(series)), f.str());
  }
}

void ResultsWriter::writeSummary(const RunSummary& summary) {
  collectively(*comm_, [&] {
    if (!root()) return;
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    std::ostringstream f;
    f << "completed,last_T,steps,newton_iterations,max_newton_per_step,passes,solve_seconds,peak_memory_mb";
    for (const auto& [column, seconds] : summary.stages) f << ',' << column;
    f << ",warnings";  // how many warnings status.txt lists (e.g. a beam strained beyond the model's 5 %)
    // Then the provenance, a column each (after the figures, so readers by name or position read
    // those as before; values with a comma or a quote are quoted as CSV does).
    for (const auto& [key, value] : provenance_) f << ',' << key;
    f << '\n'
      << (summary.run.completed ? 1 : 0) << ',' << summary.run.lastT << ',' << summary.run.steps << ','
      << summary.run.newtonIterations << ',' << summary.maxIterationsPerStep << ',' << summary.passes << ','
      << summary.solveSeconds << ',' << usage.ru_maxrss / 1024.0;
    for (const auto& [column, seconds] : summary.stages) f << ',' << seconds;
    f << ',' << summary.run.warnings.size();
    for (const auto& [key, value] : provenance_) {
      std::string quoted = value;
      if (value.find_first_of(",\"\n") != std::string::npos) {
        quoted = "\"";
        for (char c : value) quoted += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
        quoted += '"';
      }
      f << ',' << quoted;
    }
    f << '\n';
    writeFileAtomically(own("summary.csv"), f.str());
  });
}

void ResultsWriter::finish(const RunReport& run, const std::string& timerReport) {
  collectively(*comm_, [&] {
    if (!root()) return;
    // The last converged step's drawing, when VTK Every and VTK At passed it by (the contributions still
    // hold that step: a failed step is restored to it).
    if (vtk_ && unwritten_) {
      writeVtk(unwritten_->step, unwritten_->T, unwritten_->state);
      unwritten_.reset();
    }
    // A results directory removed or moved during the run took the open tables with it: the run's
    // results are not where it says they are.
    for (const OutputFile* f : {&steps_, &newton_, &tracked_, &reactions_})
      if (f->isOpen() && !f->stillAtItsPath())
        throw OutputError("cannot write " + dir_ +
                              ": the results directory was removed or moved during the run "
                              "(" +
                              f->path() + " is gone)",
                          "the results directory was removed or moved");
    steps_.close();
    newton_.close();
    tracked_.close();
    reactions_.close();
    for (auto& t : tables_)
      if (t) t->close();
    writeFileAtomically(own("timers.txt"), timerReport);
    std::ostringstream s;
    if (run.completed)
      s << "complete: " << run.steps << " steps, " << run.newtonIterations << " Newton iterations, T = " << run.lastT;
    else if (run.interrupted)
      s << "interrupted: " << signalName(run.interrupted) << " at T = " << run.lastT << " after " << run.steps
        << " converged steps (checkpoint.txt holds the last one; continue with --restart)";
    else
      s << "incomplete: stopped at T = " << run.lastT << " after " << run.steps << " converged steps; " << run.failure;
    for (const auto& w : run.warnings) s << "\nwarning: " << w;
    writeStatus(s.str());
    setStatusFile("");
  });
}

void ResultsWriter::fail(const std::string& cause) noexcept {
  if (!root()) return;
  try {
    writeStatus("failed: " + cause);
  } catch (...) {
  }
}

}  // namespace bc::core
