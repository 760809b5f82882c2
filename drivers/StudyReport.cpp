#include "StudyReport.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "Study.hpp"
#include "core/Faults.hpp"
#include "core/Provenance.hpp"

namespace bc::drivers::study {

namespace fs = std::filesystem;
using Teuchos::ParameterList;

namespace {

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> f;
  std::stringstream ls(line);
  for (std::string x; std::getline(ls, x, ',');) f.push_back(x);
  if (!line.empty() && line.back() == ',') f.push_back("");
  return f;
}

std::string csvField(std::string s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
  return q + "\"";
}

std::string jsonString(const std::string& s) {
  std::string q = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}

// Reads the outputs of a finished case at load factor `atT`; empty text where the run did not get there.
std::map<std::string, std::string> readOutputs(const fs::path& dir, const std::vector<Output>& outputs, double atT) {
  std::map<std::string, std::string> out;
  auto atRow = [&](double T) { return isAtT(T, atT); };
  std::ifstream tracked(dir / "tracked_points.csv");
  std::string line;
  std::vector<std::string> header;
  if (std::getline(tracked, line)) header = splitCsv(line);
  while (std::getline(tracked, line)) {
    const auto f = splitCsv(line);
    if (f.size() != header.size() || !atRow(std::stod(f[1]))) continue;
    for (const Output& o : outputs) {
      if (o.trackedPoint.empty()) continue;
      const auto col = std::find(header.begin(), header.end(), o.trackedPoint + "_" + o.component);
      if (col != header.end()) out[o.name] = f[col - header.begin()];
    }
  }
  std::ifstream contact(dir / "contact_points.csv");
  bool any = false;
  std::map<std::string, double> sums;
  if (std::getline(contact, line)) {
    while (std::getline(contact, line)) {
      const auto f = splitCsv(line);
      if (f.size() < 17 || !atRow(std::stod(f[1]))) continue;
      any = true;
      if (f[16] != "1") continue;
      sums["Normal Force"] += std::stod(f[11]);
      sums["Tangential Force 1"] += std::abs(std::stod(f[12]));
      sums["Tangential Force 2"] += std::abs(std::stod(f[13]));
      sums["Active Points"] += 1;
      for (int k : {14, 15}) {
        if (f[k] == "stick") sums["Stick Lines"] += 1;
        if (f[k] == "slip") sums["Slip Lines"] += 1;
      }
    }
  }
  // A step with no contact points listed at all still has zero contact forces if it was reached.
  bool reached = any;
  if (!reached) {
    std::ifstream steps(dir / "steps.csv");
    std::getline(steps, line);
    while (std::getline(steps, line)) {
      const auto f = splitCsv(line);
      if (f.size() > 1 && atRow(std::stod(f[1]))) reached = true;
    }
  }
  for (const Output& o : outputs)
    if (!o.contact.empty() && reached) out[o.name] = numberText(sums[o.contact]);
  return out;
}

// The run figures of a case, from its summary.csv.
const std::vector<std::string> kRunColumns = {"newton_iterations", "max_newton_per_step", "passes", "steps", "last_T",
                                              "solve_seconds",     "peak_memory_mb"};

std::string tableHeader(const StudyResults& r) {
  std::ostringstream csv;
  csv << "case,group";
  for (const auto& c : r.deck.columns) csv << ',' << csvField(c);
  csv << ",status";
  for (const auto& o : r.deck.outputs) csv << ',' << csvField(o.name);
  if (r.reference)
    for (const auto& o : r.deck.outputs)
      csv << ',' << csvField(o.name + " error") << ',' << csvField(o.name + " relative error");
  for (const auto& c : kRunColumns) csv << ',' << c;
  if (r.timing) csv << ",solve_seconds_median,solve_seconds_min,solve_seconds_max,timing_runs";
  csv << ",version,commit,cause\n";
  return csv.str();
}

// Error against the reference: y - y_ref and (y - y_ref) / |y_ref| (empty where either is missing).
void writeErrors(std::ostream& csv, const std::vector<Output>& outputs,
                 const std::map<std::string, std::string>& values,
                 const std::map<std::string, std::string>& referenceValues) {
  for (const auto& o : outputs) {
    const auto y = values.find(o.name), r = referenceValues.find(o.name);
    if (y == values.end() || r == referenceValues.end()) {
      csv << ",,";
      continue;
    }
    const double e = std::stod(y->second) - std::stod(r->second), ref = std::abs(std::stod(r->second));
    csv << ',' << numberText(e) << ',' << (ref > 0.0 ? numberText(e / ref) : "");
  }
}

// --timing: the median, least and largest solve time of the case's complete runs, and their number.
void writeTimings(std::ostream& csv, const Case& c) {
  std::vector<double> t = c.timings;
  std::sort(t.begin(), t.end());
  const std::size_t n = t.size();
  if (n == 0) csv << ",,,,0";
  else
    csv << ',' << numberText(n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2])) << ',' << numberText(t.front()) << ','
        << numberText(t.back()) << ',' << n;
}

// Case `c`'s figures: read from its results directory, and kept once the case is recorded (its
// status is more than "not run": its results no longer change).
const CaseFigures& figuresOf(const StudyResults& r, const Case& c, CaseFigures& scratch) {
  const auto kept = r.figures.find(c.index);
  if (kept != r.figures.end()) return kept->second;
  CaseFigures f;
  f.outputs = readOutputs(c.dir, r.deck.outputs, r.deck.atT);
  f.summary = readSummary(c.dir);
  const auto provenance = core::readFieldLines(readText(c.dir / "status.txt"));
  f.version = core::field(provenance, "version");
  f.commit = core::field(provenance, "commit");
  if (c.status != "not run") return r.figures[c.index] = std::move(f);
  scratch = std::move(f);
  return scratch;
}

void writeRow(std::ostream& csv, const StudyResults& r, const Case& c,
              const std::map<std::string, std::string>& referenceValues) {
  CaseFigures scratch;
  const CaseFigures& figures = figuresOf(r, c, scratch);
  const auto& values = figures.outputs;
  const auto& summary = figures.summary;
  csv << c.index << ',' << csvField(c.group);
  for (const auto& col : r.deck.columns) {
    const auto it = c.values.find(col);
    csv << ',' << (it == c.values.end() ? "" : csvField(it->second));
  }
  csv << ',' << c.status;
  for (const auto& o : r.deck.outputs) {
    const auto it = values.find(o.name);
    csv << ',' << (it == values.end() ? "" : it->second);
  }
  if (r.reference) writeErrors(csv, r.deck.outputs, values, referenceValues);
  for (const auto& col : kRunColumns) {
    const auto it = summary.find(col);
    csv << ',' << (it == summary.end() ? "" : it->second);
  }
  if (r.timing) writeTimings(csv, c);
  // What ran the case (a case kept from an earlier study may have run on another build).
  csv << ',' << csvField(figures.version) << ',' << csvField(figures.commit);
  csv << ',' << csvField(c.cause) << '\n';
}

// A parameter of the base deck as text ("" when absent), read without changing the deck.
std::string baseFact(const ParameterList& b, const std::string& list, const std::string& key) {
  const ParameterList* l = &b;
  std::stringstream path(list);
  for (std::string part; std::getline(path, part, '/');) {
    if (!l->isSublist(part)) return "";
    l = &l->sublist(part);
  }
  if (!l->isParameter(key)) return "";
  std::ostringstream v;
  v << l->getEntry(key).getAny();
  return v.str();
}

void jsonGroups(std::ostream& j, const std::vector<Group>& groups) {
  for (std::size_t g = 0; g < groups.size(); ++g) {
    j << (g ? ",\n" : "\n") << "    {\"name\": " << jsonString(groups[g].name) << ", \"variables\": [";
    for (std::size_t v = 0; v < groups[g].variables.size(); ++v) {
      const Variable& var = groups[g].variables[v];
      j << (v ? ", " : "") << "{\"name\": " << jsonString(var.name) << ", \"path\": " << jsonString(var.path)
        << ", \"values\": [";
      for (std::size_t k = 0; k < var.values.size(); ++k) j << (k ? ", " : "") << jsonString(var.values[k]);
      j << "]}";
    }
    j << "]}";
  }
}

// The units of the varied parameters and outputs that have one.
void jsonUnits(std::ostream& j, const StudyDeck& deck) {
  bool first = true;
  auto unit = [&](const std::string& name, const std::string& u) {
    if (u.empty()) return;
    j << (first ? "" : ", ") << jsonString(name) << ": " << jsonString(u);
    first = false;
  };
  for (const Group& g : deck.groups)
    for (const Variable& v : g.variables) unit(v.name, v.unit);
  for (const Output& o : deck.outputs) unit(o.name, o.unit);
}

// The outputs' names, then where each is read from.
void jsonOutputs(std::ostream& j, const std::vector<Output>& outputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) j << (i ? ", " : "") << jsonString(outputs[i].name);
  j << "],\n  \"output_sources\": {";
  for (std::size_t i = 0; i < outputs.size(); ++i)
    j << (i ? ", " : "") << jsonString(outputs[i].name)
      << ": {\"tracked_point\": " << jsonString(outputs[i].trackedPoint)
      << ", \"component\": " << jsonString(outputs[i].component) << ", \"contact\": " << jsonString(outputs[i].contact)
      << "}";
}

void jsonPlots(std::ostream& j, const std::vector<Plot>& plots) {
  for (std::size_t i = 0; i < plots.size(); ++i) {
    const Plot& p = plots[i];
    j << (i ? ",\n" : "\n") << "    {\"name\": " << jsonString(p.name) << ", \"x\": " << jsonString(p.x)
      << ", \"y\": " << jsonString(p.y) << ", \"series\": " << jsonString(p.series)
      << ", \"relative_to\": " << jsonString(p.relativeTo) << ", \"log_x\": " << (p.logX ? "true" : "false")
      << ", \"error\": " << (p.error ? "true" : "false") << ", \"published_x\": [";
    for (std::size_t k = 0; k < p.publishedX.size(); ++k) j << (k ? ", " : "") << numberText(p.publishedX[k]);
    j << "], \"published_y\": [";
    for (std::size_t k = 0; k < p.publishedY.size(); ++k) j << (k ? ", " : "") << numberText(p.publishedY[k]);
    j << "], \"published_labels\": [";
    for (std::size_t k = 0; k < p.publishedLabels.size(); ++k) j << (k ? ", " : "") << jsonString(p.publishedLabels[k]);
    j << "]}";
  }
}

}  // namespace

std::map<std::string, std::string> readSummary(const fs::path& dir) {
  std::map<std::string, std::string> s;
  std::ifstream f(dir / "summary.csv");
  std::string h, v;
  if (!std::getline(f, h) || !std::getline(f, v)) return s;
  const auto hs = splitCsv(h), vs = splitCsv(v);
  for (std::size_t i = 0; i < hs.size() && i < vs.size(); ++i) s[hs[i]] = vs[i];
  return s;
}

// The last non-empty line of a file that starts with `prefix` (any line when empty).
std::string lastLine(const fs::path& file, const std::string& prefix) {
  std::ifstream f(file);
  std::string line, last;
  while (std::getline(f, line))
    if (!line.empty() && line.rfind(prefix, 0) == 0) last = line;
  return last;
}

// A run's status: the first line of its status.txt (warnings and notes follow it).
std::string runStatusLine(const fs::path& dir) {
  std::ifstream f(dir / "status.txt");
  std::string line;
  std::getline(f, line);
  return line;
}

std::string readText(const fs::path& file) {
  std::ifstream f(file);
  if (!f) return "";
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

void writeCaseTable(const StudyResults& r) {
  std::ostringstream csv;
  csv << tableHeader(r);
  CaseFigures scratch;
  const auto referenceValues = r.reference && r.reference->status == "complete"
                                   ? figuresOf(r, *r.reference, scratch).outputs
                                   : std::map<std::string, std::string>{};
  for (const Case& c : r.all) writeRow(csv, r, c, referenceValues);
  r.out.add("cases.csv");
  core::writeFileAtomically(r.dir / "cases.csv", csv.str());
}

void writeStudyJson(const StudyResults& r, int parallel, const std::string& caseProcesses, int processesStarted) {
  const StudyDeck& deck = r.deck;
  const ParameterList& b = *deck.baseDeck;
  r.out.add("study.json");
  std::ofstream j(r.dir / "study.json");
  j << "{\n  \"title\": " << jsonString(deck.study->get<std::string>("Title"))
    << ",\n  \"base_deck\": " << jsonString(deck.base.string()) << ",\n  \"at_T\": " << deck.atT
    << ",\n  \"reference_group\": " << jsonString(deck.study->get<std::string>("Reference Group"))
    << ",\n  \"timing_runs\": " << r.timing << ",\n  \"parallel\": " << parallel
    << ",\n  \"case_processes\": " << jsonString(caseProcesses) << ",\n  \"processes_started\": " << processesStarted
    << ",\n  \"base\": {\"strategy\": " << jsonString(baseFact(b, "Contact/Enforcement", "Type"))
    << ", \"beams\": " << (b.isSublist("Beams") ? b.sublist("Beams").numParams() : 0)
    << ", \"increments\": " << jsonString(baseFact(b, "Load Stepping", "Number of Increments"))
    << "},\n  \"groups\": [";
  jsonGroups(j, deck.groups);
  j << "\n  ],\n  \"units\": {";
  jsonUnits(j, deck);
  j << "},\n  \"columns\": [";
  for (std::size_t i = 0; i < deck.columns.size(); ++i) j << (i ? ", " : "") << jsonString(deck.columns[i]);
  j << "],\n  \"outputs\": [";
  jsonOutputs(j, deck.outputs);
  j << "},\n  \"plots\": [";
  jsonPlots(j, deck.plots);
  j << "\n  ],\n  \"provenance\": {";
  const auto& provenance = r.provenance;
  for (std::size_t i = 0; i < provenance.size(); ++i)
    j << (i ? ", " : "") << jsonString(provenance[i].first) << ": " << jsonString(provenance[i].second);
  j << "}\n}\n";
}

bool reportModulesPresent() {
  // Exit code 4: a module is missing (the script said which); any other failure shows in the report.
  return runProgram({"/usr/bin/python3", scriptPath("study_report.py"), "--check-modules"}) != 4;
}

int writeReport(const StudyResults& r, bool quiet) {
  const std::string script = scriptPath("study_report.py");
  r.out.add("report.md");
  // The figures the script writes are named after they appear (it names them from the plots).
  std::set<std::string> before;
  for (const auto& e : fs::directory_iterator(r.dir)) before.insert(e.path().filename().string());
  std::vector<std::string> command = {"/usr/bin/python3", script, r.dir.string()};
  if (quiet) command.insert(command.begin() + 2, "--quiet");
  const int code = runProgram(command);
  for (const auto& e : fs::directory_iterator(r.dir))
    if (!before.count(e.path().filename().string()) && fs::is_regular_file(fs::symlink_status(e.path())))
      r.out.adopt(e.path().filename().string());
  return code;
}

}  // namespace bc::drivers::study
