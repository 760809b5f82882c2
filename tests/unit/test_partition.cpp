// The nodes' split over the ranks (core::coordinatePartition, recursive coordinate bisection): equal
// shares, a cut across the longest side, and on two crossed layers of beams at most one column of
// crossings with its two nodes on different ranks (a split by node number puts every crossing across
// the ranks: one layer's nodes come first).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "core/Assembler.hpp"

using bc::core::coordinatePartition;
using bc::core::Vec3d;

TEST(CoordinatePartition, SharesDifferByAtMostOneNode) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int n : {1, 2, 7, 100, 1001})
    for (int ranks = 1; ranks <= 5; ++ranks) {
      std::vector<Vec3d> X(n);
      for (auto& x : X) x = Vec3d{{u(random), 3.0 * u(random), 0.5 * u(random)}};
      const auto owner = coordinatePartition(X, ranks);
      std::vector<int> count(ranks, 0);
      for (int r : owner) {
        ASSERT_GE(r, 0);
        ASSERT_LT(r, ranks);
        ++count[r];
      }
      const auto [lo, hi] = std::minmax_element(count.begin(), count.end());
      EXPECT_LE(*hi - *lo, 1) << n << " nodes, " << ranks << " ranks";
      EXPECT_EQ(owner, coordinatePartition(X, ranks));  // the same answer on every call (every rank)
    }
}

TEST(CoordinatePartition, TwoRanksCutTheLongestSide) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3d> X(500);
  for (auto& x : X) x = Vec3d{{u(random), 4.0 * u(random), 2.0 * u(random)}};  // longest along y
  const auto owner = coordinatePartition(X, 2);
  double top0 = -1.0, bottom1 = 10.0;
  for (std::size_t k = 0; k < X.size(); ++k)
    if (owner[k] == 0) top0 = std::max(top0, X[k][1]);
    else bottom1 = std::min(bottom1, X[k][1]);
  EXPECT_LE(top0, bottom1);
}

TEST(CoordinatePartition, CrossedLayersKeepCrossingsOnOneRank) {
  // Layer A: n beams along x at y = j, layer B: n beams along y at x = i, one node per crossing and
  // the nodes numbered layer by layer (A's first), as the model generator numbers them.
  const int n = 20;
  std::vector<Vec3d> X;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) X.push_back(Vec3d{{double(i), double(j), 0.0}});
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) X.push_back(Vec3d{{double(i), double(j), 1.0}});
  const auto nodeA = [&](int i, int j) { return j * n + i; };
  const auto nodeB = [&](int i, int j) { return n * n + i * n + j; };
  for (int ranks : {2, 4}) {
    const auto owner = coordinatePartition(X, ranks);
    int across = 0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) across += owner[nodeA(i, j)] != owner[nodeB(i, j)];
    // Each cut is a plane between two columns (or rows) of crossings, or through one of them where
    // the shares end inside it: at most n crossings per cut (2 ranks: one cut; 4 ranks: 3 cuts).
    EXPECT_LE(across, (ranks - 1) * n) << ranks << " ranks";
  }
}
