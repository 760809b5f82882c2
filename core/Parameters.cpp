#include "Parameters.hpp"

#include <cmath>
#include <sstream>

#include <Teuchos_Array.hpp>

namespace bc::core {

std::string joinNames(const std::vector<std::string>& names) {
  std::string s;
  for (std::size_t i = 0; i < names.size(); ++i) s += (i ? ", " : "") + ("\"" + names[i] + "\"");
  return s;
}

ParameterUse parameterUse(const Teuchos::ParameterEntry& entry) {
  const std::string& doc = entry.docString();
  if (doc.rfind(kRequiredMark, 0) == 0) return ParameterUse::Required;
  if (doc.rfind(kOptionalMark, 0) == 0) return ParameterUse::Optional;
  return ParameterUse::Default;
}

std::string parameterDoc(const Teuchos::ParameterEntry& entry) {
  const ParameterUse use = parameterUse(entry);
  return use == ParameterUse::Required   ? entry.docString().substr(kRequiredMark.size())
         : use == ParameterUse::Optional ? entry.docString().substr(kOptionalMark.size())
                                         : entry.docString();
}

ParameterSpec& ParameterSpec::addChoice(const std::string& name, const std::string& defaultValue,
                                        const std::vector<std::string>& choices, const std::string& doc) {
  Check check = [choices](const Teuchos::ParameterEntry& e) -> std::string {
    const std::string v = Teuchos::any_cast<std::string>(e.getAny());
    for (const auto& c : choices)
      if (c == v) return "";
    return "\"" + v + "\" is not a valid choice; valid choices are " + joinNames(choices);
  };
  return add(name, defaultValue, doc, check, "one of " + joinNames(choices));
}

ParameterSpec& ParameterSpec::allowWord(const std::string& name, const std::string& word) {
  words_[name] = word;
  for (Teuchos::ParameterList* list : {&valid_, &reference_}) {
    Teuchos::ParameterEntry& entry = list->getEntry(name);
    if (entry.docString().find("\"" + word + "\"") == std::string::npos)  // unless the doc names it already
      entry.setDocString(entry.docString() + "; or \"" + word + "\"");
  }
  return *this;
}

ParameterSpec& ParameterSpec::addSublist(const std::string& name, const Teuchos::ParameterList& reference,
                                         const std::string& doc) {
  valid_.sublist(name, false, doc).setParameters(reference);
  reference_.sublist(name, false, doc).setParameters(reference);
  sublists_.insert(name);
  return *this;
}

ParameterSpec& ParameterSpec::allowNamedSublists(const Teuchos::ParameterList& reference,
                                                 const std::string& placeholder) {
  valid_.sublist(placeholder, false, "one sublist of this form per item; its name is the item's name")
      .setParameters(reference);
  reference_.sublist(placeholder, false, "one sublist of this form per item; its name is the item's name")
      .setParameters(reference);
  namedSublists_ = true;
  return *this;
}

void ParameterSpec::apply(Teuchos::ParameterList& user, const std::string& path) const {
  std::vector<std::string> validNames;
  for (auto it = valid_.begin(); it != valid_.end(); ++it)
    if (!valid_.entry(it).isList() || sublists_.count(valid_.name(it))) validNames.push_back(valid_.name(it));

  for (auto it = user.begin(); it != user.end(); ++it) {
    const std::string& name = user.name(it);
    const std::string where = "\"" + path + "/" + name + "\"";
    Teuchos::ParameterEntry& entry = user.getEntry(name);
    if (entry.isList()) {
      if (sublists_.count(name) || namedSublists_) continue;
      throw InputError("unknown sublist " + where + "; valid parameters here are " + joinNames(validNames));
    }
    if (!valid_.isParameter(name) || valid_.isSublist(name)) {
      throw InputError("unknown parameter " + where + "; valid parameters here are " + joinNames(validNames));
    }
    const Teuchos::ParameterEntry& ref = valid_.getEntry(name);
    const auto word = words_.find(name);
    if (word != words_.end() && entry.getAny().type() == typeid(std::string)) {
      if (Teuchos::any_cast<std::string>(entry.getAny()) != word->second)
        throw InputError("parameter " + where + " is \"" + Teuchos::any_cast<std::string>(entry.getAny()) +
                         "\"; give a number or \"" + word->second + "\"");
      continue;
    }
    if (entry.getAny().type() != ref.getAny().type()) {
      if (ref.getAny().type() == typeid(double) && entry.getAny().type() == typeid(int)) {
        user.set(name, double(Teuchos::any_cast<int>(entry.getAny())));
      } else {
        throw InputError("parameter " + where + " has type " + entry.getAny().typeName() + ", expected " +
                         ref.getAny().typeName());
      }
    }
  }
  for (const auto& [name, check] : checks_) {
    if (!user.isParameter(name)) continue;
    if (words_.count(name) && user.isType<std::string>(name)) continue;
    const std::string msg = check(user.getEntry(name));
    if (!msg.empty()) throw InputError("parameter \"" + path + "/" + name + "\": " + msg);
  }
  for (auto it = valid_.begin(); it != valid_.end(); ++it) {
    const std::string& name = valid_.name(it);
    if (valid_.entry(it).isList() || user.isParameter(name)) continue;
    if (required_.count(name))
      throw InputError("missing required parameter \"" + path + "/" + name + "\" (" +
                       valid_.getEntry(name).docString() + ")");
    if (optional_.count(name)) continue;
    user.setEntry(name, valid_.getEntry(name));
  }
}

Teuchos::ParameterList ParameterSpec::example() const {
  Teuchos::ParameterList e;
  for (auto it = valid_.begin(); it != valid_.end(); ++it) {
    const std::string& name = valid_.name(it);
    if (valid_.entry(it).isList() || optional_.count(name)) continue;
    e.setEntry(name, valid_.getEntry(name));
  }
  return e;
}

namespace {
double number(const Teuchos::ParameterEntry& e) {
  if (e.getAny().type() == typeid(int)) return Teuchos::any_cast<int>(e.getAny());
  return Teuchos::any_cast<double>(e.getAny());
}
std::string show(double v) {
  std::ostringstream s;
  s.precision(15);
  s << v;
  return s.str();
}
}  // namespace

ParameterSpec::Check positive() {
  return [](const Teuchos::ParameterEntry& e) {
    const double v = number(e);
    return (v > 0.0 && std::isfinite(v)) ? std::string() : "must be > 0, got " + show(v);
  };
}
ParameterSpec::Check nonNegative() {
  return [](const Teuchos::ParameterEntry& e) {
    const double v = number(e);
    return (v >= 0.0 && std::isfinite(v)) ? std::string() : "must be >= 0, got " + show(v);
  };
}
ParameterSpec::Check atLeast(int minimum) {
  return [minimum](const Teuchos::ParameterEntry& e) {
    const double v = number(e);
    return v >= minimum ? std::string() : "must be >= " + std::to_string(minimum) + ", got " + show(v);
  };
}
ParameterSpec::Check wholeBetween(int minimum, int maximum) {
  return [minimum, maximum](const Teuchos::ParameterEntry& e) {
    const double v = number(e);
    return (v >= minimum && v <= maximum)
               ? std::string()
               : "must be from " + std::to_string(minimum) + " to " + std::to_string(maximum) + ", got " + show(v);
  };
}
ParameterSpec::Check inRange(double lo, double hi) {
  return [lo, hi](const Teuchos::ParameterEntry& e) {
    const double v = number(e);
    return (v > lo && v <= hi) ? std::string() : "must be in (" + show(lo) + ", " + show(hi) + "], got " + show(v);
  };
}
ParameterSpec::Check closedRange(double lo, double hi) {
  return [lo, hi](const Teuchos::ParameterEntry& e) {
    const double v = number(e);
    return (v >= lo && v <= hi) ? std::string() : "must be in [" + show(lo) + ", " + show(hi) + "], got " + show(v);
  };
}
ParameterSpec::Check vector3() {
  return [](const Teuchos::ParameterEntry& e) {
    const auto& a = Teuchos::any_cast<Teuchos::Array<double>>(e.getAny());
    if (a.size() != 3) return std::string("must have 3 components, got ") + std::to_string(a.size());
    for (double v : a)
      if (!std::isfinite(v)) return std::string("must be finite");
    return std::string();
  };
}

}  // namespace bc::core
