#include "Checkpoint.hpp"

#include <algorithm>
#include <charconv>
#include <map>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "Parameters.hpp"
#include "Sha256.hpp"

namespace bc::core {

std::string shortest(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

std::string CheckpointOut::text() const {
  const std::string body = out_.str() + "\n";
  return body + "sha256 " + sha256Hex(body) + "\n";
}

CheckpointOut& CheckpointOut::label(const std::string& name) {
  if (out_.tellp() > 0) out_ << '\n';
  out_ << name;
  return *this;
}

CheckpointOut& CheckpointOut::real(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, " %a", v);
  out_ << buf;
  return *this;
}

CheckpointOut& CheckpointOut::integer(long long v) {
  out_ << ' ' << v;
  return *this;
}

std::string CheckpointOut::token(std::string w) {
  for (char& c : w)
    if (std::isspace(static_cast<unsigned char>(c))) c = '_';
  return w.empty() ? "_" : w;
}

CheckpointOut& CheckpointOut::word(const std::string& w) {
  out_ << ' ' << token(w);
  return *this;
}

void CheckpointOut::state(const State& s) {
  label("nodes").integer(s.numNodes());
  for (int n = 0; n < s.numNodes(); ++n) {
    label("node").integer(n);
    for (double v : s.position[n].v) real(v);
    for (double v : s.rotation[n].m) real(v);
    for (double v : s.rotationVector[n].v) real(v);
  }
  label("extra").integer(static_cast<long long>(s.extra.size()));
  integer(static_cast<long long>(s.extra.blocks().size()));
  for (double v : s.extra.values()) real(v);
  for (const auto& [id, block] : s.extra.blocks()) {
    label("block")
        .word(id.first)
        .integer(block.offset)
        .integer(block.size)
        .integer(static_cast<long long>(id.second.size()));
    for (long long k : id.second) integer(k);
  }
}

CheckpointIn::CheckpointIn(const std::string& text, const std::string& source)
    : text_(text), in_(text), source_(source) {}

void CheckpointIn::verifyChecksum() const {
  // The last line: "sha256 " and 64 lower-case hexadecimal digits, then the file's final new line.
  const std::size_t n = text_.size();
  const std::size_t cut = n >= 2 ? text_.rfind('\n', n - 2) : std::string::npos;
  const std::size_t start = cut == std::string::npos ? 0 : cut + 1;
  const std::string line = n > 0 && text_.back() == '\n' ? text_.substr(start, n - 1 - start) : std::string();
  const bool wellFormed = line.size() == 7 + 64 && line.compare(0, 7, "sha256 ") == 0 &&
                          std::all_of(line.begin() + 7, line.end(),
                                      [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); });
  if (!wellFormed)
    fail("its last line is not its checksum (\"sha256\" and 64 hexadecimal digits): it was cut short or damaged");
  if (sha256Hex(text_.substr(0, start)) != line.substr(7))
    fail("its SHA-256 checksum does not match its content: it was edited or damaged after it was written");
}

void CheckpointIn::finish() {
  label("sha256");
  next();
  in_ >> std::ws;
  if (in_.peek() != std::char_traits<char>::eof()) fail("text follows its checksum line (it is damaged)");
}

std::string CheckpointIn::where() const {
  const auto end = text_.begin() + static_cast<std::ptrdiff_t>(std::min(tokenStart_, text_.size()));
  return " on line " + std::to_string(1 + std::count(text_.begin(), end, '\n'));
}

void CheckpointIn::fail(const std::string& what) const {
  throw InputError("checkpoint " + source_ + " cannot be used: " + what);
}

std::string CheckpointIn::next() {
  in_ >> std::ws;
  const auto at = in_.tellg();
  std::string t;
  if (!(in_ >> t)) fail("it ends early (it is damaged)");
  if (at >= 0) tokenStart_ = static_cast<std::size_t>(at);
  return t;
}

void CheckpointIn::label(const std::string& name) {
  const std::string t = next();
  if (t != name) fail("expected \"" + name + "\", found \"" + t + "\"" + where() + " (it is damaged)");
}

double CheckpointIn::real() {
  const std::string t = next();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size() || errno == ERANGE)
    fail("\"" + t + "\" is not a number" + where() + " (it is damaged)");
  if (!std::isfinite(v)) fail("\"" + t + "\" is not a finite number" + where());
  return v;
}

long long CheckpointIn::integer() {
  const std::string t = next();
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(t.c_str(), &end, 10);
  if (end != t.c_str() + t.size() || errno == ERANGE)
    fail("\"" + t + "\" is not a whole number" + where() + " (it is damaged)");
  return v;
}

std::string CheckpointIn::word() { return next(); }

void CheckpointIn::state(State& s) {
  label("nodes");
  const long long nodes = integer();
  if (nodes != s.numNodes())
    fail("its state" + where() + " has " + std::to_string(nodes) + " nodes, the model " + std::to_string(s.numNodes()));
  for (int n = 0; n < s.numNodes(); ++n) {
    label("node");
    if (integer() != n) fail("nodes out of order" + where() + " (it is damaged)");
    for (double& v : s.position[n].v) v = real();
    for (double& v : s.rotation[n].m) v = real();
    for (double& v : s.rotationVector[n].v) v = real();
    // A rotation is orthonormal with determinant 1, and the rotation vector (updated at every
    // converged step) is its logarithm; both hold to round-off (about 1e-15 per update).
    const Mat3d& R = s.rotation[n];
    const Mat3d RtR = math::transpose(R) * R, I = math::identity3<double>();
    double off = 0.0;
    for (int k = 0; k < 9; ++k) off = std::max(off, std::abs(RtR.m[k] - I.m[k]));
    const double det = R(0, 0) * (R(1, 1) * R(2, 2) - R(1, 2) * R(2, 1)) -
                       R(0, 1) * (R(1, 0) * R(2, 2) - R(1, 2) * R(2, 0)) +
                       R(0, 2) * (R(1, 0) * R(2, 1) - R(1, 1) * R(2, 0));
    if (off > 1e-8 || det <= 0.0)
      fail("node " + std::to_string(n) + "'s rotation is not a rotation matrix (R^T R - I up to " + shortest(off) +
           ", det " + shortest(det) + ")" + where());
    const Mat3d E = math::expSO3(s.rotationVector[n]);
    double diff = 0.0;
    for (int k = 0; k < 9; ++k) diff = std::max(diff, std::abs(E.m[k] - R.m[k]));
    if (diff > 1e-8)
      fail("node " + std::to_string(n) + "'s rotation vector does not give its rotation (they differ by " +
           shortest(diff) + ")" + where());
  }
  label("extra");
  const long long m = integer(), nb = integer();
  if (m < 0 || m > 100000000 || nb < 0 || nb > m) fail("bad number of extra unknowns");
  std::vector<double> values(static_cast<std::size_t>(m));
  for (double& v : values) v = real();
  std::map<std::pair<std::string, ExtraUnknowns::Key>, ExtraUnknowns::Block> blocks;
  long long next = 0;
  for (long long b = 0; b < nb; ++b) {
    label("block");
    const std::string owner = word();
    ExtraUnknowns::Block block;
    block.offset = static_cast<int>(integer());
    block.size = static_cast<int>(integer());
    const long long nk = integer();
    if (nk < 0 || nk > 64) fail("bad extra-unknown key");
    ExtraUnknowns::Key key(static_cast<std::size_t>(nk));
    for (long long& k : key) k = integer();
    if (block.offset != next || block.size <= 0 || block.offset + block.size > m)
      fail("extra unknowns out of order (it is damaged)");
    next += block.size;
    blocks[{owner, key}] = block;
  }
  if (next != m) fail("extra unknowns without an owner (it is damaged)");
  s.extra.assign(std::move(blocks), std::move(values));
}

std::uint64_t fingerprint(const std::string& text) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

}  // namespace bc::core
