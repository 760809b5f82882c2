#include "XmlDeck.hpp"

#include <algorithm>
#include <sys/resource.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include <Teuchos_Array.hpp>

#include "core/Checkpoint.hpp"
#include "core/Parameters.hpp"
#include "core/Sha256.hpp"

namespace bc::input {

using core::InputError;
using Teuchos::Array;
using Teuchos::ParameterList;

namespace {

constexpr int kMaxDepth = 32;
// Generated many-beam decks are large: 21 MB for the 200 x 200 crossed layers (4 x 10^4 contact points).
constexpr std::size_t kMaxBytes = std::size_t(256) << 20;
constexpr const char* kTooLarge = "larger than 256 MB (a generated deck of 10^5 contact points takes about 50 MB)";

// The reader's memory per deck byte, at most (measured, `beamcontact check`'s peak resident memory
// over the deck's size: 9.0 for the 200 x 200 crossed layers with loads, 21 MB; 10.1 for a network of
// 4000 fibres without contact, 9.9 MB; the lists, the text once and the checked model).
constexpr double kReadBytesPerByte = 12.0;

struct Attribute {
  std::string name, value;
};

// The position of the first byte of `s` that does not begin or continue a valid UTF-8 sequence
// (overlong forms, surrogates and code points beyond U+10FFFF included), or npos.
std::size_t firstNonUtf8(const std::string& s) {
  std::size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x80) {
      ++i;
      continue;
    }
    int n = 0;
    unsigned lo = 0x80, hi = 0xBF;  // the allowed range of the second byte
    if (c >= 0xC2 && c <= 0xDF) n = 1;
    else if (c == 0xE0) n = 2, lo = 0xA0;
    else if (c >= 0xE1 && c <= 0xEC) n = 2;
    else if (c == 0xED) n = 2, hi = 0x9F;
    else if (c >= 0xEE && c <= 0xEF) n = 2;
    else if (c == 0xF0) n = 3, lo = 0x90;
    else if (c >= 0xF1 && c <= 0xF3) n = 3;
    else if (c == 0xF4) n = 3, hi = 0x8F;
    else return i;
    for (int k = 1; k <= n; ++k) {
      if (i + k >= s.size()) return i;
      const auto b = static_cast<unsigned char>(s[i + k]);
      if (k == 1 ? (b < lo || b > hi) : (b < 0x80 || b > 0xBF)) return i;
    }
    i += n + 1;
  }
  return std::string::npos;
}

class Parser {
 public:
  Parser(const std::string& text, const std::string& source) : s_(text), source_(source) {}
  ParameterList parse();

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(source_ + ":" + std::to_string(line_) + ": " + what);
  }
  bool atEnd() const { return i_ >= s_.size(); }
  char peek(std::size_t k = 0) const { return i_ + k < s_.size() ? s_[i_ + k] : '\0'; }
  bool startsWith(const char* t) const { return s_.compare(i_, std::char_traits<char>::length(t), t) == 0; }
  void advance(std::size_t n = 1) {
    for (std::size_t k = 0; k < n && i_ < s_.size(); ++k)
      if (s_[i_++] == '\n') ++line_;
  }
  void skipSpace() {
    while (!atEnd() && std::isspace(static_cast<unsigned char>(peek()))) advance();
  }
  void skipUntil(const char* end, const char* what) {
    const std::size_t at = s_.find(end, i_);
    if (at == std::string::npos) fail("unterminated " + std::string(what));
    advance(at - i_ + std::char_traits<char>::length(end));
  }
  std::string name() {
    const std::size_t start = i_;
    while (!atEnd() && (std::isalnum(static_cast<unsigned char>(peek())) || peek() == '_' || peek() == ':' ||
                        peek() == '-' || peek() == '.'))
      advance();
    if (i_ == start)
      fail(std::string("expected a name, found '") + (atEnd() ? std::string("end of file") : std::string(1, peek())) +
           "'");
    return s_.substr(start, i_ - start);
  }
  std::string attributeValue();
  // Skips text, comments and declarations up to the next element tag; false at the end of input.
  bool nextTag();

  // The steps of parse(): the text's encoding; a closing tag; an opening tag's attributes (up to its
  // '>' or '/>'); a <ParameterList>; a <Parameter>.
  void checkEncoding();
  void closeTag(const std::string& tag);
  std::vector<Attribute> attributes(const std::string& tag, bool& selfClosing);
  void openList(const std::vector<Attribute>& attrs, bool selfClosing, int line);
  void parameter(const std::vector<Attribute>& attrs, bool selfClosing, int line);
  // Records the name `n` (on `line`) in the open list; a name given twice there fails.
  void claim(const std::string& n, int line);

  const std::string& s_;
  std::string source_;
  std::size_t i_ = 0;
  int line_ = 1;
  // The lists open at the parser's position, outermost first.
  struct Open {
    ParameterList* list;
    std::string path;
    std::map<std::string, int> names;  // name -> line
  };
  ParameterList root_;
  std::vector<Open> stack_;
  bool done_ = false;  // the top-level list has ended
};

const std::string* attributeNamed(const std::vector<Attribute>& attrs, const std::string& key) {
  for (const auto& a : attrs)
    if (a.name == key) return &a.value;
  return nullptr;
}

std::string Parser::attributeValue() {
  const char quote = peek();
  if (quote != '"' && quote != '\'') fail("an attribute value must be quoted");
  advance();
  std::string v;
  while (true) {
    if (atEnd()) fail("unterminated attribute value");
    const char c = peek();
    if (c == quote) {
      advance();
      return v;
    }
    if (c == '<') fail("'<' inside an attribute value (write &lt;)");
    if (c != '&') {
      v += c;
      advance();
      continue;
    }
    const std::size_t semi = s_.find(';', i_);
    if (semi == std::string::npos || semi - i_ > 10) fail("an '&' that starts no entity (write &amp;)");
    const std::string e = s_.substr(i_ + 1, semi - i_ - 1);
    if (e == "lt") v += '<';
    else if (e == "gt") v += '>';
    else if (e == "amp") v += '&';
    else if (e == "quot") v += '"';
    else if (e == "apos") v += '\'';
    else if (e.size() > 1 && e[0] == '#') {
      char* end = nullptr;
      const bool hex = e[1] == 'x' || e[1] == 'X';
      const long code = std::strtol(e.c_str() + (hex ? 2 : 1), &end, hex ? 16 : 10);
      if (*end != '\0' || code <= 0 || code > 127) fail("entity &" + e + "; is not a supported character (ASCII only)");
      v += static_cast<char>(code);
    } else {
      fail("unknown entity &" + e + ";");
    }
    advance(semi - i_ + 1);
  }
}

bool Parser::nextTag() {
  while (true) {
    skipSpace();
    if (atEnd()) return false;
    if (peek() != '<') {
      fail("text outside an element (values go in the value=\"...\" attribute)");
    }
    if (startsWith("<!--")) {
      // XML forbids "--" inside a comment (other readers, e.g. ParaView's or Python's, refuse it).
      advance(4);
      const std::size_t dashes = s_.find("--", i_), end = s_.find("-->", i_);
      if (dashes != std::string::npos && dashes < end)
        fail("\"--\" inside a comment (XML does not allow it; write it another way)");
      skipUntil("-->", "comment");
    } else if (startsWith("<?")) {
      skipUntil("?>", "declaration");
    } else if (startsWith("<![CDATA[")) {
      fail("CDATA sections are not part of a deck");
    } else if (startsWith("<!")) {
      fail("DOCTYPE and other declarations are not part of a deck");
    } else {
      return true;
    }
  }
}

std::string trim(const std::string& t) {
  const auto a = t.find_first_not_of(" \t\r\n");
  if (a == std::string::npos) return "";
  const auto b = t.find_last_not_of(" \t\r\n");
  return t.substr(a, b - a + 1);
}

// Strict conversions: "" when `text` is the value, else what is wrong.
std::string toDouble(const std::string& raw, double& v) {
  const std::string t = trim(raw);
  if (t.empty()) return "is empty, expected a number";
  if (t.find_first_not_of("0123456789+-.eE") != std::string::npos) {
    std::string lower;
    for (char c : t) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (lower.find("nan") != std::string::npos || lower.find("inf") != std::string::npos)
      return "\"" + t + "\" is not a finite number";
    return "\"" + t + "\" is not a number";
  }
  char* end = nullptr;
  errno = 0;
  v = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size()) return "\"" + t + "\" is not a number";
  if (errno == ERANGE && std::abs(v) > 1.0) return "\"" + t + "\" is out of range for a double";
  // Below the smallest normal double (about 2.2e-308) strtod sets ERANGE and returns 0 or a subnormal
  // number with fewer digits ("1e-400" was read as 0).
  if (errno == ERANGE)
    return "\"" + t + "\" is too small for a double (its magnitude is below 2.2e-308; write 0 for zero)";
  if (!std::isfinite(v)) return "\"" + t + "\" is not a finite number";
  return "";
}

std::string toInt(const std::string& raw, int& v) {
  const std::string t = trim(raw);
  if (t.empty()) return "is empty, expected a whole number";
  std::size_t k = (t[0] == '+' || t[0] == '-') ? 1 : 0;
  if (k == t.size() || t.find_first_not_of("0123456789", k) != std::string::npos) {
    double d;
    if (toDouble(t, d).empty())
      return "\"" + t + "\" is not a whole number (write it without a decimal point or exponent)";
    return "\"" + t + "\" is not a whole number";
  }
  errno = 0;
  const long long x = std::strtoll(t.c_str(), nullptr, 10);
  if (errno == ERANGE || x > INT_MAX || x < INT_MIN) return "\"" + t + "\" is out of range for an int";
  v = static_cast<int>(x);
  return "";
}

std::string toBool(const std::string& raw, bool& v) {
  std::string t = trim(raw);
  for (char& c : t) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (t == "true") v = true;
  else if (t == "false") v = false;
  else return "\"" + trim(raw) + "\" is not a bool (true or false)";
  return "";
}

// "{a, b, c}" -> its entries (trimmed).
std::string splitArray(const std::string& raw, std::vector<std::string>& entries) {
  const std::string t = trim(raw);
  if (t.size() < 2 || t.front() != '{' || t.back() != '}') return "\"" + t + "\" is not an array; write {a, b, c}";
  const std::string inner = t.substr(1, t.size() - 2);
  if (trim(inner).empty()) return "";
  std::stringstream in(inner);
  for (std::string e; std::getline(in, e, ',');) entries.push_back(trim(e));
  if (!inner.empty() && inner.back() == ',') entries.push_back("");
  return "";
}

// Converts every entry with `convert` (toDouble, toInt) and sets the array; else what is wrong.
template <class T>
std::string setArray(ParameterList& list, const std::string& name, const std::vector<std::string>& entries,
                     std::string (*convert)(const std::string&, T&)) {
  Array<T> a;
  for (const auto& e : entries) {
    T v{};
    const std::string err = convert(e, v);
    if (!err.empty()) return err;
    a.push_back(v);
  }
  list.set(name, a);
  return "";
}

void setValue(ParameterList& list, const std::string& name, const std::string& type, const std::string& value,
              const std::function<void(const std::string&)>& fail) {
  std::string err;
  if (type == "double") {
    double v = 0;
    err = toDouble(value, v);
    if (err.empty()) list.set(name, v);
  } else if (type == "int") {
    int v = 0;
    err = toInt(value, v);
    if (err.empty()) list.set(name, v);
  } else if (type == "bool") {
    bool v = false;
    err = toBool(value, v);
    if (err.empty()) list.set(name, v);
  } else if (type == "string") {
    list.set(name, value);
  } else if (type == "Array(double)" || type == "Array(int)" || type == "Array(string)") {
    std::vector<std::string> entries;
    err = splitArray(value, entries);
    if (err.empty()) {
      if (type == "Array(double)") err = setArray<double>(list, name, entries, toDouble);
      else if (type == "Array(int)") err = setArray<int>(list, name, entries, toInt);
      else list.set(name, Array<std::string>(entries.begin(), entries.end()));
    }
  } else {
    fail("parameter \"" + name + "\" has type \"" + type +
         "\"; types are int, double, bool, string, Array(int), Array(double), Array(string)");
  }
  if (!err.empty()) fail("parameter \"" + name + "\" (" + type + "): " + err);
}

void Parser::checkEncoding() {
  if (s_.size() > kMaxBytes) fail(std::string("the file is ") + kTooLarge);
  // UTF-16 (a byte order mark, or ASCII characters each followed or preceded by a NUL byte) is what
  // some Windows editors save; its NUL bytes would otherwise end the first name read.
  if (startsWith("\xFF\xFE") || startsWith("\xFE\xFF") ||
      (s_.size() >= 2 && ((s_[0] != '\0' && s_[1] == '\0') || (s_[0] == '\0' && s_[1] != '\0'))))
    fail("the deck is UTF-16; save it as UTF-8");
  // A NUL byte is no text: C strings (and messages quoting the deck) end at it.
  if (const std::size_t nul = s_.find('\0'); nul != std::string::npos) {
    line_ = 1 + static_cast<int>(std::count(s_.begin(), s_.begin() + static_cast<std::ptrdiff_t>(nul), '\n'));
    fail("a NUL byte (byte " + std::to_string(nul + 1) + " of the file); a deck is UTF-8 text");
  }
  // Other encodings (a Latin-1 "é" in a beam's name) would pass through into the results' CSV and XML
  // files, which are UTF-8, and make them unreadable: the first byte that is not UTF-8 is an error.
  if (const std::size_t bad = firstNonUtf8(s_); bad != std::string::npos) {
    line_ = 1 + static_cast<int>(std::count(s_.begin(), s_.begin() + static_cast<std::ptrdiff_t>(bad), '\n'));
    char byte[8];
    std::snprintf(byte, sizeof byte, "0x%02X", static_cast<unsigned>(static_cast<unsigned char>(s_[bad])));
    fail(std::string("byte ") + byte + " (byte " + std::to_string(bad + 1) +
         " of the file) is not UTF-8 (a Latin-1 or Windows-1252 character?); a deck is UTF-8 text: save it as UTF-8");
  }
  // A UTF-8 byte order mark is valid UTF-8 and is skipped.
  if (startsWith("\xEF\xBB\xBF")) advance(3);
}

void Parser::closeTag(const std::string& tag) {
  skipSpace();
  if (peek() != '>') fail("expected '>' to close </" + tag + ">");
  advance();
  if (tag != "ParameterList" || stack_.empty()) fail("unexpected </" + tag + ">");
  stack_.pop_back();
  if (stack_.empty()) done_ = true;
}

std::vector<Attribute> Parser::attributes(const std::string& tag, bool& selfClosing) {
  std::vector<Attribute> attrs;
  selfClosing = false;
  const int tagLine = line_;
  while (true) {
    skipSpace();
    if (atEnd() || peek() == '<')
      fail("the <" + tag + "> tag opened on line " + std::to_string(tagLine) + " is not closed (missing '/>' or '>')");
    if (peek() == '/' && peek(1) == '>') {
      advance(2);
      selfClosing = true;
      return attrs;
    }
    if (peek() == '>') {
      advance();
      return attrs;
    }
    Attribute a;
    a.name = name();
    skipSpace();
    if (peek() != '=') fail("attribute " + a.name + " of <" + tag + "> has no value");
    advance();
    skipSpace();
    a.value = attributeValue();
    for (const auto& b : attrs)
      if (b.name == a.name) fail("attribute " + a.name + " given twice in <" + tag + ">");
    attrs.push_back(a);
  }
}

void Parser::claim(const std::string& n, int line) {
  Open& parent = stack_.back();
  const auto [it, fresh] = parent.names.emplace(n, line);
  if (!fresh)
    fail("\"" + n + "\" is given twice in \"" + parent.path + "\" (first on line " + std::to_string(it->second) + ")");
}

void Parser::openList(const std::vector<Attribute>& attrs, bool selfClosing, int line) {
  const std::string* n = attributeNamed(attrs, "name");
  if (stack_.empty()) {
    root_.setName(n ? *n : "ANONYMOUS");
    stack_.push_back({&root_, n ? *n : "ANONYMOUS", {}});
  } else {
    if (!n) fail("a nested <ParameterList> needs a name attribute");
    if (static_cast<int>(stack_.size()) >= kMaxDepth)
      fail("lists nested deeper than " + std::to_string(kMaxDepth) + " levels");
    claim(*n, line);
    ParameterList& sub = stack_.back().list->sublist(*n);
    stack_.push_back({&sub, stack_.back().path + "/" + *n, {}});
  }
  if (selfClosing) {
    stack_.pop_back();
    if (stack_.empty()) done_ = true;
  }
}

void Parser::parameter(const std::vector<Attribute>& attrs, bool selfClosing, int line) {
  if (stack_.empty()) fail("a <Parameter> outside any <ParameterList>");
  if (!selfClosing) fail("<Parameter> must be closed in its own tag: <Parameter name=... type=... value=.../>");
  const std::string *n = attributeNamed(attrs, "name"), *type = attributeNamed(attrs, "type"),
                    *value = attributeNamed(attrs, "value");
  if (!n) fail("a <Parameter> without a name attribute");
  if (!type) fail("parameter \"" + *n + "\" has no type attribute (int, double, bool, string, Array(...))");
  if (!value) fail("parameter \"" + *n + "\" has no value attribute");
  for (const auto& a : attrs)
    if (a.name != "name" && a.name != "type" && a.name != "value" && a.name != "id" && a.name != "docString" &&
        a.name != "isDefault" && a.name != "isUsed" && a.name != "validatorId")
      fail("parameter \"" + *n + "\" has an unknown attribute " + a.name);
  claim(*n, line);
  setValue(*stack_.back().list, *n, *type, *value, [&](const std::string& m) { fail(m); });
}

ParameterList Parser::parse() {
  checkEncoding();
  while (nextTag()) {
    if (done_) fail("content after the top-level ParameterList has ended");
    advance();  // '<'
    const bool closing = peek() == '/';
    if (closing) advance();
    const std::string tag = name();
    if (closing) {
      closeTag(tag);
      continue;
    }
    bool selfClosing = false;
    const std::vector<Attribute> attrs = attributes(tag, selfClosing);
    const int line = line_;
    if (tag == "ParameterList") {
      openList(attrs, selfClosing, line);
    } else if (tag == "Parameter") {
      parameter(attrs, selfClosing, line);
    } else if (tag == "Validators" && !stack_.empty() && stack_.size() == 1) {
      // Written by Teuchos after the top-level list's entries; nothing in a deck uses validators.
      if (!selfClosing) skipUntil("</Validators>", "<Validators>");
    } else {
      fail("unknown element <" + tag + ">; a deck holds <ParameterList> and <Parameter> elements");
    }
  }
  if (!done_) {
    if (stack_.empty()) fail("no <ParameterList> found");
    fail("the file ends inside <ParameterList name=\"" + stack_.back().path + "\"> (a closing tag is missing)");
  }
  return root_;
}

}  // namespace

double physicalMemory() { return double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGESIZE)); }

double usableMemory(std::string* note) {
  const double physical = physicalMemory();
  struct rlimit limit {};
  if (getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY && double(limit.rlim_cur) < physical) {
    if (note) {
      char buf[120];
      std::snprintf(buf, sizeof buf, "; this process may use %.1f GB (its address-space limit, ulimit -v)",
                    double(limit.rlim_cur) / 1e9);
      *note = buf;
    }
    return double(limit.rlim_cur);
  }
  return physical;
}

ParameterList parseParameterXml(const std::string& text, const std::string& source) {
  return Parser(text, source).parse();
}

ParameterList readParameterXmlFile(const std::string& path, std::string* sha256) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError("file \"" + path + "\" does not exist");
  if (std::filesystem::is_directory(path, ec)) throw InputError("\"" + path + "\" is a directory, not a deck file");
  const auto size = std::filesystem::file_size(path, ec);
  if (!ec && size > kMaxBytes) throw InputError("file \"" + path + "\" is " + kTooLarge);
  // Reading takes up to kReadBytesPerByte per deck byte (docs/faults.md, "Input"): at most 80 % of the
  // memory (the 256 MB limit is the smaller one from 4 GB up).
  std::string limited;
  const double usable = usableMemory(&limited);
  if (!ec && usable > 0 && kReadBytesPerByte * double(size) > 0.8 * usable) {
    char buf[300];
    std::snprintf(buf, sizeof buf,
                  "file \"%s\" is %.0f MB, which takes about %.1f GB to read (%.0f bytes per byte); "
                  "this machine has %.1f GB",
                  path.c_str(), double(size) / 1e6, kReadBytesPerByte * double(size) / 1e9, kReadBytesPerByte,
                  physicalMemory() / 1e9);
    throw InputError(buf + limited);
  }
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError("file \"" + path + "\" cannot be read");
  // The text once, at its size (through a string stream it was there twice, and the stream's buffer
  // grew by doubling: up to 4 bytes per deck byte while the lists were built).
  std::string text;
  if (!ec) {
    text.resize(size);
    f.read(text.data(), static_cast<std::streamsize>(size));
    text.resize(static_cast<std::size_t>(f.gcount()));
  }
  // Grown since, or no size known (a pipe, a device): the rest, a chunk at a time, within the limit and
  // only while it is text (/dev/zero or /dev/urandom would otherwise be read until memory runs out).
  std::vector<char> chunk;
  while (f.peek() != std::ifstream::traits_type::eof()) {
    chunk.resize(std::size_t(1) << 20);  // (allocated only when there is a rest)
    f.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    const auto got = static_cast<std::size_t>(f.gcount());
    const auto nul = std::find(chunk.begin(), chunk.begin() + got, '\0') - chunk.begin();
    if (static_cast<std::size_t>(nul) < got)
      throw InputError("file \"" + path + "\" holds a NUL byte (byte " + std::to_string(text.size() + nul + 1) +
                       "); a deck is UTF-8 text");
    if (text.size() + got > kMaxBytes) throw InputError("file \"" + path + "\" is " + kTooLarge);
    text.append(chunk.data(), got);
  }
  if (sha256) *sha256 = core::sha256Hex(text);
  return parseParameterXml(text, path);
}

namespace {
template <class T, class F> std::string arrayText(const Array<T>& a, F text) {
  std::string s = "{";
  for (std::size_t i = 0; i < std::size_t(a.size()); ++i) s += (i ? ", " : "") + text(a[i]);
  return s + "}";
}
}  // namespace

std::string deckType(const Teuchos::ParameterEntry& e) {
  if (e.isType<double>()) return "double";
  if (e.isType<int>()) return "int";
  if (e.isType<bool>()) return "bool";
  if (e.isType<std::string>()) return "string";
  if (e.isType<Array<double>>()) return "Array(double)";
  if (e.isType<Array<int>>()) return "Array(int)";
  if (e.isType<Array<std::string>>()) return "Array(string)";
  throw std::logic_error("a parameter of type " + e.getAny().typeName() + ", which decks do not have");
}

std::string deckValue(const Teuchos::ParameterEntry& e) {
  const auto number = [](double v) { return core::shortest(v); };
  const auto whole = [](int v) { return std::to_string(v); };
  if (e.isType<double>()) return number(Teuchos::getValue<double>(e));
  if (e.isType<int>()) return whole(Teuchos::getValue<int>(e));
  if (e.isType<bool>()) return Teuchos::getValue<bool>(e) ? "true" : "false";
  if (e.isType<std::string>()) return Teuchos::getValue<std::string>(e);
  if (e.isType<Array<double>>()) return arrayText(Teuchos::getValue<Array<double>>(e), number);
  if (e.isType<Array<int>>()) return arrayText(Teuchos::getValue<Array<int>>(e), whole);
  if (e.isType<Array<std::string>>())
    return arrayText(Teuchos::getValue<Array<std::string>>(e), [](const std::string& v) { return v; });
  throw std::logic_error("a parameter of type " + e.getAny().typeName() + ", which decks do not have");
}

std::string xmlEscaped(const std::string& text) {
  std::string e;
  for (const char c : text) {
    if (c == '&') e += "&amp;";
    else if (c == '<') e += "&lt;";
    else if (c == '>') e += "&gt;";
    else if (c == '"') e += "&quot;";
    else e += c;
  }
  return e;
}

Teuchos::ParameterList& sublistAtPath(Teuchos::ParameterList& list, const std::string& path, bool create) {
  Teuchos::ParameterList* at = &list;
  std::size_t start = 0;
  while (start <= path.size()) {
    const auto slash = path.find('/', start);
    const std::string name = path.substr(start, slash == std::string::npos ? std::string::npos : slash - start);
    if (name.empty()) throw core::InputError("parameter path \"" + path + "\" has an empty name");
    if (at->isParameter(name) && !at->isSublist(name))
      throw core::InputError("\"" + name + "\" in path \"" + path + "\" is a parameter, not a sublist");
    if (!create && !at->isSublist(name)) throw core::InputError("path \"" + path + "\" names no sublist");
    at = &at->sublist(name);
    if (slash == std::string::npos) break;
    start = slash + 1;
  }
  return *at;
}

}  // namespace bc::input
