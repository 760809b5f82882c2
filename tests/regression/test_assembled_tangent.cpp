// The assembled tangent (all contributions, supports applied) against central finite differences of
// the assembled residual, at a deformed large-rotation state of a cantilever. Also runs on 2 ranks.
#include <gtest/gtest.h>

#include <cmath>

#include "support/AssembledTangent.hpp"
#include "support/TestSupport.hpp"

using namespace bc;

TEST(AssembledTangent, MatchesCentralDifferencesOfTheResidual) {
  auto comm = Tpetra::getDefaultComm();
  const double EI = 30000.0 * 2.0 * 64.0 / 12.0;
  const double P = 3.0 * EI / (100.0 * 100.0);
  auto p = test::problemFromXml(test::cantileverXml(100.0, 2.0, 4.0, 30000.0, 0.25, 6,
                                                    "0," + test::num(0.3 * P) + "," + test::num(P),
                                                    test::num(0.2 * P) + ",0,0", 3));
  const auto run = test::runQuiet(p, comm, "assembled_tangent");
  ASSERT_TRUE(run.report.completed);
  core::State s = run.finalState;
  // Move away from equilibrium so that the residual is not zero.
  s.applyNodeIncrement(3, std::array<double, 6>{0.5, -0.3, 0.2, 0.05, -0.1, 0.08}.data());

  core::Assembler a(comm, p.model);
  const auto [err, kmax] = test::assembledTangentError(a, s, 0.7);
  if (comm->getRank() == 0) std::printf("assembled tangent: max |K - FD| / max |K| = %.3e\n", err / kmax);
  EXPECT_LT(err / kmax, 1e-6);
}
