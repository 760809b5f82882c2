#include "CommandLine.hpp"

#include <cctype>
#include <sstream>

#include "core/Provenance.hpp"

namespace bc::drivers::cli {

namespace {

const Option* findLong(const Command& c, const std::string& name) {
  for (const auto& o : c.options)
    if (o.name == name) return &o;
  return nullptr;
}

const Option* findShort(const Command& c, char s) {
  for (const auto& o : c.options)
    if (o.shortName && o.shortName == s) return &o;
  return nullptr;
}

bool wholeNumber(const std::string& s) { return !s.empty() && s.find_first_not_of("0123456789") == std::string::npos; }

// Whether `s` is an option word (a number such as -0.5 is a value).
bool optionWord(const std::string& s) {
  return s.size() > 1 && s[0] == '-' && !(std::isdigit(static_cast<unsigned char>(s[1])) || s[1] == '.');
}

}  // namespace

Parsed parse(const Command& command, const std::vector<std::string>& args) {
  Parsed p;
  for (const auto& a : args)
    if (a == "--") break;
    else if (a == "-h" || a == "--help") {
      p.help = true;
      return p;
    }
  bool optionsEnded = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (!optionsEnded && a == "--") {
      optionsEnded = true;
      continue;
    }
    if (optionsEnded || !optionWord(a)) {
      if (p.positionals.size() >= command.positionals.size())
        throw UsageError(command.name, "unexpected argument \"" + a + "\"");
      p.positionals.push_back(a);
      continue;
    }
    const Option* o = nullptr;
    std::string name = a, value;
    bool inline_ = false;
    if (a.rfind("--", 0) == 0) {
      const auto eq = a.find('=');
      name = a.substr(0, eq);
      if (eq != std::string::npos) {
        value = a.substr(eq + 1);
        inline_ = true;
      }
      o = findLong(command, name.substr(2));
    } else if (a.size() == 2) {
      o = findShort(command, a[1]);
    }
    if (!o) throw UsageError(command.name, "unknown option \"" + name + "\"");
    const std::string shown = "--" + o->name;
    if (o->value.empty()) {
      if (inline_) throw UsageError(command.name, shown + " takes no value, got \"" + a + "\"");
    } else if (!inline_) {
      if (o->optionalValue) {
        value = i + 1 < args.size() && wholeNumber(args[i + 1]) ? args[++i] : o->implicit;
      } else {
        if (i + 1 >= args.size()) throw UsageError(command.name, "missing " + o->value + " after \"" + a + "\"");
        value = args[++i];
      }
    }
    auto& slot = p.values[o->name];
    if (!slot.empty() && !o->repeat) throw UsageError(command.name, shown + " is given twice");
    slot.push_back(value);
  }
  if (p.positionals.size() < command.positionals.size())
    throw UsageError(command.name, "missing " + command.positionals[p.positionals.size()].name);
  return p;
}

std::string help(const Command& command) {
  std::ostringstream s;
  s << "usage: beamcontact " << command.name;
  for (const auto& p : command.positionals) s << " " << p.name;
  s << " [options]\n\n" << command.summary;
  if (!command.summary.empty() && command.summary.back() != '\n') s << "\n";
  auto row = [&](const std::string& left, const std::string& right) {
    s << "  " << left;
    if (left.size() < 24) s << std::string(24 - left.size(), ' ');
    else s << "\n  " << std::string(24, ' ');
    // The meaning wrapped at 100 columns, its lines under each other.
    std::istringstream words(right);
    std::string word;
    std::size_t column = 26;
    bool first = true;
    while (words >> word) {
      if (!first && column + 1 + word.size() > 100) {
        s << "\n" << std::string(26, ' ');
        column = 26;
      } else if (!first) {
        s << ' ';
        ++column;
      }
      s << word;
      column += word.size();
      first = false;
    }
    s << "\n";
  };
  if (!command.positionals.empty()) {
    s << "\narguments:\n";
    for (const auto& p : command.positionals) row(p.name, p.meaning);
  }
  s << "\noptions:\n";
  for (const auto& o : command.options) {
    std::string left = o.shortName ? std::string("-") + o.shortName + ", --" + o.name : "    --" + o.name;
    if (!o.value.empty()) left += o.optionalValue ? " [" + o.value + "]" : " " + o.value;
    std::string right = o.meaning;
    if (o.repeat) right += "; may be repeated";
    right +=
        " (default: " + (o.defaultText.empty() ? std::string(o.value.empty() ? "off" : "none") : o.defaultText) + ")";
    row(left, right);
  }
  row("-h, --help", "print this help and exit");
  if (!command.notes.empty()) s << "\n" << command.notes << (command.notes.back() == '\n' ? "" : "\n");
  if (s.str().find("docs/") != std::string::npos) s << "\n" << documentationNote();
  return s.str();
}

std::string documentationNote() {
  return "docs/ above is " + core::documentationDirectory() + " (the documentation)\n";
}

}  // namespace bc::drivers::cli
