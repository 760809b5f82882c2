#include "Study.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>

#include <set>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include <Teuchos_XMLParameterListHelpers.hpp>

#include "core/Faults.hpp"
#include "core/Parameters.hpp"
#include "input/XmlDeck.hpp"
#include "input/Plugins.hpp"
#include "core/OutputDirectory.hpp"

extern char** environ;

namespace bc::drivers {

namespace fs = std::filesystem;
using core::InputError;
using Teuchos::Array;
using Teuchos::ParameterList;

namespace {

// One varied parameter: its column name, its path in the base deck and its values as text
// (kept as the user wrote them for the table) with the XML type they came with.
struct Variable {
  std::string name, path, unit;
  std::vector<std::string> values;
  enum class Kind { Double, Int, String, Bool } kind = Kind::Double;
};

struct Group {
  std::string name;
  std::vector<Variable> variables;
};

// An output quantity read from a case's results at the study's "At T".
struct Output {
  std::string name;
  std::string trackedPoint, component;  // a tracked point's component, or
  std::string contact;                  // a contact total
  std::string unit;                     // for the report's axes and tables
};

struct Plot {
  std::string name, x, y, series, relativeTo;
  bool logX = false;
  bool error = false;  // |relative error| against the reference on log-log axes, with fitted slopes
  // Published values drawn over the cases: at (x, y), or as horizontal lines without x; one label each.
  std::vector<double> publishedX, publishedY;
  std::vector<std::string> publishedLabels;
};

struct Case {
  int index = 0;
  std::string group;
  std::map<std::string, std::string> values;  // variable name -> value text
  std::vector<std::pair<const Variable*, std::string>> settings;
  fs::path dir;
  std::string status = "not run", cause;
  int exitCode = -1;
  bool kept = false;  // complete from an earlier run of the study (same deck)
  std::vector<double> timings;  // --timing: the solve time of each complete run
};

const std::vector<std::string> kContactQuantities = {"Normal Force", "Tangential Force 1", "Tangential Force 2",
                                                     "Active Points", "Stick Lines", "Slip Lines"};
const std::vector<std::string> kComponents = {"ux", "uy", "uz", "rx", "ry", "rz"};

std::string text(double v) {
  std::ostringstream s;
  s.precision(12);
  s << v;
  return s.str();
}

// Calls fn(name, path, sublist) for every entry of `list` (at `path`); each must be a sublist.
template <class F>
void forEachSublist(const ParameterList& list, const std::string& path, const std::string& what, F fn) {
  for (auto it = list.begin(); it != list.end(); ++it) {
    const std::string name = list.name(it), sub = path + "/" + name;
    if (!list.isSublist(name)) throw InputError("parameter \"" + sub + "\" must be a sublist (" + what + ")");
    fn(name, sub, list.sublist(name));
  }
}

// Rejects keys of `list` (at `path`) other than `known`.
void onlyKeys(const ParameterList& list, const std::string& path, const std::vector<std::string>& known) {
  for (auto it = list.begin(); it != list.end(); ++it)
    if (std::find(known.begin(), known.end(), list.name(it)) == known.end())
      throw InputError("parameter \"" + path + "/" + list.name(it) + "\" is not known; valid parameters here are " +
                       core::joinNames(known));
}

// A string parameter of `list` (at `path`); empty when optional and absent.
std::string stringParameter(const ParameterList& list, const std::string& path, const std::string& key, bool required) {
  if (!list.isParameter(key)) {
    if (required) throw InputError("missing required parameter \"" + path + "/" + key + "\"");
    return "";
  }
  if (!list.isType<std::string>(key)) throw InputError("parameter \"" + path + "/" + key + "\" must be a string");
  return list.get<std::string>(key);
}

Variable readVariable(const ParameterList& v, const std::string& name, const std::string& path) {
  Variable var;
  var.name = name;
  for (auto it = v.begin(); it != v.end(); ++it) {
    const std::string& key = v.name(it);
    if (key != "Path" && key != "Values" && key != "Unit")
      throw InputError("parameter \"" + path + "/" + key +
                       "\" is not known; a varied parameter has \"Path\", \"Values\" and optionally \"Unit\"");
  }
  if (!v.isParameter("Path") || !v.isType<std::string>("Path"))
    throw InputError("missing required parameter \"" + path + "/Path\" (string: a parameter path in the base deck, "
                     "e.g. \"Contact/Enforcement/Type\")");
  var.path = v.get<std::string>("Path");
  var.unit = stringParameter(v, path, "Unit", false);
  if (!v.isParameter("Values"))
    throw InputError("missing required parameter \"" + path + "/Values\" (Array(double), Array(int) or Array(string))");
  if (v.isType<Array<double>>("Values")) {
    for (double x : v.get<Array<double>>("Values")) var.values.push_back(text(x));
  } else if (v.isType<Array<int>>("Values")) {
    var.kind = Variable::Kind::Int;
    for (int x : v.get<Array<int>>("Values")) var.values.push_back(std::to_string(x));
  } else if (v.isType<Array<std::string>>("Values")) {
    var.kind = Variable::Kind::String;
    for (const auto& x : v.get<Array<std::string>>("Values")) var.values.push_back(x);
  } else {
    throw InputError("parameter \"" + path + "/Values\" must be Array(double), Array(int) or Array(string)");
  }
  if (var.values.empty()) throw InputError("parameter \"" + path + "/Values\" is empty");
  return var;
}

// Sets `path` ("A/B/name") in `deck` to the value, keeping the type the base deck has there.
void setByPath(ParameterList& deck, const Variable& var, const std::string& value, const std::string& where) {
  const auto slash = var.path.rfind('/');
  ParameterList* list = &deck;
  if (slash != std::string::npos) {
    try {
      list = &input::sublistAtPath(deck, var.path.substr(0, slash));
    } catch (const InputError& e) {
      throw InputError(where + ": " + e.what());
    }
  }
  const std::string rest = var.path.substr(slash == std::string::npos ? 0 : slash + 1);
  const bool exists = list->isParameter(rest);
  if (exists && list->isSublist(rest))
    throw InputError(where + ": path \"" + var.path + "\" names a sublist, not a parameter");
  if (var.kind == Variable::Kind::String) {
    if (exists && list->isType<bool>(rest)) list->set(rest, value == "true" || value == "1");
    else list->set(rest, value);
  } else if ((exists && list->isType<int>(rest)) || (!exists && var.kind == Variable::Kind::Int)) {
    const double x = std::stod(value);
    if (x != std::floor(x)) throw InputError(where + ": \"" + var.path + "\" takes whole numbers, got " + value);
    list->set(rest, static_cast<int>(x));
  } else {
    list->set(rest, std::stod(value));
  }
}

// setByPath with the conversion errors of a mistyped value named.
void setValue(ParameterList& deck, const Variable& var, const std::string& value, const std::string& where) {
  try {
    setByPath(deck, var, value, where);
  } catch (const std::invalid_argument&) {
    throw InputError(where + ": \"" + var.path + "\" takes a number, got \"" + value + "\"");
  } catch (const std::out_of_range&) {
    throw InputError(where + ": \"" + var.path + "\" value " + value + " is out of range");
  }
}

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
  auto atRow = [&](double T) { return std::abs(T - atT) <= 1e-9 * std::max(1.0, std::abs(atT)); };
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
    if (!o.contact.empty() && reached) out[o.name] = text(sums[o.contact]);
  return out;
}

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
std::string lastLine(const fs::path& file, const std::string& prefix = "") {
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

std::string selfExecutable() {
  std::error_code ec;
  const auto p = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error("cannot locate the beamcontact executable (/proc/self/exe): " + ec.message());
  return p.string();
}

// Starts `command` (program path and arguments, no shell); with `log`, its stdout and stderr go to
// that file.
// With `ownGroup` it runs in a process group of its own, so a Ctrl-C at the terminal reaches the study
// alone, which then stops its cases with one SIGTERM each (two signals would end a case at once).
pid_t spawn(const std::vector<std::string>& command, const std::string& log = "", bool ownGroup = false) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (!log.empty()) {
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
  }
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  if (ownGroup) {
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
    posix_spawnattr_setpgroup(&attributes, 0);
  }
  std::vector<std::string> args = command;
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, argv[0], &actions, &attributes, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  if (rc != 0) throw std::runtime_error("cannot start " + command[0] + ": " + std::strerror(rc));
  return pid;
}

// The exit code of a finished process, 128 + the signal when one killed it.
int exitCode(int status) {
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

}  // namespace

std::string scriptPath(const std::string& name) {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error("cannot locate the beamcontact executable (/proc/self/exe): " + ec.message());
  const fs::path script = exe.parent_path().parent_path() / "share" / "beamcontact" / name;
  if (!fs::is_regular_file(script, ec))
    throw std::runtime_error("the helper script " + script.string() + " is missing (install or build BeamContact again)");
  return script.string();
}

namespace {

pid_t launch(const std::string& exe, const Case& c, const std::vector<std::string>& plugins, bool overwrite) {
  std::vector<std::string> command = {exe, "run", (c.dir / "deck.xml").string(), "--output", c.dir.string(), "--quiet"};
  if (overwrite) command.push_back("--overwrite");
  for (const auto& p : plugins) {
    command.push_back("--plugin");
    command.push_back(p);
  }
  return spawn(command, (c.dir / "log.txt").string(), true);
}

std::string describe(const Case& c, const std::vector<std::string>& columns) {
  std::string s = c.group;
  for (const auto& name : columns) {
    const auto it = c.values.find(name);
    if (it != c.values.end() && s.size() < 70) s += " " + name + "=" + it->second;
  }
  return s;
}

}  // namespace

int runProgram(const std::vector<std::string>& command) {
  const pid_t pid = spawn(command);
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) throw std::runtime_error("waiting for " + command[0] + " failed");
  return exitCode(status);
}

int runStudy(const std::string& studyFile, const StudyOptions& options) {
  // Plug-ins as absolute paths: the cases run in their own folders.
  std::vector<std::string> plugins;
  for (const auto& p : options.plugins) {
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) throw InputError("plug-in \"" + p + "\" does not exist (or is not a file)");
    plugins.push_back(fs::canonical(p).string());
  }
  // Each case is its own process; under mpirun every rank would run the whole study.
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    const char* size = std::getenv(var);
    if (size && std::atoi(size) > 1)
      throw InputError("run the study without mpirun: it starts each case as a process of its own");
  }
  if (!fs::exists(studyFile)) throw InputError("study deck \"" + studyFile + "\" does not exist");
  const Teuchos::RCP<ParameterList> study = Teuchos::rcp(new ParameterList(input::readParameterXmlFile(studyFile)));
  const std::string root = "Study";
  const std::string stem = fs::path(studyFile).stem().string();

  core::ParameterSpec spec;
  spec.addRequired("Base Deck", std::string(), "the deck every case starts from, relative to the study deck");
  spec.add("Title", stem, "title of the report");
  spec.add("Output Directory", "results/" + stem, "the study directory (--output overrides it)");
  spec.add("Parallel Cases", 0, "cases run at once; 0: one per core", core::atLeast(0), ">= 0");
  spec.add("At T", 1.0, "load factor at which the outputs are read", core::inRange(0.0, 1.0), "in (0, 1]");
  spec.add("Reference Group", std::string(),
           "a group of one case (e.g. the Lagrange multiplier run) that every case's outputs are compared with: "
           "cases.csv gets each output's error and relative error against it; empty: none");
  ParameterList anyList;
  spec.addSublist("Cases", anyList, "groups of cases: each a sublist of varied parameters (Path, Values)");
  spec.addSublist("Outputs", anyList, "named outputs: {Tracked Point, Component} or {Contact}");
  spec.addSublist("Plots", anyList, "named plots: X, Y, optional Series, Relative To Group, Log X");
  spec.apply(*study, root);

  const fs::path base = (fs::path(studyFile).parent_path() / study->get<std::string>("Base Deck")).lexically_normal();
  if (!fs::exists(base)) throw InputError("parameter \"" + root + "/Base Deck\": file \"" + base.string() + "\" does not exist");
  const Teuchos::RCP<ParameterList> baseDeck = Teuchos::rcp(new ParameterList(input::readParameterXmlFile(base.string())));
  // The base deck's Plugins must be among --plugin; they become absolute paths with their digests, so each
  // case's copy of the deck names exactly what runs.
  input::checkDeckPlugins(*baseDeck, base.string(), options.plugins);
  const double atT = study->get<double>("At T");

  // Groups and their cases.
  std::vector<Group> groups;
  std::vector<std::string> columns;
  forEachSublist(study->sublist("Cases"), root + "/Cases", "a group of cases",
                 [&](const std::string& gname, const std::string& gpath, const ParameterList& gl) {
                   Group g{gname, {}};
                   forEachSublist(gl, gpath, "a varied parameter with \"Path\" and \"Values\"",
                                  [&](const std::string& vname, const std::string& vpath, const ParameterList& v) {
                                    g.variables.push_back(readVariable(v, vname, vpath));
                                    if (std::find(columns.begin(), columns.end(), vname) == columns.end())
                                      columns.push_back(vname);
                                  });
                   groups.push_back(std::move(g));
                 });
  if (groups.empty()) throw InputError("parameter \"" + root + "/Cases\" has no groups: nothing to run");

  std::vector<Output> outputs;
  forEachSublist(study->sublist("Outputs"), root + "/Outputs", "an output",
                 [&](const std::string& name, const std::string& path, const ParameterList& o) {
                   onlyKeys(o, path, {"Contact", "Tracked Point", "Component", "Unit"});
                   Output out;
                   out.name = name;
                   out.unit = stringParameter(o, path, "Unit", false);
                   out.contact = stringParameter(o, path, "Contact", false);
                   out.trackedPoint = stringParameter(o, path, "Tracked Point", false);
                   if (!out.contact.empty()) {
                     if (!o.isParameter("Unit") && out.contact.find("Force") != std::string::npos) out.unit = "force";
                     if (std::find(kContactQuantities.begin(), kContactQuantities.end(), out.contact) ==
                         kContactQuantities.end())
                       throw InputError("parameter \"" + path + "/Contact\": \"" + out.contact + "\" is not one of " +
                                        core::joinNames(kContactQuantities));
                   } else if (!out.trackedPoint.empty()) {
                     out.component = stringParameter(o, path, "Component", true);
                     if (std::find(kComponents.begin(), kComponents.end(), out.component) == kComponents.end())
                       throw InputError("parameter \"" + path + "/Component\" must be one of " +
                                        core::joinNames(kComponents));
                     if (!o.isParameter("Unit")) out.unit = out.component[0] == 'u' ? "length" : "rad";
                   } else {
                     throw InputError("parameter \"" + path + "\" needs \"Contact\" (" +
                                      core::joinNames(kContactQuantities) + ") or \"Tracked Point\" with \"Component\"");
                   }
                   outputs.push_back(out);
                 });

  std::vector<Plot> plots;
  auto isColumn = [&](const std::string& c) { return std::find(columns.begin(), columns.end(), c) != columns.end(); };
  auto isOutput = [&](const std::string& c) {
    return std::any_of(outputs.begin(), outputs.end(), [&](const Output& o) { return o.name == c; }) ||
           c == "newton_iterations" || c == "solve_seconds" || c == "passes" || c == "max_newton_per_step";
  };
  forEachSublist(study->sublist("Plots"), root + "/Plots", "a plot",
                 [&](const std::string& name, const std::string& path, const ParameterList& p) {
                   onlyKeys(p, path,
                            {"X", "Y", "Series", "Relative To Group", "Log X", "Error", "Published X", "Published Y",
                             "Published Labels"});
                   Plot plot;
                   plot.name = name;
                   plot.x = stringParameter(p, path, "X", true);
                   plot.y = stringParameter(p, path, "Y", true);
                   plot.series = stringParameter(p, path, "Series", false);
                   plot.relativeTo = stringParameter(p, path, "Relative To Group", false);
                   if (p.isParameter("Log X")) {
                     if (!p.isType<bool>("Log X")) throw InputError("parameter \"" + path + "/Log X\" must be a bool");
                     plot.logX = p.get<bool>("Log X");
                   }
                   auto numbers = [&](const std::string& key) {
                     std::vector<double> v;
                     if (!p.isParameter(key)) return v;
                     if (!p.isType<Array<double>>(key))
                       throw InputError("parameter \"" + path + "/" + key + "\" must be Array(double)");
                     for (double x : p.get<Array<double>>(key)) v.push_back(x);
                     return v;
                   };
                   plot.publishedX = numbers("Published X");
                   plot.publishedY = numbers("Published Y");
                   if (p.isParameter("Published Labels")) {
                     if (!p.isType<Array<std::string>>("Published Labels"))
                       throw InputError("parameter \"" + path + "/Published Labels\" must be Array(string)");
                     for (const auto& l : p.get<Array<std::string>>("Published Labels"))
                       plot.publishedLabels.push_back(l);
                   }
                   const std::size_t np = plot.publishedY.size();
                   if ((!plot.publishedX.empty() && plot.publishedX.size() != np) ||
                       (!plot.publishedLabels.empty() && plot.publishedLabels.size() != np) ||
                       (np == 0 && (!plot.publishedX.empty() || !plot.publishedLabels.empty())))
                     throw InputError("parameter \"" + path +
                                      "/Published Y\": give one value per published point, and as many \"Published X\" "
                                      "(or none: horizontal lines) and \"Published Labels\" (or none)");
                   if (p.isParameter("Error")) {
                     if (!p.isType<bool>("Error")) throw InputError("parameter \"" + path + "/Error\" must be a bool");
                     plot.error = p.get<bool>("Error");
                     if (plot.error && plot.relativeTo.empty())
                       plot.relativeTo = study->get<std::string>("Reference Group");
                     if (plot.error && plot.relativeTo.empty())
                       throw InputError("parameter \"" + path + "/Error\": an error needs a reference; give \"" + path +
                                        "/Relative To Group\" or \"" + root + "/Reference Group\"");
                   }
                   if (!isColumn(plot.x))
                     throw InputError("parameter \"" + path + "/X\": \"" + plot.x + "\" is not a varied parameter");
                   if (!isOutput(plot.y))
                     throw InputError("parameter \"" + path + "/Y\": \"" + plot.y + "\" is not an output");
                   if (!plot.series.empty() && !isColumn(plot.series))
                     throw InputError("parameter \"" + path + "/Series\": \"" + plot.series + "\" is not a varied parameter");
                   if (!plot.relativeTo.empty() &&
                       std::none_of(groups.begin(), groups.end(), [&](const Group& g) { return g.name == plot.relativeTo; }))
                     throw InputError("parameter \"" + path + "/Relative To Group\": no group \"" + plot.relativeTo + "\"");
                   plots.push_back(plot);
                 });

  // Expand the groups and write each case's deck.
  const fs::path dir = options.output.empty() ? fs::path(study->get<std::string>("Output Directory")) : fs::path(options.output);
  if (std::error_code ec; fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw InputError("the study directory \"" + dir.string() + "\" is a file, not a directory; give " +
                     (options.output.empty() ? "\"" + root + "/Output Directory\"" : std::string("--output")) +
                     " a directory");
  core::OutputDirectory::Options where;
  where.overwrite = options.overwrite;
  where.pathFromDeck = options.output.empty();
  where.parameter = root + "/Output Directory";
  where.what = "study directory";
  core::OutputDirectory out(dir, where);
  // One study at a time in a directory: the manifest is locked (flock) while this study runs, and the
  // lock goes with the process, however it ends.
  {
    const int lock = ::open((dir / core::kManifestName).c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
    if (lock < 0 || flock(lock, LOCK_EX | LOCK_NB) != 0)
      throw InputError("study directory \"" + dir.string() + "\" is in use by another beamcontact study; wait for it "
                       "or choose another --output");
  }
  out.folder("cases/");
  out.removeLeftovers();
  std::vector<Case> all;
  for (const Group& g : groups) {
    std::vector<std::size_t> idx(g.variables.size(), 0);
    while (true) {
      Case c;
      c.index = static_cast<int>(all.size()) + 1;
      c.group = g.name;
      for (std::size_t k = 0; k < g.variables.size(); ++k) {
        c.values[g.variables[k].name] = g.variables[k].values[idx[k]];
        c.settings.push_back({&g.variables[k], g.variables[k].values[idx[k]]});
      }
      all.push_back(c);
      if (all.size() > 10000)
        throw InputError("the study has more than 10000 cases (group \"" + g.name +
                         "\" alone multiplies its value lists); split it into several studies");
      std::size_t k = 0;
      while (k < idx.size() && ++idx[k] == g.variables[k].values.size()) idx[k++] = 0;
      if (k == idx.size()) break;
    }
  }
  // The reference: a group of exactly one case.
  const std::string referenceGroup = study->get<std::string>("Reference Group");
  const Case* reference = nullptr;
  if (!referenceGroup.empty()) {
    const auto n = std::count_if(all.begin(), all.end(), [&](const Case& c) { return c.group == referenceGroup; });
    if (n != 1)
      throw InputError("parameter \"" + root + "/Reference Group\": " +
                       (n == 0 ? "no group \"" + referenceGroup + "\""
                               : "group \"" + referenceGroup + "\" has " + std::to_string(n) +
                                     " cases; the reference must be a group of one case"));
    reference = &*std::find_if(all.begin(), all.end(), [&](const Case& c) { return c.group == referenceGroup; });
  }
  const int timing = options.timing;
  // A case whose directory holds the same deck (same parameters, same base deck) and a complete run
  // is kept from an earlier run of the study; any other case directory is cleared and run again.
  // Case directories beyond this study's cases, and the last report, are from an earlier study.
  {
    // Only what the study's manifest names goes (a case folder with its own manifest: its listed files).
    for (const auto& entry : fs::directory_iterator(dir / "cases")) {
      const std::string n = entry.path().filename().string();
      const bool number = n.size() == 3 && n.find_first_not_of("0123456789") == std::string::npos;
      const std::string rel = "cases/" + n + "/";
      if ((!number || std::stoi(n) < 1 || std::stoi(n) > static_cast<int>(all.size())) && out.lists(rel))
        out.removeOwnFolder(rel);
    }
    out.removeOwn([](const std::string& name) {
      const fs::path p(name);
      return name.find('/') == std::string::npos &&
             (p.extension() == ".png" || p.extension() == ".pdf" || name == "report.md");
    });
  }
  int kept = 0;
  for (Case& c : all) {
    char name[16];
    std::snprintf(name, sizeof name, "%03d", c.index);
    c.dir = dir / "cases" / name;
    ParameterList deck(*baseDeck);
    for (const auto& [var, value] : c.settings)
      setValue(deck, *var, value, "case " + std::to_string(c.index) + " (group \"" + c.group + "\")");
    // The case's deck names its folder where a deck may (relative, no ".."), so it can be run again
    // by itself; otherwise it keeps the default (results/deck). The study runs it with --output.
    const bool deckMayName = c.dir.is_relative() && std::none_of(c.dir.begin(), c.dir.end(), [](const fs::path& part) {
                               return part == "..";
                             });
    if (deckMayName) deck.sublist("Output").set("Directory", c.dir.string());
    else deck.sublist("Output").remove("Directory", false);
    if (timing) deck.sublist("Output").set("Write VTK", false);  // fair timing: the method, not the output
    std::ostringstream xml;
    Teuchos::writeParameterListToXmlOStream(deck, xml);
    if (!timing && readText(c.dir / "deck.xml") == xml.str() &&
        runStatusLine(c.dir).rfind("complete", 0) == 0) {
      c.status = "complete";
      c.kept = true;
      c.exitCode = 0;
      ++kept;
      continue;
    }
    const std::string rel = "cases/" + std::string(name) + "/";
    if (out.lists(rel)) out.removeOwnFolder(rel);
    out.folder(rel);  // a case folder that is a link is refused: nothing is written through it
    core::OutputDirectory::Options caseWhere;
    caseWhere.overwrite = options.overwrite;
    caseWhere.what = "case directory";
    core::OutputDirectory caseDir(c.dir, caseWhere);
    caseDir.removeLeftovers();
    caseDir.add("deck.xml");
    caseDir.add("log.txt");
    core::writeFileAtomically(c.dir / "deck.xml", xml.str());
  }

  // The table, rewritten (atomically) after every finished case, so an interrupted study keeps it.
  const std::vector<std::string> runColumns = {"newton_iterations", "max_newton_per_step", "passes", "steps", "last_T",
                                               "solve_seconds", "peak_memory_mb"};
  auto writeTable = [&] {
    std::ostringstream csv;
    csv << "case,group";
    for (const auto& c : columns) csv << ',' << csvField(c);
    csv << ",status";
    for (const auto& o : outputs) csv << ',' << csvField(o.name);
    if (reference)
      for (const auto& o : outputs)
        csv << ',' << csvField(o.name + " error") << ',' << csvField(o.name + " relative error");
    for (const auto& r : runColumns) csv << ',' << r;
    if (timing) csv << ",solve_seconds_median,solve_seconds_min,solve_seconds_max,timing_runs";
    csv << ",cause\n";
    const auto referenceValues = reference && reference->status == "complete"
                                     ? readOutputs(reference->dir, outputs, atT)
                                     : std::map<std::string, std::string>{};
    for (const Case& c : all) {
      const auto values = readOutputs(c.dir, outputs, atT);
      const auto summary = readSummary(c.dir);
      csv << c.index << ',' << csvField(c.group);
      for (const auto& col : columns) {
        const auto it = c.values.find(col);
        csv << ',' << (it == c.values.end() ? "" : csvField(it->second));
      }
      csv << ',' << c.status;
      for (const auto& o : outputs) {
        const auto it = values.find(o.name);
        csv << ',' << (it == values.end() ? "" : it->second);
      }
      // Error against the reference: y - y_ref and (y - y_ref) / |y_ref| (empty where either is missing).
      if (reference)
        for (const auto& o : outputs) {
          const auto y = values.find(o.name), r = referenceValues.find(o.name);
          if (y == values.end() || r == referenceValues.end()) {
            csv << ",,";
            continue;
          }
          const double e = std::stod(y->second) - std::stod(r->second), ref = std::abs(std::stod(r->second));
          csv << ',' << text(e) << ',' << (ref > 0.0 ? text(e / ref) : "");
        }
      for (const auto& r : runColumns) {
        const auto it = summary.find(r);
        csv << ',' << (it == summary.end() ? "" : it->second);
      }
      if (timing) {
        std::vector<double> t = c.timings;
        std::sort(t.begin(), t.end());
        const std::size_t n = t.size();
        if (n == 0) csv << ",,,,0";
        else
          csv << ',' << text(n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2])) << ',' << text(t.front()) << ','
              << text(t.back()) << ',' << n;
      }
      csv << ',' << csvField(c.cause) << '\n';
    }
    out.add("cases.csv");
    core::writeFileAtomically(dir / "cases.csv", csv.str());
  };

  // Run them, several at once.
  int parallel = options.parallel > 0 ? options.parallel : study->get<int>("Parallel Cases");
  if (parallel <= 0) parallel = std::max(1u, std::thread::hardware_concurrency());
  if (timing) parallel = 1;  // one at a time: no case competes with another for the cores
  const std::string exe = selfExecutable();
  std::printf("study %s: %zu cases from %s, %d at a time, in %s", stem.c_str(), all.size(), base.string().c_str(),
              parallel, dir.string().c_str());
  if (timing) std::printf(" (timing: each case %d times, VTK off)", timing);
  if (kept) std::printf(" (%d complete from an earlier run, kept)", kept);
  std::printf("\n");
  std::fflush(stdout);
  // SIGTERM / SIGINT: the running cases get SIGTERM (each stops at its next Newton iteration and
  // records itself interrupted), are waited for and recorded; no new case starts.
  core::installSignalHandlers(false);
  std::map<pid_t, Case*> running;
  std::size_t next = 0, done = static_cast<std::size_t>(kept);
  int stopSignal = 0;
  const auto t0 = std::chrono::steady_clock::now();
  writeTable();
  while (done < all.size() && !(stopSignal && running.empty())) {
    while (!stopSignal && next < all.size() && static_cast<int>(running.size()) < parallel) {
      if (!all[next].kept) running[launch(exe, all[next], plugins, options.overwrite)] = &all[next];
      ++next;
    }
    if (running.empty()) break;
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (!stopSignal && core::receivedSignal()) {
      stopSignal = core::receivedSignal();
      std::printf("study %s: %s received; stopping the %zu running cases\n", stem.c_str(),
                  core::signalName(stopSignal).c_str(), running.size());
      std::fflush(stdout);
      for (const auto& [p, c] : running) kill(p, SIGTERM);
    }
    if (pid < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error("waiting for a case process failed");
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    Case& c = *it->second;
    running.erase(it);
    c.exitCode = exitCode(status);
    // Timing: a complete run adds its solve time; the case runs again until it has them all.
    if (timing && c.exitCode == 0) {
      const auto summary = readSummary(c.dir);
      const auto seconds = summary.find("solve_seconds");
      if (seconds != summary.end()) c.timings.push_back(std::stod(seconds->second));
      if (static_cast<int>(c.timings.size()) < timing && !stopSignal && !core::receivedSignal()) {
        running[launch(exe, c, plugins, options.overwrite)] = &c;
        continue;
      }
    }
    ++done;
    const std::string runStatus = runStatusLine(c.dir);
    // A run that recorded itself complete is complete, whatever ended its process afterwards (its
    // status is written last, after every other file).
    if (c.exitCode == 0 || runStatus.rfind("complete: ", 0) == 0) {
      c.status = "complete";
    } else if (runStatus.rfind("interrupted: ", 0) == 0 || (stopSignal && c.exitCode > 128)) {
      c.status = "interrupted";
      c.cause = runStatus.rfind("interrupted: ", 0) == 0 ? runStatus.substr(13)
                                                         : "stopped by " + core::signalName(c.exitCode - 128);
    } else {
      c.status = c.exitCode == 2 ? "incomplete" : c.exitCode == 1 ? "input error" : "failed";
      // The run's own record first (status.txt: "incomplete: <cause>"), else its one-line error.
      c.cause = runStatus.rfind("incomplete: ", 0) == 0 ? runStatus.substr(12) : lastLine(c.dir / "log.txt", "beamcontact: ");
      if (c.cause.empty()) c.cause = "exit code " + std::to_string(c.exitCode);
    }
    writeTable();
    const int width = 30, filled = static_cast<int>(width * done / all.size());
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("[%s%s] %3zu/%zu  %6.1f s  case %03d %-10s %s\n", std::string(filled, '#').c_str(),
                std::string(width - filled, '.').c_str(), done, all.size(), elapsed, c.index, c.status.c_str(),
                describe(c, columns).c_str());
    std::fflush(stdout);
  }
  if (stopSignal) {
    writeTable();
    std::printf("study %s: stopped by %s; %zu of %zu cases complete; run the study again to run the others\n",
                stem.c_str(), core::signalName(stopSignal).c_str(),
                static_cast<std::size_t>(std::count_if(all.begin(), all.end(), [](const Case& c) { return c.status == "complete"; })),
                all.size());
    std::fprintf(stderr, "beamcontact: study interrupted by %s; run it again to run the cases not complete\n",
                 core::signalName(stopSignal).c_str());
    return 128 + stopSignal;
  }

  writeTable();
  // What the report script needs to know (with a few facts of the base deck, read without changing it).
  {
    const ParameterList& b = *baseDeck;
    const auto baseFact = [&](const std::string& list, const std::string& key) -> std::string {
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
    };
    out.add("study.json");
    std::ofstream j(dir / "study.json");
    j << "{\n  \"title\": " << jsonString(study->get<std::string>("Title")) << ",\n  \"base_deck\": "
      << jsonString(base.string()) << ",\n  \"at_T\": " << atT << ",\n  \"reference_group\": "
      << jsonString(referenceGroup) << ",\n  \"timing_runs\": " << timing << ",\n  \"parallel\": " << parallel
      << ",\n  \"base\": {\"strategy\": " << jsonString(baseFact("Contact/Enforcement", "Type"))
      << ", \"beams\": " << (b.isSublist("Beams") ? b.sublist("Beams").numParams() : 0)
      << ", \"increments\": " << jsonString(baseFact("Load Stepping", "Number of Increments")) << "},\n  \"groups\": [";
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
    j << "\n  ],\n  \"units\": {";
    {
      bool first = true;
      auto unit = [&](const std::string& name, const std::string& u) {
        if (u.empty()) return;
        j << (first ? "" : ", ") << jsonString(name) << ": " << jsonString(u);
        first = false;
      };
      for (const Group& g : groups)
        for (const Variable& v : g.variables) unit(v.name, v.unit);
      for (const Output& o : outputs) unit(o.name, o.unit);
    }
    j << "},\n  \"columns\": [";
    for (std::size_t i = 0; i < columns.size(); ++i) j << (i ? ", " : "") << jsonString(columns[i]);
    j << "],\n  \"outputs\": [";
    for (std::size_t i = 0; i < outputs.size(); ++i) j << (i ? ", " : "") << jsonString(outputs[i].name);
    j << "],\n  \"output_sources\": {";
    for (std::size_t i = 0; i < outputs.size(); ++i)
      j << (i ? ", " : "") << jsonString(outputs[i].name)
        << ": {\"tracked_point\": " << jsonString(outputs[i].trackedPoint)
        << ", \"component\": " << jsonString(outputs[i].component)
        << ", \"contact\": " << jsonString(outputs[i].contact) << "}";
    j << "},\n  \"plots\": [";
    for (std::size_t i = 0; i < plots.size(); ++i) {
      const Plot& p = plots[i];
      j << (i ? ",\n" : "\n") << "    {\"name\": " << jsonString(p.name) << ", \"x\": " << jsonString(p.x)
        << ", \"y\": " << jsonString(p.y) << ", \"series\": " << jsonString(p.series)
        << ", \"relative_to\": " << jsonString(p.relativeTo) << ", \"log_x\": " << (p.logX ? "true" : "false")
        << ", \"error\": " << (p.error ? "true" : "false") << ", \"published_x\": [";
      for (std::size_t k = 0; k < p.publishedX.size(); ++k) j << (k ? ", " : "") << text(p.publishedX[k]);
      j << "], \"published_y\": [";
      for (std::size_t k = 0; k < p.publishedY.size(); ++k) j << (k ? ", " : "") << text(p.publishedY[k]);
      j << "], \"published_labels\": [";
      for (std::size_t k = 0; k < p.publishedLabels.size(); ++k)
        j << (k ? ", " : "") << jsonString(p.publishedLabels[k]);
      j << "]}";
    }
    j << "\n  ]\n}\n";
  }
  const auto failed = std::count_if(all.begin(), all.end(), [](const Case& c) { return c.status != "complete"; });
  std::printf("study %s: %zu cases, %td complete, %td not; table %s\n", stem.c_str(), all.size(),
              static_cast<std::ptrdiff_t>(all.size()) - failed, failed, (dir / "cases.csv").string().c_str());
  if (options.report) {
    const std::string script = scriptPath("study_report.py");
    out.add("report.md");
    // The figures the script writes are named after they appear (it names them from the plots).
    std::set<std::string> before;
    for (const auto& e : fs::directory_iterator(dir)) before.insert(e.path().filename().string());
    const int code = runProgram({"/usr/bin/python3", script, dir.string()});
    for (const auto& e : fs::directory_iterator(dir))
      if (!before.count(e.path().filename().string()) && fs::is_regular_file(fs::symlink_status(e.path())))
        out.add(e.path().filename().string());
    if (code != 0)
      throw std::runtime_error("the report script " + script + " failed; the table is in " + (dir / "cases.csv").string());
  }
  if (failed)
    std::fprintf(stderr, "beamcontact: study incomplete: %td of %zu cases did not complete (their causes are in %s)\n",
                 static_cast<std::ptrdiff_t>(failed), all.size(), (dir / "cases.csv").string().c_str());
  return failed == 0 ? 0 : 2;
}

}  // namespace bc::drivers
