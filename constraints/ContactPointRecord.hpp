// What the contact keeps of one contact point (or line node): where it lies, its history, the
// strategy's state and its results of the last commit. Shared by the parts of the contact
// (ContactManager composes them).
#pragma once
#include <map>
#include <memory>

#include "ConstraintEnforcer.hpp"
#include "ContactKinematics.hpp"
#include "PointKey.hpp"
#include "core/State.hpp"

namespace bc::constraints {

// A strategy's point state with value semantics (copied by clone, so points can be committed,
// marked and restored).
class PointStateHolder {
 public:
  PointStateHolder() = default;
  explicit PointStateHolder(std::unique_ptr<PointState> s) : s_(std::move(s)) {}
  PointStateHolder(const PointStateHolder& o) : s_(o.s_ ? o.s_->clone() : nullptr) {}
  PointStateHolder& operator=(const PointStateHolder& o) {
    if (this != &o) s_ = o.s_ ? o.s_->clone() : nullptr;
    return *this;
  }
  PointStateHolder(PointStateHolder&&) = default;
  PointStateHolder& operator=(PointStateHolder&&) = default;
  PointState& operator*() const { return *s_; }

 private:
  std::unique_ptr<PointState> s_;
};

struct ContactPointRecord {
  // A point contact joins two lines, a Gauss point of line contact lies on a segment of line A, a
  // line node carries a strategy's multiplier field on line A (PointKey). A line node's elements
  // are one element of beam A at its node.
  PointKey key;
  bool node() const { return key.kind == PointKey::Kind::LineNode; }
  bool line() const { return key.kind == PointKey::Kind::Gauss; }
  // An end point: its element A is the end's (of either beam), B the other beam's; sigma is its side.
  bool end() const { return key.end(); }
  int gauss() const { return key.gauss; }
  int edge() const { return key.edge; }
  int face() const { return key.face; }
  int elementA = 0, elementB = 0;  // indices into the beam set's element list
  double sigma = 1.0;
  double xiPrev = 0.0, etaPrev = 0.0;  // previous converged point, as beam coordinates (element + xi)
  // Line points: d eta / d xi at the last converged state (LineHistory; an end point: its coordinate
  // across B, endProjection), the Gauss point's parameter
  // on A's element at the last detection, and the length of line A it stood for at the last commit.
  double etaRate = 0.0, xi = 0.0, length = 0.0;
  // A Gauss point of a nodal field on a part of the field that a free end of the other beam cuts
  // (Candidate::endCut, at the last detection): 1 the end at the piece's low bound, 2 at its high.
  int endCut = 0;
  double across2 = 0.0;  // an end-to-end point: the end's second offset on the other end's face
  PointStateHolder state;  // the strategy's
  int extraOffset = -1, extraCount = 0;  // its multipliers in State::extra (as laid out last)
  // Last committed values, for output: the normal gap (a line node: its field-weighted gap) and
  // the following.
  double gap = 0.0;
  PointResult result;
  // The values of the strategy's own columns of the table (ConstraintEnforcer::outputValues).
  std::vector<double> outputs;
  // The beams' compliance at the point (ConstraintEnforcer::setCompliance; 0: not asked for).
  double compliance[3] = {0.0, 0.0, 0.0};
  Vec3d position{};
  Vec3d normal{};  // unit normal (from beam A to beam B)
  Vec3d normalForce{};  // the force the point applies on beam B: its normal part ...
  Vec3d tangentialForce{};  // ... and its tangential part (global components)
};

// The points in the order of their keys (PointKey: the order of rows, arrays and multipliers).
using PointMap = std::map<PointKey, ContactPointRecord>;

// A strategy's multipliers are extra unknowns of the state (core::ExtraUnknowns) of this owner,
// under the point's code (PointKey::code).
constexpr const char* kContactExtraOwner = "contact";
inline core::ExtraUnknowns::Key extraKey(const ContactPointRecord& p) {
  const auto c = p.key.code();
  return {c.begin(), c.end()};
}
// The point's multipliers in `state` (null when it has none) and how many there are.
inline const double* pointMultipliers(const ContactPointRecord& p, const core::State& state, int* count = nullptr) {
  const auto* block = state.extra.find(kContactExtraOwner, extraKey(p));
  if (count) *count = block ? block->size : 0;
  return block ? &state.extra[block->offset] : nullptr;
}

}  // namespace bc::constraints
