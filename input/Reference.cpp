#include "Reference.hpp"

#include <sstream>
#include <vector>

#include "XmlDeck.hpp"
#include "core/Parameters.hpp"

namespace bc::input {

using core::ParameterUse;
using Teuchos::ParameterEntry;
using Teuchos::ParameterList;

namespace {

const char* useName(ParameterUse use) {
  return use == ParameterUse::Required ? "required" : use == ParameterUse::Optional ? "optional" : "default";
}

// `text` in lines of at most `width` characters, each starting with `indent` spaces.
std::string wrapped(const std::string& text, std::size_t indent, std::size_t width = 100) {
  std::istringstream words(text);
  std::string out, line, word;
  const std::string pad(indent, ' ');
  while (words >> word) {
    if (!line.empty() && pad.size() + line.size() + 1 + word.size() > width) {
      out += pad + line + "\n";
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
  }
  if (!line.empty()) out += pad + line + "\n";
  return out;
}

void writeText(const ParameterList& list, std::ostream& out, std::size_t depth) {
  const std::string pad(2 * depth, ' ');
  for (auto it = list.begin(); it != list.end(); ++it) {
    const ParameterEntry& e = list.entry(it);
    if (e.isList()) {
      out << pad << list.name(it) << "/\n" << wrapped(e.docString(), 2 * depth + 4);
      writeText(Teuchos::getValue<ParameterList>(e), out, depth + 1);
      continue;
    }
    const ParameterUse use = core::parameterUse(e);
    out << pad << list.name(it) << " : " << deckType(e) << ", "
        << (use == ParameterUse::Default ? "default: " : std::string(useName(use)) + ", e.g. ") << deckValue(e) << "\n"
        << wrapped(core::parameterDoc(e), 2 * depth + 4);
  }
}

void writeXml(const ParameterList& list, const std::string& name, const std::string& doc, std::ostream& out,
              std::size_t depth) {
  const std::string pad(2 * depth, ' ');
  out << pad << "<ParameterList name=\"" << xmlEscaped(name) << "\"";
  if (!doc.empty()) out << " docString=\"" << xmlEscaped(doc) << "\"";
  out << ">\n";
  for (auto it = list.begin(); it != list.end(); ++it) {
    const ParameterEntry& e = list.entry(it);
    if (e.isList()) {
      writeXml(Teuchos::getValue<ParameterList>(e), list.name(it), e.docString(), out, depth + 1);
      continue;
    }
    out << pad << "  <Parameter name=\"" << xmlEscaped(list.name(it)) << "\" type=\"" << deckType(e) << "\" value=\""
        << xmlEscaped(deckValue(e)) << "\" use=\"" << useName(core::parameterUse(e)) << "\" docString=\""
        << xmlEscaped(core::parameterDoc(e)) << "\"/>\n";
  }
  out << pad << "</ParameterList>\n";
}

// A YAML double-quoted scalar (JSON's escapes, which YAML shares).
std::string quoted(const std::string& text) {
  std::string q = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') q += std::string("\\") + c;
    else if (c == '\n') q += "\\n";
    else if (c == '\t') q += "\\t";
    else if (static_cast<unsigned char>(c) < 32) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", static_cast<unsigned char>(c));
      q += hex;
    } else q += c;
  }
  return q + "\"";
}

// One list as a mapping: name, doc, parameters (a sequence of flow mappings), sublists (a sequence
// of such mappings); `pad` is the indentation of its keys.
void writeYaml(const ParameterList& list, const std::string& name, const std::string& doc, std::ostream& out,
               const std::string& first, const std::string& pad) {
  out << first << "name: " << quoted(name) << "\n" << pad << "doc: " << quoted(doc) << "\n";
  std::vector<std::string> parameters;
  for (auto it = list.begin(); it != list.end(); ++it) {
    const ParameterEntry& e = list.entry(it);
    if (e.isList()) continue;
    parameters.push_back("{name: " + quoted(list.name(it)) + ", type: " + quoted(deckType(e)) +
                         ", use: " + useName(core::parameterUse(e)) + ", value: " + quoted(deckValue(e)) +
                         ", doc: " + quoted(core::parameterDoc(e)) + "}");
  }
  out << pad << "parameters:" << (parameters.empty() ? " []\n" : "\n");
  for (const auto& p : parameters) out << pad << "  - " << p << "\n";
  bool any = false;
  for (auto it = list.begin(); it != list.end(); ++it) any = any || list.entry(it).isList();
  out << pad << "sublists:" << (any ? "\n" : " []\n");
  for (auto it = list.begin(); it != list.end(); ++it) {
    const ParameterEntry& e = list.entry(it);
    if (!e.isList()) continue;
    writeYaml(Teuchos::getValue<ParameterList>(e), list.name(it), e.docString(), out, pad + "  - ", pad + "    ");
  }
}

}  // namespace

void writeReference(const ParameterList& reference, ReferenceFormat format, std::ostream& out) {
  const std::string name = reference.name();
  switch (format) {
    case ReferenceFormat::Text:
      out << wrapped("Every parameter of a deck's ParameterList \"" + name +
                         "\" (docs/input.md), as NAME : TYPE, then \"default: VALUE\" (what the reader takes when "
                         "the parameter is left out), or \"required, e.g. VALUE\", or \"optional, e.g. VALUE\" "
                         "(no fixed default: the text says what leaving it out does), and what it means, with its "
                         "unit and its range in [brackets]. NAME/ is a sublist; a name in <angle brackets> stands "
                         "for names of your own, one sublist each. Values are as a deck writes them: bools true or "
                         "false, arrays {a, b, c}.",
                     0)
          << "\n"
          << name << "/\n";
      writeText(reference, out, 1);
      break;
    case ReferenceFormat::Xml:
      // (An XML comment may not hold two hyphens in a row: the option is named without them.)
      out << "<!-- The " << name
          << " deck reference (beamcontact print-valid-parameters, format xml): each parameter's type\n"
             "     and value as a deck writes them. use=\"default\": the value is the default the reader takes\n"
             "     when the parameter is left out; use=\"required\" or \"optional\": it is an example (an\n"
             "     optional value has no fixed default; its docString says what leaving it out does). A list\n"
             "     named <...> stands for lists of names of your own. -->\n";
      writeXml(reference, name, "", out, 0);
      break;
    case ReferenceFormat::Yaml:
      out << "# The " << name
          << " deck reference (beamcontact --print-valid-parameters --format yaml): each list's\n"
             "# parameters (name, type, use, value as a deck writes it, doc) and sublists. use: default: the\n"
             "# value is the default the reader takes when the parameter is left out; required or optional:\n"
             "# it is an example (an optional value has no fixed default; its doc says what leaving it out\n"
             "# does). A list named <...> stands for lists of names of your own.\n";
      writeYaml(reference, name, "", out, "", "");
      break;
  }
}

}  // namespace bc::input
