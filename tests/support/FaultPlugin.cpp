// A plug-in for the fault tests (tests/cli/plugin_faults.py, the bad-input catalogue). What it does is
// set by the environment:
//   BC_TEST_PLUGIN_MARKER=FILE   writes FILE when the library is registered (shows whether it was loaded)
//   BC_TEST_PLUGIN=MODE[@RANK]   with RANK, only on that MPI rank (OMPI_COMM_WORLD_RANK):
//     register-fail    registration throws a std::runtime_error
//     register-odd     registration throws an int (not a std::exception)
//     hijack           registers a strategy under the built-in name "Penalty"
//     construct-fail   the strategy "Test Penalty"'s constructor throws
//     evaluate-fail    its evaluation throws (inside Newton)
//     evaluate-exit    its evaluation calls exit(0)
//     evaluate-abort   its evaluation calls std::abort() (the process ends by SIGABRT)
//     multipliers      also registers "Test Lagrange Multiplier", the built-in Lagrange Multiplier
//                      strategy under another name (a plug-in that adds multiplier rows)
// Otherwise it registers "Test Penalty", the built-in Penalty strategy under another name.
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "constraints/LagrangeMultiplierEnforcer.hpp"
#include "constraints/PenaltyEnforcer.hpp"
#include "constraints/Plugin.hpp"

namespace {

bool mode(const char* wanted) {
  const char* v = std::getenv("BC_TEST_PLUGIN");
  if (!v) return false;
  const std::string spec(v);
  const auto at = spec.find('@');
  if (spec.substr(0, at) != wanted) return false;
  if (at == std::string::npos) return true;
  const char* rank = std::getenv("OMPI_COMM_WORLD_RANK");
  return std::atoi(spec.c_str() + at + 1) == (rank ? std::atoi(rank) : 0);
}

class TestPenalty : public bc::constraints::PenaltyEnforcer {
 public:
  static const char* name() { return "Test Penalty"; }
  static const char* description() { return "the Penalty strategy under another name (fault tests)"; }
  static const bc::core::ParameterSpec& spec() { return PenaltyEnforcer::spec(); }
  explicit TestPenalty(const Teuchos::ParameterList& p) : PenaltyEnforcer(p) {
    if (mode("construct-fail")) throw std::runtime_error("Test Penalty's constructor failed on purpose");
  }
  std::string type() const override { return name(); }
  bc::constraints::PointResult evaluate(const bc::constraints::ContactPoint& p, const bc::constraints::PointState& s,
                                        double* f, double* K) const override {
    if (mode("evaluate-fail")) throw std::runtime_error("Test Penalty's evaluation failed on purpose");
    if (mode("evaluate-exit")) std::exit(0);
    if (mode("evaluate-abort")) std::abort();
    return PenaltyEnforcer::evaluate(p, s, f, K);
  }
};

class Hijack : public TestPenalty {
 public:
  static const char* name() { return "Penalty"; }
  using TestPenalty::TestPenalty;
};

class TestLagrange : public bc::constraints::LagrangeMultiplierEnforcer {
 public:
  static const char* name() { return "Test Lagrange Multiplier"; }
  static const char* description() { return "the Lagrange Multiplier strategy under another name (fault tests)"; }
  static const bc::core::ParameterSpec& spec() { return LagrangeMultiplierEnforcer::spec(); }
  using LagrangeMultiplierEnforcer::LagrangeMultiplierEnforcer;
  std::string type() const override { return name(); }
};

void registerAll() {
  if (const char* marker = std::getenv("BC_TEST_PLUGIN_MARKER")) {
    if (std::FILE* f = std::fopen(marker, "w")) {
      std::fputs("loaded\n", f);
      std::fclose(f);
    }
  }
  if (mode("register-fail")) throw std::runtime_error("registration failed on purpose");
  if (mode("register-odd")) throw 42;
  if (mode("hijack")) bc::constraints::registerEnforcer<Hijack>();
  else bc::constraints::registerEnforcer<TestPenalty>();
  if (mode("multipliers")) bc::constraints::registerEnforcer<TestLagrange>();
}

}  // namespace

BEAMCONTACT_PLUGIN(registerAll();)
