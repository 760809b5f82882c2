// A failed allocation is recognised and reported in one line: std::bad_alloc, and Kokkos' report of
// one (a std::runtime_error over several lines), produced here by asking Kokkos for a 2^60-byte view.
#include <gtest/gtest.h>

#include <new>
#include <stdexcept>
#include <string>

#include <Kokkos_Core.hpp>

#include "core/Faults.hpp"

using namespace bc::core;

TEST(OutOfMemory, KokkosAllocationFailureIsOneLine) {
  std::string what, line;
  bool recognised = false;
  try {
    Kokkos::View<double*> huge("a huge view", std::size_t(1) << 57);
  } catch (const std::exception& e) {
    what = e.what();
    recognised = isOutOfMemory(e);
    line = oneLine(e);
  }
  ASSERT_FALSE(what.empty()) << "Kokkos allocated 2^60 bytes";
  EXPECT_NE(what.find('\n'), std::string::npos) << what;  // (why it needs a translation)
  EXPECT_TRUE(recognised) << what;
  EXPECT_EQ(line.find('\n'), std::string::npos) << line;
  EXPECT_EQ(line.rfind("out of memory (Kokkos could not allocate ", 0), 0u) << line;
  EXPECT_NE(line.find("for \"a huge view\""), std::string::npos) << line;
}

TEST(OutOfMemory, BadAllocAndOthers) {
  EXPECT_TRUE(isOutOfMemory(std::bad_alloc()));
  EXPECT_EQ(oneLine(std::bad_alloc()).rfind("out of memory (", 0), 0u);
  const OutOfMemory named("out of memory: UMFPACK ran out");
  EXPECT_EQ(oneLine(named), "out of memory: UMFPACK ran out");
  const std::runtime_error other("a singular matrix\nand its trace");
  EXPECT_FALSE(isOutOfMemory(other));
  EXPECT_EQ(oneLine(other), "a singular matrix");
}

int main(int argc, char** argv) {
  Kokkos::ScopeGuard kokkos(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
