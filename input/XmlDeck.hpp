// The XML reader of decks and study decks: the Teuchos parameter-list format
//   <ParameterList name="BeamContact">
//     <ParameterList name="Beams"> ... </ParameterList>
//     <Parameter name="..." type="double" value="..."/>
//   </ParameterList>
// read strictly, with the file and line in every message:
//  - a value must be its type entirely: "10abc" is no int, "30000.0xyz" no double, "10000.0" no int;
//    reals must be finite (no nan, inf, or overflow); bools are true or false; arrays are {a, b, c}
//    of such values;
//  - a name given twice in one list is an error (naming both lines), not a silent overwrite;
//  - types: int, double, bool, string, Array(int), Array(double), Array(string);
//  - nesting deeper than 32 lists, a file over 16 MB, DOCTYPE/CDATA, "--" inside a comment and text
//    outside attributes are refused (the parser is iterative: no input can exhaust the stack).
// Attributes Teuchos writes (id, docString, isDefault, isUsed) are accepted and ignored, so the
// effective_parameters.xml of a run and a study's case decks read back.
#pragma once
#include <string>

#include <Teuchos_ParameterList.hpp>

#include "core/Parameters.hpp"

namespace bc::input {

// Parses `text`; `source` names it in messages ("deck.xml"). Throws core::InputError.
Teuchos::ParameterList parseParameterXml(const std::string& text, const std::string& source);
// Reads and parses a file. Throws core::InputError for a missing, unreadable or oversized file.
// With `sha256`, also the SHA-256 of the text read (hex), from the one reading.
Teuchos::ParameterList readParameterXmlFile(const std::string& path, std::string* sha256 = nullptr);

// Parameter paths ("Contact/Enforcement/Type", relative to the list given): the sublist at a path
// (created when `create`, else an InputError naming the path), and a parameter set at a path (its
// sublists created as needed). For tests, studies and deck generators: edits by path, never by text.
Teuchos::ParameterList& sublistAtPath(Teuchos::ParameterList& list, const std::string& path, bool create = true);
template <class T> void setAtPath(Teuchos::ParameterList& list, const std::string& path, const T& value) {
  const auto slash = path.rfind('/');
  Teuchos::ParameterList& parent = slash == std::string::npos ? list : sublistAtPath(list, path.substr(0, slash));
  parent.set(slash == std::string::npos ? path : path.substr(slash + 1), value);
}
// Replaces an existing parameter (an InputError naming the path if there is none): a misspelt path
// in a test or generator fails instead of adding a parameter nobody reads.
template <class T> void replaceAtPath(Teuchos::ParameterList& list, const std::string& path, const T& value) {
  const auto slash = path.rfind('/');
  Teuchos::ParameterList& parent =
      slash == std::string::npos ? list : sublistAtPath(list, path.substr(0, slash), false);
  const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  if (!parent.isParameter(name) || parent.isSublist(name))
    throw core::InputError("path \"" + path + "\" names no parameter to replace");
  parent.set(name, value);
}

// The writer's side of the reader: a parameter's type as a deck names it ("double", "Array(double)")
// and its value as the reader takes it back: numbers in their shortest exact form, bools true or
// false, arrays {a, b, c} (not XML-escaped). Throws std::logic_error for a type decks do not have.
std::string deckType(const Teuchos::ParameterEntry& entry);
std::string deckValue(const Teuchos::ParameterEntry& entry);
// `text` for a double-quoted XML attribute: &, <, > and " escaped.
std::string xmlEscaped(const std::string& text);

// The machine's physical memory in bytes.
double physicalMemory();
// What this process may use: the machine's memory, or less under an address-space limit (ulimit -v,
// prlimit --as); then `note`, when given, receives "; this process may use N GB (...)".
double usableMemory(std::string* note = nullptr);

}  // namespace bc::input
