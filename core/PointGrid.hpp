// Ids at points, found through the cells of a uniform grid: near(x) lists every id inserted at a point
// in x's cell or one of its 26 neighbours, so every id within one cell side of x (and some farther),
// in increasing order and each once. For checks over many items (a deck's beam ends, a generator's
// fibres) that would otherwise compare every pair.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <unordered_map>
#include <vector>

#include "SmallMath.hpp"

namespace bc::core {

class PointGrid {
 public:
  explicit PointGrid(double cell) : cell_(cell) {}
  void insert(const math::Vec3d& x, int id) {
    std::vector<int>& ids = cells_[cellOf(x)];
    if (ids.empty() || ids.back() != id) ids.push_back(id);
  }
  std::vector<int> near(const math::Vec3d& x) const {
    const Cell c = cellOf(x);
    std::vector<int> ids;
    for (long long i = -1; i <= 1; ++i)
      for (long long j = -1; j <= 1; ++j)
        for (long long k = -1; k <= 1; ++k) {
          const auto it = cells_.find({c[0] + i, c[1] + j, c[2] + k});
          if (it != cells_.end()) ids.insert(ids.end(), it->second.begin(), it->second.end());
        }
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    return ids;
  }

 private:
  using Cell = std::array<long long, 3>;
  struct Hash {
    std::size_t operator()(const Cell& c) const {
      std::size_t h = 0;
      for (long long v : c) h = h * 1000003u ^ std::hash<long long>()(v);
      return h;
    }
  };
  // (Clamped, so a point far out, or not finite, still has a cell.)
  Cell cellOf(const math::Vec3d& x) const {
    Cell c{};
    for (int k = 0; k < 3; ++k) {
      const double v = x[k] / cell_;
      c[k] = static_cast<long long>(std::floor(std::isfinite(v) ? std::clamp(v, -1e18, 1e18) : 0.0));
    }
    return c;
  }
  double cell_;
  std::unordered_map<Cell, std::vector<int>, Hash> cells_;
};

}  // namespace bc::core
