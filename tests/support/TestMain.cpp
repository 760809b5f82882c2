// GoogleTest main for tests that need MPI and Kokkos (Tpetra::ScopeGuard); only rank 0 reports.
#include <gtest/gtest.h>

#include <Tpetra_Core.hpp>

#include "constraints/EnforcerRegistry.hpp"

int main(int argc, char** argv) {
  Tpetra::ScopeGuard scope(&argc, &argv);
  bc::constraints::registerBuiltinEnforcers();
  ::testing::InitGoogleTest(&argc, argv);
  if (Tpetra::getDefaultComm()->getRank() != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  return RUN_ALL_TESTS();
}
