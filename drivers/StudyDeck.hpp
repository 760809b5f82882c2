// The study deck read (drivers/Study.hpp): its groups of varied parameters, outputs and plots, checked,
// and the cases the groups expand to, each with the deck it runs. The format is in docs/studies.md.
#pragma once
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>

namespace bc::drivers::study {

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
  std::string contact;  // a contact total
  std::string unit;  // for the report's axes and tables
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
  std::filesystem::path dir;
  std::string status = "not run", cause;
  int exitCode = -1;
  bool kept = false;  // complete from an earlier run of the study (same deck)
  std::vector<double> timings;  // --timing: the solve time of each complete run
};

// A study deck with its defaults applied, and its base deck.
struct StudyDeck {
  std::string root = "Study";  // the study deck's top list, in messages
  std::string stem;  // the study deck's file name without extension
  Teuchos::RCP<Teuchos::ParameterList> study;
  std::filesystem::path base;  // the base deck, relative to the working directory
  Teuchos::RCP<Teuchos::ParameterList> baseDeck;
  double atT = 1.0;
  std::vector<Group> groups;
  std::vector<std::string> columns;  // the varied parameters' names, each once, in the order first met
  std::vector<Output> outputs;
  std::vector<Plot> plots;
};

// A number as the study writes it (12 significant digits).
std::string numberText(double v);

// Reads and checks `studyFile` and its base deck, whose Plugins must be among `plugins` (--plugin).
// Throws core::InputError.
StudyDeck readStudyDeck(const std::string& studyFile, const std::vector<std::string>& plugins);

// Every group's cases (all combinations of its value lists), numbered from 1 in the groups' order.
// The cases point to the groups' variables. Throws core::InputError beyond 10000 cases.
std::vector<Case> expandCases(const std::vector<Group>& groups);

// The case of the deck's "Reference Group" (a group of exactly one case); null without one.
// Throws core::InputError.
const Case* referenceCase(const StudyDeck& deck, const std::vector<Case>& all);

// The deck `c` runs, as XML: the base deck with the case's values, naming the case's folder where a
// deck may; with `timing`, VTK output off.
std::string caseDeckXml(const StudyDeck& deck, const Case& c, bool timing);
// Whether load factor `T` (a step's, as a results table gives it) is the study's `atT`.
bool isAtT(double T, double atT);
// Refuses a study whose "At T" is not a load step of case `c` (its deck's Load Factors, or its Number
// of Increments equal steps): the outputs are read at a converged step, and the case would end
// complete with none.
void checkAtTIsAStep(const StudyDeck& deck, const Case& c);

}  // namespace bc::drivers::study
