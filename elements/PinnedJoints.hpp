// Pinned joints as a Contribution: two nodes (of two beams, at the same place) whose translations are
// tied and whose rotations stay independent, so the joint carries force but no moment. Each joint
// owns three multipliers lambda (core::ExtraUnknowns, owner "joints", key the joint's index), the
// force the joint passes between the beams, with the rows
//   node A translations:  + lambda          node B translations:  - lambda
//   multiplier rows:      x_A - x_B = 0
// exactly linear (tangent: identity blocks), so Newton sees the constraint at once.
#pragma once
#include <string>
#include <vector>

#include "core/Contribution.hpp"

namespace bc::elements {

using core::Vec3d;

struct PinnedJoint {
  std::string name;
  int nodeA = 0, nodeB = 0;
};

class PinnedJoints : public core::Contribution {
 public:
  explicit PinnedJoints(std::vector<PinnedJoint> joints) : joints_(std::move(joints)) {}
  static constexpr const char* kExtraOwner = "joints";

  std::string name() const override { return "pinned joints"; }
  const std::vector<PinnedJoint>& joints() const { return joints_; }
  bool prepareIteration(core::State& state) override;
  void connectivity(const OwnsDof& owns, std::vector<std::vector<core::GlobalDof>>& blocks) const override;
  void evaluate(const core::State& state, const OwnsDof& owns, core::AssemblySink& sink, bool tangent) const override;
  // The force each joint transmits (on node A's beam, global components), for tests.
  Vec3d force(const core::State& state, std::size_t joint) const;

 private:
  std::vector<core::GlobalDof> blockDofs(std::size_t j) const;
  std::vector<PinnedJoint> joints_;
  std::vector<int> offsets_;  // each joint's first multiplier in State::extra
  int numNodes_ = 0;
};

}  // namespace bc::elements
