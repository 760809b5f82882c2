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
//
// Its last line is "sha256 <64 hex digits>", the SHA-256 of every byte before that line: a file whose
// checksum does not match is refused. The content is also checked where a recomputed checksum would
// let an edit through: the format and BeamContact versions, counters >= 0, every real finite, the
// load factor against the load stepping, the reference geometry against the model's (StaticSolver,
// ContactManager), its step against the results directory's steps.csv (ResultsWriter). Every refusal
// is an InputError "checkpoint FILE cannot be used: WHAT", thrown before the results directory changes.
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
  // The file's content: the lines written, then "sha256 <hex>" over them.
  std::string text() const;

 private:
  std::ostringstream out_;
};

class CheckpointIn {
 public:
  CheckpointIn(const std::string& text, const std::string& source);
  // Checks the last line, "sha256 <hex>", against the SHA-256 of every byte before it.
  void verifyChecksum() const;
  // After the last item: the checksum line, and nothing after it.
  void finish();
  // Reads the next token and checks that it is `name`.
  void label(const std::string& name);
  double real();  // a finite number (nan and inf are refused)
  long long integer();
  std::string word();
  // Reads a state written by CheckpointOut::state into `s` (whose reference and size are the model's).
  void state(State& s);
  // Throws an InputError naming the checkpoint: it is damaged or from another model.
  [[noreturn]] void fail(const std::string& what) const;

 private:
  std::string next();
  // " on line N": the line of the token read last.
  std::string where() const;
  std::string text_;
  std::istringstream in_;
  std::size_t tokenStart_ = 0;
  std::string source_;
};

// The format the checkpoint's first line states ("beamcontact-checkpoint 6"); a file of another format
// is refused.
inline constexpr int kCheckpointFormat = 6;

// A number as the shortest text that reads back to it (for messages).
std::string shortest(double v);

// FNV-1a fingerprint of a text (the deck, without its Output sublist).
std::uint64_t fingerprint(const std::string& text);

}  // namespace bc::core
