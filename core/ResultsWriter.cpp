#include "ResultsWriter.hpp"

#include <sys/resource.h>

#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <sstream>

namespace bc::core {

namespace fs = std::filesystem;

ResultsWriter::ResultsWriter(const std::string& directory, const Model& model, Teuchos::RCP<const Comm> comm,
                             bool writeVtk)
    : dir_(directory), model_(model), rank_(comm->getRank()), vtk_(writeVtk) {
  if (!root()) return;
  std::error_code ec;
  fs::create_directories(fs::path(dir_) / "vtk", ec);
  if (ec) throw std::runtime_error("cannot create the results directory \"" + dir_ + "\": " + ec.message());
  for (const auto& old : fs::directory_iterator(fs::path(dir_) / "vtk")) fs::remove(old.path());
  writeStatus("running");
  steps_.open(fs::path(dir_) / "steps.csv");
  tracked_.open(fs::path(dir_) / "tracked_points.csv");
  reactions_.open(fs::path(dir_) / "reactions.csv");
  if (!steps_ || !tracked_ || !reactions_) throw std::runtime_error("cannot write in \"" + dir_ + "\"");
  steps_ << "step,T,cut_level,newton_iterations,passes,final_residual,linear_iterations,backtracks\n";
  tracked_ << "step,T";
  for (const auto& p : model_.tracked)
    for (const char* c : {"ux", "uy", "uz", "rx", "ry", "rz"}) tracked_ << "," << p.name << "_" << c;
  tracked_ << "\n";
  reactions_ << "step,T";
  for (const auto& s : model_.supports)
    for (const char* c : {"Fx", "Fy", "Fz", "Mx", "My", "Mz"}) reactions_ << "," << s.name << "_" << c;
  reactions_ << "\n";
  for (auto* f : {&steps_, &tracked_, &reactions_}) *f << std::setprecision(12);
  for (const auto& c : model_.contributions) {
    if (c->tableName().empty()) {
      tables_.emplace_back();
      continue;
    }
    tables_.push_back(std::make_unique<std::ofstream>(fs::path(dir_) / c->tableName()));
    *tables_.back() << "step,T," << c->tableHeader() << "\n";
  }
}

void ResultsWriter::writeStatus(const std::string& text) {
  const fs::path tmp = fs::path(dir_) / "status.txt.tmp";
  {
    std::ofstream s(tmp);
    s << text << "\n";
  }
  fs::rename(tmp, fs::path(dir_) / "status.txt");
}

void ResultsWriter::writeInitial(const State& state) {
  if (root() && vtk_) writeVtk(0, 0.0, state);
}

void ResultsWriter::writeStep(const StepReport& step, const State& state, const std::vector<double>& r) {
  if (!root()) return;
  int linear = 0;
  for (const auto& h : step.history) linear += h.linearIterations;
  steps_ << step.step << "," << step.T << "," << step.cutLevel << "," << step.iterations << "," << step.passes << ","
         << step.history.back().residualNorm << "," << linear << "," << step.backtracks << "\n";
  tracked_ << step.step << "," << step.T;
  for (const auto& p : model_.tracked) {
    const Vec3d u = state.displacement(p.node);
    const Vec3d& psi = state.rotationVector[p.node];
    tracked_ << "," << u[0] << "," << u[1] << "," << u[2] << "," << psi[0] << "," << psi[1] << "," << psi[2];
  }
  tracked_ << "\n";
  reactions_ << step.step << "," << step.T;
  for (const auto& s : model_.supports) {
    double sum[6] = {0, 0, 0, 0, 0, 0};
    for (int n : s.nodes)
      for (int k = 0; k < 6; ++k) sum[k] += r[std::size_t(kDofsPerNode) * n + k];
    for (double v : sum) reactions_ << "," << v;
  }
  reactions_ << "\n";
  for (auto* f : {&steps_, &tracked_, &reactions_}) f->flush();
  for (std::size_t i = 0; i < model_.contributions.size(); ++i) {
    if (!tables_[i]) continue;
    for (const auto& row : model_.contributions[i]->tableRows()) *tables_[i] << step.step << "," << step.T << "," << row << "\n";
    tables_[i]->flush();
  }
  if (vtk_) writeVtk(step.step, step.T, state);
}

void ResultsWriter::writeVtk(int step, double T, const State& state) {
  VtkMesh mesh;
  for (const auto& c : model_.contributions) c->appendVtk(state, mesh);
  char name[64];
  std::snprintf(name, sizeof name, "vtk/step_%05d.vtu", step);
  std::ofstream f(fs::path(dir_) / name);
  f << std::setprecision(12);
  f << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
    << "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" << mesh.points.size() << "\" NumberOfCells=\""
    << mesh.cells.size() << "\">\n<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const auto& p : mesh.points) f << p[0] << " " << p[1] << " " << p[2] << "\n";
  f << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const auto& c : mesh.cells) {
    for (int i : c) f << i << " ";
    f << "\n";
  }
  f << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  long long off = 0;
  for (const auto& c : mesh.cells) f << (off += c.size()) << "\n";
  f << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (int t : mesh.cellTypes) f << t << "\n";
  f << "</DataArray>\n</Cells>\n<PointData Vectors=\"displacement\">\n"
    << "<DataArray type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const auto& u : mesh.pointDisplacement) f << u[0] << " " << u[1] << " " << u[2] << "\n";
  f << "</DataArray>\n<DataArray type=\"Float64\" Name=\"contact force\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const auto& u : mesh.pointForce) f << u[0] << " " << u[1] << " " << u[2] << "\n";
  f << "</DataArray>\n</PointData>\n<CellData>\n<DataArray type=\"Int32\" Name=\"beam\" format=\"ascii\">\n";
  for (int b : mesh.cellBeam) f << b << "\n";
  f << "</DataArray>\n<DataArray type=\"Int32\" Name=\"element\" format=\"ascii\">\n";
  for (int e : mesh.cellElement) f << e << "\n";
  f << "</DataArray>\n</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  f.close();
  if (!f) throw std::runtime_error(std::string("cannot write ") + name);
  vtkFiles_.emplace_back(T, name);
  writePvd();
}

void ResultsWriter::writePvd() {
  const fs::path tmp = fs::path(dir_) / "results.pvd.tmp";
  {
    std::ofstream f(tmp);
    f << std::setprecision(12)
      << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n";
    for (const auto& [T, file] : vtkFiles_)
      f << "<DataSet timestep=\"" << T << "\" part=\"0\" file=\"" << file << "\"/>\n";
    f << "</Collection>\n</VTKFile>\n";
  }
  fs::rename(tmp, fs::path(dir_) / "results.pvd");
}

void ResultsWriter::writeSummary(const RunSummary& summary) {
  if (!root()) return;
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const fs::path tmp = fs::path(dir_) / "summary.csv.tmp";
  {
    std::ofstream f(tmp);
    f << "completed,last_T,steps,newton_iterations,max_newton_per_step,passes,solve_seconds,peak_memory_mb\n"
      << (summary.run.completed ? 1 : 0) << ',' << summary.run.lastT << ',' << summary.run.steps << ','
      << summary.run.newtonIterations << ',' << summary.maxIterationsPerStep << ',' << summary.passes << ','
      << summary.solveSeconds << ',' << usage.ru_maxrss / 1024.0 << '\n';
  }
  fs::rename(tmp, fs::path(dir_) / "summary.csv");
}

void ResultsWriter::finish(const RunReport& run, const std::string& timerReport) {
  if (!root()) return;
  {
    std::ofstream t(fs::path(dir_) / "timers.txt");
    t << timerReport;
  }
  std::ostringstream s;
  if (run.completed)
    s << "complete: " << run.steps << " steps, " << run.newtonIterations << " Newton iterations, T = " << run.lastT;
  else
    s << "incomplete: stopped at T = " << run.lastT << " after " << run.steps << " converged steps; " << run.failure;
  writeStatus(s.str());
}

}  // namespace bc::core
