// Checkpoint files: the complete state of a run after a converged step, from which
// `beamcontact run DECK --restart DIR` continues as if it had never stopped.
//
// The file (checkpoint.txt in the results directory) is text: labelled lines of whitespace-separated
// tokens, every real number in C99 hexadecimal notation ("%a"), so it is read back bit for bit on any
// machine and any number of ranks (the state is replicated, so the rank count may change). It holds
// the deck's fingerprint (a restart with another deck is refused), the solver's position in the load
// stepping (increment, load factor, cut level), the converged state and the one before it (the
// predictor's), and each contribution's history (contact points with their multipliers, friction
// forces, active sets and stick/slip states). It is written through a temporary file and a rename.
#pragma once
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "State.hpp"

namespace bc::core {

class CheckpointOut {
 public:
  // Starts a labelled line; the values that follow belong to it.
  CheckpointOut& label(const std::string& name);
  CheckpointOut& real(double v);
  CheckpointOut& integer(long long v);
  CheckpointOut& word(const std::string& w);  // whitespace is written as '_' (see token)
  // A name as word() writes it: whitespace replaced by '_'.
  static std::string token(std::string w);
  void state(const State& s);
  std::string text() const { return out_.str() + "\n"; }

 private:
  std::ostringstream out_;
};

class CheckpointIn {
 public:
  CheckpointIn(const std::string& text, const std::string& source);
  // Reads the next token and checks that it is `name`.
  void label(const std::string& name);
  double real();
  long long integer();
  std::string word();
  // Reads a state written by CheckpointOut::state into `s` (whose reference and size are the model's).
  void state(State& s);
  // Throws an InputError naming the checkpoint: it is damaged or from another model.
  [[noreturn]] void fail(const std::string& what) const;

 private:
  std::string next();
  std::istringstream in_;
  std::string source_;
};

// FNV-1a fingerprint of a text (the deck, without its Output sublist).
std::uint64_t fingerprint(const std::string& text);

}  // namespace bc::core
