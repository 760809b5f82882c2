// A restart continues as if the run had never stopped, for every strategy of the registry (each
// strategy's own state goes through the checkpoint: multipliers, augmentations, friction forces, stick
// and slip, active sets): Example 1 slid and pressed (beam 2's ends moved by (40, 0, -20) at T = 1,
// friction 0.5) over its first 15 increments of 50, with a checkpoint after step 8; then a fresh problem
// built from the same deck restarts from that checkpoint in the same results directory and solves steps
// 9 to 15 again. The final state, every contact point's committed values and every results table equal
// the uninterrupted run's exactly (the checkpoint keeps every number bit for bit, and the steps after
// it are the same arithmetic).
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <sstream>

#include "constraints/EnforcerRegistry.hpp"
#include "core/Checkpoint.hpp"
#include "support/ContactDecks.hpp"

using namespace bc;
using namespace bc::test;

namespace {

// The deck of Example 1 with the strategy `entry`; a strategy the deck has no sublist for takes its
// specification's example values.
Deck restartDeck(const constraints::EnforcerEntry& entry) {
  Deck deck = example1(entry.name);
  Deck& enforcement = input::sublistAtPath(deck, "Contact/Enforcement", false);
  if (!enforcement.isSublist(entry.name)) enforcement.sublist(entry.name).setParameters(entry.spec->example());
  return deck;
}

struct SolvedRun {
  core::RunResult result;
  input::Problem problem;
};

// The deck's first 15 increments with a checkpoint after every 8th step, from the start or restarted.
SolvedRun solve(const Deck& deck, const std::string& directory, bool restart) {
  SolvedRun run{{}, input::buildProblem(deck, "restart")};
  auto& factors = run.problem.solver.loadFactors;
  factors.resize(15);
  core::RunOptions o;
  o.outputDirectory = directory;
  o.writeVtk = false;
  o.progress = false;
  o.overwrite = true;
  o.checkpointEvery = 8;
  o.restart = restart;
  o.fingerprint = "restart-test";
  run.result =
      core::simulate(run.problem.model, run.problem.solver, run.problem.linearSolver, o, Tpetra::getDefaultComm());
  return run;
}

std::string fileText(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The components of a vector or a rotation, for exact comparison.
std::vector<double> components(const math::Vec3d& x) { return {x.v, x.v + 3}; }
std::vector<double> components(const math::Mat3d& R) { return {R.m, R.m + 9}; }

// The results tables whose rows hold no measured times.
const char* const kTables[] = {"steps.csv", "tracked_points.csv", "reactions.csv", "contact_points.csv"};

}  // namespace

TEST(Restart, EveryStrategyContinuesFromItsCheckpointAsIfNeverStopped) {
  for (const auto& entry : constraints::enforcers()) {
    SCOPED_TRACE(entry.name);
    const Deck deck = restartDeck(entry);
    const std::string directory = scratchDirectory("restart_" + core::CheckpointOut::token(entry.name));
    const SolvedRun whole = solve(deck, directory, false);
    ASSERT_TRUE(whole.result.report.completed) << whole.result.report.failure;
    ASSERT_EQ(whole.result.steps.size(), 15u);
    std::map<std::string, std::string> tables;
    for (const char* t : kTables) tables[t] = fileText(directory + "/" + t);
    ASSERT_FALSE(tables["contact_points.csv"].empty());

    const SolvedRun resumed = solve(deck, directory, true);
    ASSERT_TRUE(resumed.result.report.completed) << resumed.result.report.failure;
    EXPECT_EQ(resumed.result.restartedAtStep, 8);
    EXPECT_EQ(resumed.result.steps.size(), 7u);

    const core::State &a = whole.result.finalState, &b = resumed.result.finalState;
    ASSERT_EQ(a.position.size(), b.position.size());
    for (std::size_t n = 0; n < a.position.size(); ++n) {
      EXPECT_EQ(components(a.position[n]), components(b.position[n])) << "node " << n;
      EXPECT_EQ(components(a.rotation[n]), components(b.rotation[n])) << "node " << n;
      EXPECT_EQ(components(a.rotationVector[n]), components(b.rotationVector[n])) << "node " << n;
    }
    EXPECT_EQ(a.extra.values(), b.extra.values());

    const auto &pa = whole.problem.contact->points(), &pb = resumed.problem.contact->points();
    ASSERT_EQ(pa.size(), pb.size());
    int active = 0, slipping = 0;
    for (auto i = pa.begin(), j = pb.begin(); i != pa.end(); ++i, ++j) {
      ASSERT_EQ(i->first, j->first);
      const auto &x = i->second, &y = j->second;
      EXPECT_EQ(x.gap, y.gap);
      EXPECT_EQ(x.result.active, y.result.active);
      EXPECT_EQ(x.result.lambdaN, y.result.lambdaN);
      for (int k = 0; k < 2; ++k) {
        EXPECT_EQ(x.result.lambdaT[k], y.result.lambdaT[k]);
        EXPECT_EQ(x.result.slip[k], y.result.slip[k]);
      }
      EXPECT_EQ(components(x.tangentialForce), components(y.tangentialForce));
      active += x.result.active;
      slipping += x.result.active && (x.result.slip[0] || x.result.slip[1]);
    }
    std::printf("%-20s restarted at step 8 of 15: %d points active (%d slipping), final state and tables equal\n",
                entry.name.c_str(), active, slipping);
    EXPECT_GT(active, 0);
    for (const char* t : kTables) EXPECT_EQ(fileText(directory + "/" + t), tables[t]) << t;
  }
}
