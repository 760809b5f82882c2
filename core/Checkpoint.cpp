#include "Checkpoint.hpp"

#include <map>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "Parameters.hpp"

namespace bc::core {

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
    label("block").word(id.first).integer(block.offset).integer(block.size).integer(static_cast<long long>(id.second.size()));
    for (long long k : id.second) integer(k);
  }
}

CheckpointIn::CheckpointIn(const std::string& text, const std::string& source) : in_(text), source_(source) {}

void CheckpointIn::fail(const std::string& what) const {
  throw InputError("checkpoint " + source_ + " cannot be used: " + what);
}

std::string CheckpointIn::next() {
  std::string t;
  if (!(in_ >> t)) fail("it ends early (it is damaged)");
  return t;
}

void CheckpointIn::label(const std::string& name) {
  const std::string t = next();
  if (t != name) fail("expected \"" + name + "\", found \"" + t + "\" (it is damaged)");
}

double CheckpointIn::real() {
  const std::string t = next();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size() || errno == ERANGE) fail("\"" + t + "\" is not a number (it is damaged)");
  return v;
}

long long CheckpointIn::integer() {
  const std::string t = next();
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(t.c_str(), &end, 10);
  if (end != t.c_str() + t.size() || errno == ERANGE) fail("\"" + t + "\" is not a whole number (it is damaged)");
  return v;
}

std::string CheckpointIn::word() { return next(); }

void CheckpointIn::state(State& s) {
  label("nodes");
  if (integer() != s.numNodes()) fail("it is for a model with another number of nodes");
  for (int n = 0; n < s.numNodes(); ++n) {
    label("node");
    if (integer() != n) fail("nodes out of order (it is damaged)");
    for (double& v : s.position[n].v) v = real();
    for (double& v : s.rotation[n].m) v = real();
    for (double& v : s.rotationVector[n].v) v = real();
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
    if (block.offset != next || block.size <= 0 || block.offset + block.size > m) fail("extra unknowns out of order (it is damaged)");
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
