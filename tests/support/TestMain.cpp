// GoogleTest main for tests that need MPI and Kokkos (Tpetra::ScopeGuard); only rank 0 reports.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include <Tpetra_Core.hpp>

#include "constraints/EnforcerRegistry.hpp"

int main(int argc, char** argv) {
  // Listing the cases (CTest's discovery, at build time) needs neither MPI nor Kokkos, so it starts
  // neither.
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--gtest_list_tests") {
      ::testing::InitGoogleTest(&argc, argv);
      return RUN_ALL_TESTS();
    }
  // Open MPI refuses to start as root without these (the tests' CTest entries run the program
  // without mpirun); a value set outside stays.
  setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 0);
  setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 0);
  Tpetra::ScopeGuard scope(&argc, &argv);
  bc::constraints::registerBuiltinEnforcers();
  ::testing::InitGoogleTest(&argc, argv);
  if (Tpetra::getDefaultComm()->getRank() != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  return RUN_ALL_TESTS();
}
