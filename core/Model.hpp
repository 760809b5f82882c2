// What a run needs to know, independent of the input format: the reference state, the
// contributions (beams, later contact), supports and prescribed motions, nodal loads and the
// points to track. All values are the ones reached at load factor T = 1 (scaled by T).
#pragma once
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "Contribution.hpp"
#include "State.hpp"

namespace bc::core {

using Dofs6 = std::array<double, 6>;

struct Support {
  std::string name;
  std::vector<int> nodes;
  std::array<bool, 6> fixed{};  // ux uy uz rx ry rz
  Dofs6 value{};                // prescribed displacement / rotation (spin about global axes) at T = 1
};

struct NodalLoad {
  std::string name;
  int node = 0;
  Dofs6 value{};  // force (3) and moment (3) at T = 1
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
