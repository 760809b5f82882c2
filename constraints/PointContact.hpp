// Point contact: a point per two lines of a beam pair (only lines facing the other beam, so a pair
// of rectangular beams has at most 2 x 2 = 4 points), on the element pair where the closest points
// of the two lines fall inside both elements (a point on a shared node is taken once). And end
// contact: a point per free beam end whose end face is turned towards the other beam (the closest
// points of the two axes lie beyond the end, where no point contact exists) and whose centre
// projects onto the other beam's element (endKinematics). And end-to-end contact: a point per two free
// ends whose end faces are turned towards each other (endToEndKinematics).
#pragma once

#include <set>
#include "ContactGeometry.hpp"

namespace bc::constraints {

class PointContact {
 public:
  explicit PointContact(const ContactGeometry& geometry) : geometry_(geometry) {}
  // End points that leave the element they were found on at a converged state for the neighbour that
  // holds their closest point (ContactManager::acceptSolution, once per increment): the search does not
  // keep them on their element (the hysteresis of 5 % of an element beyond a node) until the increment
  // ends (clearHandedOver: a step committed, restored or loaded).
  void handOver(const PointKey& key) { handedOver_.insert(key); }
  bool handedOver(const PointKey& key) const { return handedOver_.count(key) > 0; }
  void clearHandedOver() { handedOver_.clear(); }
  // The narrow phase of one element pair of pair `pi`, the broad phase's `visit`-th: offers each
  // point contact it finds (`known`: the present points, which keep their orientation and element pair).
  void findPoints(int pi, int ea, int eb, long long visit, const core::State& s, const PointMap& known,
                  const CandidateOffer& offer) const;
  // Closest points of a point's two lines in `s`, with the point's normal orientation and gap.
  ClosestPoints geometry(const ContactPointRecord& p, const core::State& s) const;
  ContactKinematics kinematics(const ContactPointRecord& p, const core::State& s, Variations order) const;
  // The angle between the normal of point contact p (its closest points `cp` in `s`, as geometry()
  // gives them) and that of a second closest point of the same two lines on a neighbouring element
  // pair (across a node of either beam) whose gap is within `tolerance` of p's; 0 when there is none.
  // Where a beam bends towards the other at a node, its two chords there each hold a closest point as
  // close as the other; the point takes one, and its normal is that chord's. Hermite axes are smooth
  // across a node of a beam that was straight there, and keep the kink of one whose elements met at
  // an angle in its initial shape: `initialKink`, the largest such angle at the rivals' nodes.
  double rivalAngle(const ContactPointRecord& p, const ClosestPoints& cp, const core::State& s, double tolerance,
                    double* initialKink = nullptr) const;
  // The end-to-end point of a free end of element ea and one of element eb facing each other (the
  // larger end face is the plane, the other end presses on it), whatever the angle of the axes
  // (two ends meet with their axes in line, where circles are in line contact).
  void findEndToEnd(int pi, int ea, int eb, long long visit, const core::State& s, const PointMap& known,
                    const CandidateOffer& offer) const;

 private:
  // A point's two lines in `s`: the elements' Hermite curves, or their chords (ContactOptions).
  LinePairInput input(int eA, int lA, int eB, int lB, const core::State& s) const;
  // Whether the closest points of two rectangles' edges lie across the sections' faces: the sections
  // lie apart (or just touch) along A's section axis across the points' normal and overlap deeper
  // along the normal; no contact along that normal.
  bool acrossFaces(int ea, int eb, const ClosestPoints& cp, const LinePairInput& in, double thinner) const;
  // The orientation of a newly found point (from the last converged state).
  double referenceSigma(int eA, int lA, int eB, int lB, const ClosestPoints& current) const;
  // End contact: the end `end` (0: the beam's first node, 1: its last) of element eE's beam against
  // element eS's surface (rectangles: its face `face`), in `s`; `corner` 0..3: that corner of a
  // rectangular end only (LinePairInput::endCorner).
  LinePairInput endInput(int eE, int end, int eS, int face, const core::State& s, int corner = -1) const;
  // Half the depth of element eS's rectangular section across its face `face` (0..3: +e2, +e3, -e2,
  // -e3): the distance of the face's plane from the axis.
  double faceDepth(int eS, int face) const;
  // The face of element eS (rectangular) whose plane the point x lies furthest outside, in `s`.
  int outsideFace(int eS, const Vec3d& x, const core::State& s) const;
  // The corner `corner` (LinePairInput::endCorner) of element eE's rectangular end section at its
  // node `node`, in `s`.
  Vec3d cornerAt(int eE, int node, int corner, const core::State& s) const;
  // The outward axis of element e at its node `node` (e1, minus at its first node), in `s`.
  Vec3d outwardAxis(int e, int node, const core::State& s) const;
  bool nearFreeEnd(int e, const Vec3d& x, double reach, const core::State& s) const;
  // The end points of element eE's free ends (if any) on element eS, the pair's beam B's ends if ofB.
  void findEnds(int pi, int eE, int eS, bool ofB, long long visit, const core::State& s, const PointMap& known,
                const CandidateOffer& offer) const;
  // Whether the end at `node` of element eE lies past a free end of element eS whose face is turned
  // towards it (no deeper than its circumscribed radius): end-to-end contact's, not end contact's.
  bool beyondFreeEnd(int eE, int node, int eS, const core::State& s) const;
  // End-to-end contact: the end `end` of element eE's beam against the end face `otherEnd` of element
  // eO's beam (endToEndKinematics), in `s`.
  LinePairInput endToEndInput(int eE, int end, int eO, int otherEnd, const core::State& s) const;

  std::set<PointKey> handedOver_;
  const ContactGeometry& geometry_;
};

}  // namespace bc::constraints
