// The contact points and their life cycle. A point is identified by its key (PointKey); per
// iteration it lies on the element pair the search found for it. Its history: the contact
// coordinates of the last converged step (the tangential gaps are measured from them, mapped on the
// current configuration), the normal orientation, and the strategy's own point state (opaque here).
// When a point moves to a neighbouring element within a step, its tangential gap is the parameter
// difference times the current element's line length (exact within one element); a new Gauss point
// of line contact takes the history of the nearest line point of its element and line at the last
// converged state. The set keeps the present points, the last committed ones (restored when an
// increment fails, written to checkpoints) and those of a marked iterate.
#pragma once
#include <map>
#include <tuple>
#include <vector>

#include "ContactGeometry.hpp"
#include "LineContact.hpp"
#include "core/Checkpoint.hpp"

namespace bc::constraints {

class ContactPointSet {
 public:
  ContactPointSet(const ContactGeometry& geometry, const ConstraintEnforcer& enforcer, const LineContact& lines)
      : geometry_(geometry), enforcer_(enforcer), lines_(lines) {}

  const PointMap& current() const { return points_; }
  PointMap& current() { return points_; }
  const PointMap& committed() const { return committed_; }
  PointMap& committed() { return committed_; }

  // The points of the search's candidates: those known keep their history (moved to the
  // candidate's element pair), new ones start theirs; with a nodal line field, the line nodes of the
  // Gauss points are added. True if a point appeared, went or changed its element pair.
  bool update(const std::map<PointKey, Candidate>& candidates);
  // Asks the state's extra unknowns for the multipliers every point's strategy wants now (values of
  // points that keep theirs are kept); true if the layout changed.
  bool layoutMultipliers(core::State& state);

  void commit() { committed_ = points_; }
  void restore() { points_ = committed_; }
  void mark() { marked_ = points_; }
  void returnToMark() { points_ = marked_; }

  // The committed points, field by field, for checkpoints (their number is written before them);
  // and `n` of them read back, with their multipliers in the committed state `committed`.
  void save(core::CheckpointOut& out) const;
  void load(core::CheckpointIn& in, long long n, const core::State& committed);

 private:
  ContactPointRecord newPoint(const PointKey& key, const Candidate& c) const;
  // A new Gauss point takes the history of the nearest line point (`donors`, found when first asked
  // for) of the same element and line of A at the last converged state.
  using Donors = std::map<std::tuple<int, int, int, int>, std::vector<const ContactPointRecord*>>;
  void inherit(ContactPointRecord& p, Donors& donors, bool& donorsFound) const;
  // The line nodes of the Gauss points of `next` (kept with their state, or new).
  void addLineNodes(PointMap& next, bool& changed) const;
  ContactPointRecord readPoint(core::CheckpointIn& in, long long i, StateFields& reader);

  const ContactGeometry& geometry_;
  const ConstraintEnforcer& enforcer_;
  const LineContact& lines_;
  PointMap points_, committed_, marked_;
};

}  // namespace bc::constraints
