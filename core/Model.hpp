// What a run needs to know, independent of the input format: the reference state, the
// contributions (beams, later contact), supports and prescribed motions, nodal loads and the
// points to track. All values are the ones reached at load factor T = 1, scaled by T or, where a
// support or load has a load curve, by the curve's factor at T (load histories: press, then slide).
#pragma once
#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "Contribution.hpp"
#include "State.hpp"

namespace bc::core {

using Dofs6 = std::array<double, 6>;

// A piecewise-linear factor of the load factor T through the points (T_i, f_i), T_0 = 0 < T_1 < ...
// < T_n = 1 (linear between them). Without points the factor is T itself.
struct LoadCurve {
  std::vector<std::pair<double, double>> points;
  double operator()(double T) const {
    if (points.empty()) return T;
    if (T <= points.front().first) return points.front().second;
    for (std::size_t i = 1; i < points.size(); ++i)
      if (T <= points[i].first) {
        const auto& [t0, f0] = points[i - 1];
        const auto& [t1, f1] = points[i];
        return f0 + (f1 - f0) * (T - t0) / (t1 - t0);
      }
    return points.back().second;
  }
};

struct Support {
  std::string name;
  std::vector<int> nodes;
  std::array<bool, 6> fixed{};  // ux uy uz rx ry rz
  Dofs6 value{};  // prescribed displacement / rotation (spin about global axes) at T = 1
  LoadCurve curve;  // value(T) = value * curve(T)
};

struct NodalLoad {
  std::string name;
  int node = 0;
  Dofs6 value{};  // force (3) and moment (3) at T = 1
  LoadCurve curve;  // value(T) = value * curve(T)
};

struct TrackedPoint {
  std::string name;
  int node = 0;
};

struct Model {
  State initial;
  std::vector<std::shared_ptr<Contribution>> contributions;
  std::vector<Support> supports;
  std::vector<NodalLoad> loads;
  std::vector<TrackedPoint> tracked;
};

}  // namespace bc::core
