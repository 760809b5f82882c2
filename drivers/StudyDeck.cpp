#include "StudyDeck.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Teuchos_XMLParameterListHelpers.hpp>

#include "core/Faults.hpp"
#include "core/Parameters.hpp"
#include "core/StaticSolver.hpp"
#include "input/Plugins.hpp"
#include "input/XmlDeck.hpp"

namespace bc::drivers::study {

namespace fs = std::filesystem;
using core::InputError;
using Teuchos::Array;
using Teuchos::ParameterList;

std::string numberText(double v) {
  std::ostringstream s;
  s.precision(12);
  s << v;
  return s.str();
}

namespace {

const std::vector<std::string> kContactQuantities = {"Normal Force",  "Tangential Force 1", "Tangential Force 2",
                                                     "Active Points", "Stick Lines",        "Slip Lines"};
const std::vector<std::string> kComponents = {"ux", "uy", "uz", "rx", "ry", "rz"};

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
    throw InputError("missing required parameter \"" + path +
                     "/Path\" (string: a parameter path in the base deck, "
                     "e.g. \"Contact/Enforcement/Type\")");
  var.path = v.get<std::string>("Path");
  var.unit = stringParameter(v, path, "Unit", false);
  if (!v.isParameter("Values"))
    throw InputError("missing required parameter \"" + path + "/Values\" (Array(double), Array(int) or Array(string))");
  if (v.isType<Array<double>>("Values")) {
    for (double x : v.get<Array<double>>("Values")) var.values.push_back(numberText(x));
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
  // (A value twice would run the same case twice, and its rows would look like a repeatability check.)
  for (std::size_t i = 0; i < var.values.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (var.values[i] == var.values[j])
        throw InputError("parameter \"" + path + "/Values\" gives " + var.values[i] +
                         " twice: each value makes a case, and the two would be the same case");
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

// The study deck's own parameters, their defaults and checks, applied to `study`.
void applyStudySpec(ParameterList& study, const std::string& stem, const std::string& root) {
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
  spec.apply(study, root);
}

// The groups of cases and the varied parameters' column names.
void readGroups(StudyDeck& deck) {
  forEachSublist(deck.study->sublist("Cases"), deck.root + "/Cases", "a group of cases",
                 [&](const std::string& gname, const std::string& gpath, const ParameterList& gl) {
                   if (gname.find_first_not_of(" \t") == std::string::npos)
                     throw InputError("a group of cases in \"" + deck.root +
                                      "/Cases\" has an empty name; a group needs one (it names the group in cases.csv, "
                                      "the report and Reference Group)");
                   Group g{gname, {}};
                   forEachSublist(
                       gl, gpath, "a varied parameter with \"Path\" and \"Values\"",
                       [&](const std::string& vname, const std::string& vpath, const ParameterList& v) {
                         Variable var = readVariable(v, vname, vpath);
                         // (Both would set the one parameter, the later winning, while the table showed
                         // each column's value as the case's.)
                         for (const Variable& other : g.variables)
                           if (other.path == var.path)
                             throw InputError("parameters \"" + gpath + "/" + other.name + "/Path\" and \"" + vpath +
                                              "/Path\" both vary \"" + var.path +
                                              "\": a case would run with one of the values while its row showed "
                                              "both; vary a parameter once per group");
                         g.variables.push_back(std::move(var));
                         if (std::find(deck.columns.begin(), deck.columns.end(), vname) == deck.columns.end())
                           deck.columns.push_back(vname);
                       });
                   deck.groups.push_back(std::move(g));
                 });
  if (deck.groups.empty()) throw InputError("parameter \"" + deck.root + "/Cases\" has no groups: nothing to run");
}

// One output (sublist `o` at `path`): a contact total, or a tracked point's component.
Output readOutput(const std::string& name, const std::string& path, const ParameterList& o) {
  onlyKeys(o, path, {"Contact", "Tracked Point", "Component", "Unit"});
  Output out;
  out.name = name;
  out.unit = stringParameter(o, path, "Unit", false);
  out.contact = stringParameter(o, path, "Contact", false);
  out.trackedPoint = stringParameter(o, path, "Tracked Point", false);
  if (!out.contact.empty() && (o.isParameter("Tracked Point") || o.isParameter("Component")))
    throw InputError("parameter \"" + path + "\" gives \"Contact\" and \"" +
                     (o.isParameter("Tracked Point") ? "Tracked Point" : "Component") +
                     "\": an output is a contact total or a tracked point's component, not both; make two outputs");
  if (!out.contact.empty()) {
    if (!o.isParameter("Unit") && out.contact.find("Force") != std::string::npos) out.unit = "force";
    if (std::find(kContactQuantities.begin(), kContactQuantities.end(), out.contact) == kContactQuantities.end())
      throw InputError("parameter \"" + path + "/Contact\": \"" + out.contact + "\" is not one of " +
                       core::joinNames(kContactQuantities));
  } else if (!out.trackedPoint.empty()) {
    out.component = stringParameter(o, path, "Component", true);
    if (std::find(kComponents.begin(), kComponents.end(), out.component) == kComponents.end())
      throw InputError("parameter \"" + path + "/Component\" must be one of " + core::joinNames(kComponents));
    if (!o.isParameter("Unit")) out.unit = out.component[0] == 'u' ? "length" : "rad";
  } else {
    throw InputError("parameter \"" + path + "\" needs \"Contact\" (" + core::joinNames(kContactQuantities) +
                     ") or \"Tracked Point\" with \"Component\"");
  }
  return out;
}

// A tracked point's output must name one of the base deck's Output/Tracked Points, or one a case
// variable's Path adds (Output/Tracked Points/<name>/...): otherwise every case would run and its
// column would stay empty.
void checkTrackedPoint(const StudyDeck& deck, const Output& out, const std::string& path) {
  if (out.trackedPoint.empty()) return;
  const std::string added = "Output/Tracked Points/" + out.trackedPoint + "/";
  for (const Group& g : deck.groups)
    for (const Variable& v : g.variables)
      if (v.path.rfind(added, 0) == 0) return;
  std::vector<std::string> names;
  if (deck.baseDeck->isSublist("Output") && deck.baseDeck->sublist("Output").isSublist("Tracked Points")) {
    const ParameterList& tracked = deck.baseDeck->sublist("Output").sublist("Tracked Points");
    for (auto it = tracked.begin(); it != tracked.end(); ++it)
      if (tracked.isSublist(tracked.name(it))) names.push_back(tracked.name(it));
  }
  if (std::find(names.begin(), names.end(), out.trackedPoint) != names.end()) return;
  throw InputError("parameter \"" + path + "/Tracked Point\": \"" + out.trackedPoint +
                   "\" is not a tracked point of the base deck \"" + deck.base.string() + "\" (" +
                   (names.empty() ? std::string("it has no Output/Tracked Points")
                                  : "its tracked points are " + core::joinNames(names)) +
                   ")");
}

// A plot's published points (sublist `p` at `path`): Published Y, with as many X (or none) and labels (or none).
void readPublished(const ParameterList& p, const std::string& path, Plot& plot) {
  auto numbers = [&](const std::string& key) {
    std::vector<double> v;
    if (!p.isParameter(key)) return v;
    if (!p.isType<Array<double>>(key)) throw InputError("parameter \"" + path + "/" + key + "\" must be Array(double)");
    for (double x : p.get<Array<double>>(key)) v.push_back(x);
    return v;
  };
  plot.publishedX = numbers("Published X");
  plot.publishedY = numbers("Published Y");
  if (p.isParameter("Published Labels")) {
    if (!p.isType<Array<std::string>>("Published Labels"))
      throw InputError("parameter \"" + path + "/Published Labels\" must be Array(string)");
    for (const auto& l : p.get<Array<std::string>>("Published Labels")) plot.publishedLabels.push_back(l);
  }
  const std::size_t np = plot.publishedY.size();
  if ((!plot.publishedX.empty() && plot.publishedX.size() != np) ||
      (!plot.publishedLabels.empty() && plot.publishedLabels.size() != np) ||
      (np == 0 && (!plot.publishedX.empty() || !plot.publishedLabels.empty())))
    throw InputError("parameter \"" + path +
                     "/Published Y\": give one value per published point, and as many \"Published X\" "
                     "(or none: horizontal lines) and \"Published Labels\" (or none)");
}

// Checks that a plot (at `path`) names a varied parameter as X and Series, an output as Y and a group as
// its reference.
void checkPlotNames(const StudyDeck& deck, const std::string& path, const Plot& plot) {
  const auto& columns = deck.columns;
  const auto& outputs = deck.outputs;
  auto isColumn = [&](const std::string& c) { return std::find(columns.begin(), columns.end(), c) != columns.end(); };
  auto isOutput = [&](const std::string& c) {
    return std::any_of(outputs.begin(), outputs.end(), [&](const Output& o) { return o.name == c; }) ||
           c == "newton_iterations" || c == "solve_seconds" || c == "passes" || c == "max_newton_per_step";
  };
  if (!isColumn(plot.x)) throw InputError("parameter \"" + path + "/X\": \"" + plot.x + "\" is not a varied parameter");
  if (!isOutput(plot.y)) throw InputError("parameter \"" + path + "/Y\": \"" + plot.y + "\" is not an output");
  if (!plot.series.empty() && !isColumn(plot.series))
    throw InputError("parameter \"" + path + "/Series\": \"" + plot.series + "\" is not a varied parameter");
  if (!plot.relativeTo.empty() &&
      std::none_of(deck.groups.begin(), deck.groups.end(), [&](const Group& g) { return g.name == plot.relativeTo; }))
    throw InputError("parameter \"" + path + "/Relative To Group\": no group \"" + plot.relativeTo + "\"");
}

// One plot (sublist `p` at `path`), after the groups and outputs it names.
Plot readPlot(const StudyDeck& deck, const std::string& name, const std::string& path, const ParameterList& p) {
  onlyKeys(
      p, path,
      {"X", "Y", "Series", "Relative To Group", "Log X", "Error", "Published X", "Published Y", "Published Labels"});
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
  readPublished(p, path, plot);
  if (p.isParameter("Error")) {
    if (!p.isType<bool>("Error")) throw InputError("parameter \"" + path + "/Error\" must be a bool");
    plot.error = p.get<bool>("Error");
    if (plot.error && plot.relativeTo.empty()) plot.relativeTo = deck.study->get<std::string>("Reference Group");
    if (plot.error && plot.relativeTo.empty())
      throw InputError("parameter \"" + path + "/Error\": an error needs a reference; give \"" + path +
                       "/Relative To Group\" or \"" + deck.root + "/Reference Group\"");
  }
  checkPlotNames(deck, path, plot);
  return plot;
}

}  // namespace

StudyDeck readStudyDeck(const std::string& studyFile, const std::vector<std::string>& plugins) {
  if (!fs::exists(studyFile)) throw InputError("study deck \"" + studyFile + "\" does not exist");
  StudyDeck deck;
  deck.study = Teuchos::rcp(new ParameterList(input::readParameterXmlFile(studyFile)));
  deck.stem = fs::path(studyFile).stem().string();
  if (deck.study->name() == "BeamContact" || deck.study->isSublist("Beams"))
    throw InputError("\"" + studyFile + "\" is a run's deck (its top-level ParameterList is \"" + deck.study->name() +
                     "\"), not a study deck: run it with \"beamcontact run " + studyFile +
                     "\", or give a study deck (top-level ParameterList \"Study\" naming it as its Base Deck: "
                     "docs/studies.md)");
  applyStudySpec(*deck.study, deck.stem, deck.root);

  deck.base = (fs::path(studyFile).parent_path() / deck.study->get<std::string>("Base Deck")).lexically_normal();
  if (!fs::exists(deck.base))
    throw InputError("parameter \"" + deck.root + "/Base Deck\": file \"" + deck.base.string() + "\" does not exist");
  deck.baseDeck = Teuchos::rcp(new ParameterList(input::readParameterXmlFile(deck.base.string())));
  // The base deck's Plugins must be among --plugin; they become absolute paths with their digests, so each
  // case's copy of the deck names exactly what runs.
  input::checkDeckPlugins(*deck.baseDeck, deck.base.string(), plugins);
  deck.atT = deck.study->get<double>("At T");

  readGroups(deck);
  forEachSublist(deck.study->sublist("Outputs"), deck.root + "/Outputs", "an output",
                 [&](const std::string& name, const std::string& path, const ParameterList& o) {
                   deck.outputs.push_back(readOutput(name, path, o));
                   checkTrackedPoint(deck, deck.outputs.back(), path);
                 });
  forEachSublist(deck.study->sublist("Plots"), deck.root + "/Plots", "a plot",
                 [&](const std::string& name, const std::string& path, const ParameterList& p) {
                   deck.plots.push_back(readPlot(deck, name, path, p));
                 });
  return deck;
}

std::vector<Case> expandCases(const std::vector<Group>& groups) {
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
  return all;
}

const Case* referenceCase(const StudyDeck& deck, const std::vector<Case>& all) {
  const std::string referenceGroup = deck.study->get<std::string>("Reference Group");
  if (referenceGroup.empty()) return nullptr;
  const auto n = std::count_if(all.begin(), all.end(), [&](const Case& c) { return c.group == referenceGroup; });
  if (n != 1)
    throw InputError("parameter \"" + deck.root + "/Reference Group\": " +
                     (n == 0 ? "no group \"" + referenceGroup + "\""
                             : "group \"" + referenceGroup + "\" has " + std::to_string(n) +
                                   " cases; the reference must be a group of one case"));
  return &*std::find_if(all.begin(), all.end(), [&](const Case& c) { return c.group == referenceGroup; });
}

bool isAtT(double T, double atT) { return std::abs(T - atT) <= 1e-9 * std::max(1.0, std::abs(atT)); }

namespace {
// The base deck with case `c`'s values.
ParameterList withCaseValues(const StudyDeck& deck, const Case& c) {
  ParameterList caseDeck(*deck.baseDeck);
  for (const auto& [var, value] : c.settings)
    setValue(caseDeck, *var, value, "case " + std::to_string(c.index) + " (group \"" + c.group + "\")");
  return caseDeck;
}
}  // namespace

void checkAtTIsAStep(const StudyDeck& deck, const Case& c) {
  ParameterList caseDeck = withCaseValues(deck, c);
  const ParameterList& stepping = caseDeck.sublist("Load Stepping");
  std::vector<double> steps;
  std::string how;
  if (stepping.isType<Teuchos::Array<double>>("Load Factors")) {
    for (double t : stepping.get<Teuchos::Array<double>>("Load Factors")) steps.push_back(t);
    how = "its Load Factors";
  } else {
    int n = core::loadSteppingSpec().reference().get<int>("Number of Increments");
    if (stepping.isParameter("Number of Increments")) {
      if (!stepping.isType<int>("Number of Increments")) return;  // the case's run names the wrong type
      n = stepping.get<int>("Number of Increments");
    }
    if (n < 1 || n > 10000000) return;  // the case's run refuses it
    for (int k = 1; k <= n; ++k) steps.push_back(double(k) / n);
    how = "Number of Increments " + std::to_string(n);
  }
  if (steps.empty()) return;
  const double atT = deck.atT;
  for (double t : steps)
    if (isAtT(t, atT)) return;
  std::ostringstream m;
  m << "parameter \"" << deck.root << "/At T\" = " << atT << " is not a load step of case " << c.index << " (group \""
    << c.group << "\", " << how << ": steps at ";
  for (std::size_t i = 0; i < steps.size() && i < 6; ++i) m << (i ? ", " : "") << steps[i];
  if (steps.size() > 6) m << ", ...";
  m << "); the outputs are read at a converged step: choose an At T on every case's steps";
  throw InputError(m.str());
}

std::string caseDeckXml(const StudyDeck& deck, const Case& c, bool timing) {
  ParameterList caseDeck = withCaseValues(deck, c);
  // The case's deck names its folder where a deck may (relative, no ".."), so it can be run again
  // by itself; otherwise it keeps the default (results/deck). The study runs it with --output.
  const bool deckMayName = c.dir.is_relative() &&
                           std::none_of(c.dir.begin(), c.dir.end(), [](const fs::path& part) { return part == ".."; });
  if (deckMayName) caseDeck.sublist("Output").set("Directory", c.dir.string());
  else caseDeck.sublist("Output").remove("Directory", false);
  if (timing) caseDeck.sublist("Output").set("Write VTK", false);  // fair timing: the method, not the output
  std::ostringstream xml;
  Teuchos::writeParameterListToXmlOStream(caseDeck, xml);
  return xml.str();
}

}  // namespace bc::drivers::study
