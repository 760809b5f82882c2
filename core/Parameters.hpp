// Validation of Teuchos parameter lists. Each component declares a ParameterSpec for its own sublist:
// every key with its type, default (or "required"/"optional"), documentation and range or choices.
// applySpec() then rejects unknown or mistyped keys and out-of-range values with an InputError naming
// the full parameter path (and, for choices or misspelt keys, the valid names), and fills in the
// defaults, so the effective list written beside the results is complete. Defaults live only here.
#pragma once
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <Teuchos_ParameterList.hpp>

namespace bc::core {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// How a reference list (ParameterSpec::reference()) shows a parameter: its value is the default the
// reader fills in, or an example of a value the user must give (Required) or may give (Optional; no
// fixed default: its doc says what leaving it out does). The doc string of a reference entry starts
// with kRequiredMark or kOptionalMark for the last two.
enum class ParameterUse { Default, Required, Optional };
inline const std::string kRequiredMark = "(required) ";
inline const std::string kOptionalMark = "(optional) ";
ParameterUse parameterUse(const Teuchos::ParameterEntry& entry);
// The entry's doc string without its kRequiredMark or kOptionalMark.
std::string parameterDoc(const Teuchos::ParameterEntry& entry);

class ParameterSpec {
 public:
  // Returns an empty string when the value is acceptable, otherwise what is wrong ("must be > 0").
  using Check = std::function<std::string(const Teuchos::ParameterEntry&)>;

  template <class T>
  ParameterSpec& add(const std::string& name, const T& defaultValue, const std::string& doc, Check check = {},
                     const std::string& rule = "") {
    valid_.set(name, defaultValue, withRule(doc, rule));
    reference_.set(name, defaultValue, withRule(doc, rule));
    if (check) checks_.push_back({name, check});
    return *this;
  }
  // A value the user must give. `example` fixes its type and is a typical, valid value: the reference
  // shows it as an example, never as a default (example() uses it, e.g. to construct a strategy in tests).
  template <class T>
  ParameterSpec& addRequired(const std::string& name, const T& example, const std::string& doc, Check check = {},
                             const std::string& rule = "") {
    add(name, example, kRequiredMark + doc, check, rule);
    required_.insert(name);
    return *this;
  }
  // A value the user may leave out, with no fixed default (the component decides, as `doc` says):
  // `sample` fixes its type and is a valid example.
  template <class T>
  ParameterSpec& addOptional(const std::string& name, const T& sample, const std::string& doc, Check check = {},
                             const std::string& rule = "") {
    add(name, sample, kOptionalMark + doc, check, rule);
    optional_.insert(name);
    return *this;
  }
  // Lets `name` (a number) also be given as the string `word` (e.g. "Automatic": a value the
  // component chooses itself); its range check then does not apply. isWord() tells which was given.
  ParameterSpec& allowWord(const std::string& name, const std::string& word);
  static bool isWord(const Teuchos::ParameterList& list, const std::string& name, const std::string& word) {
    return list.isType<std::string>(name) && list.get<std::string>(name) == word;
  }
  ParameterSpec& addChoice(const std::string& name, const std::string& defaultValue,
                           const std::vector<std::string>& choices, const std::string& doc);
  // A sublist the user may give (validated by its owner), shown in the reference as `reference`.
  ParameterSpec& addSublist(const std::string& name, const Teuchos::ParameterList& reference, const std::string& doc);
  // Accepts sublists of any name (e.g. one per beam), each documented by `reference`.
  ParameterSpec& allowNamedSublists(const Teuchos::ParameterList& reference, const std::string& placeholder);

  // Validates `user` (at `path`, e.g. "BeamContact/Beams/beam 1") and fills the defaults.
  void apply(Teuchos::ParameterList& user, const std::string& path) const;
  // The documented reference list (for --print-valid-parameters): every parameter with its type and
  // its default, or, for a required or optional one (parameterUse()), an example of its type.
  const Teuchos::ParameterList& reference() const { return reference_; }
  // A complete valid list: the defaults and, for required values, their examples (optional values
  // left out). For tests and templates.
  Teuchos::ParameterList example() const;

 private:
  static std::string withRule(const std::string& doc, const std::string& rule) {
    return rule.empty() ? doc : doc + " [" + rule + "]";
  }
  Teuchos::ParameterList valid_, reference_;
  std::vector<std::pair<std::string, Check>> checks_;
  std::set<std::string> required_, optional_, sublists_;
  std::map<std::string, std::string> words_;  // name -> the word it may be instead of a number
  bool namedSublists_ = false;
};

// Common checks.
ParameterSpec::Check positive();
ParameterSpec::Check nonNegative();
ParameterSpec::Check atLeast(int minimum);
ParameterSpec::Check wholeBetween(int minimum, int maximum);  // minimum <= v <= maximum
ParameterSpec::Check inRange(double lo, double hi);  // lo < v <= hi
ParameterSpec::Check closedRange(double lo, double hi);  // lo <= v <= hi
ParameterSpec::Check vector3();  // Array(double) of 3 entries

std::string joinNames(const std::vector<std::string>& names);

}  // namespace bc::core
