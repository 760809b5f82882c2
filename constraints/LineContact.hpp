// Line contact of nearly parallel beams: Gauss points along the segment of each element of beam A
// that lies between the planes of the nodes of an element of beam B (rectangular sections: on the
// lines bounding the overlap of the two facing faces, each an edge of A on B's face or an edge of B
// on A's face, whose points then have the roles of A and B swapped), each standing for its share of
// its line. A
// strategy may carry its multipliers on a field on the nodes of line A (LineField::Nodal): its line
// nodes are points of their own, and each Gauss point acts through its field nodes' multipliers.
// After each step the Gauss points' resolution of the contact zone is checked (warnings).
#pragma once
#include <array>
#include <map>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

#include "ContactGeometry.hpp"

namespace bc::constraints {

class LineContact {
 public:
  LineContact(const ContactGeometry& geometry, const ConstraintEnforcer& enforcer);
  // Whether the strategy's multipliers live on a field on line A's nodes.
  bool nodal() const { return nodal_; }

  // The narrow phase of one element pair in line contact, the broad phase's `visit`-th: offers its
  // Gauss points (the last visit wins; `known`: the present points).
  void findPoints(int pi, int ea, int eb, long long visit, const core::State& s, const PointMap& known,
                  const CandidateOffer& offer) const;
  // A Gauss point's closest points in `s` at its Gauss point of its segment (keeping its side), the
  // segment's length in `segment`; its kinematics; and the values segmentKinematics would give,
  // without their variations.
  ClosestPoints geometry(const ContactPointRecord& p, const core::State& s, double* segment = nullptr) const;
  ContactKinematics kinematics(const ContactPointRecord& p, const core::State& s, Variations order) const;
  ContactKinematics values(const ContactPointRecord& p, const ClosestPoints& cp, double segment,
                           const core::State& s) const;
  // The length of line A a Gauss point stands for (its weight times its segment's reference length),
  // and its rate with the segment's length (a point at a free end of B: a fixed length, rate 0).
  double weight(const ContactPointRecord& p, double segment) const;
  double weightRate(const ContactPointRecord& p) const;
  // Whether a line point is the point at a free end (of B inside a part of the field, or A's own end:
  // offerSegment), a point force rather than a traction sample.
  static bool endPoint(const ContactPointRecord& p);
  // The Gauss point's parameter on its piece of segment (a point at a free end of B: 0 or 1).
  double pointXi(const ContactPointRecord& p) const;
  // The Gauss point's parameter on A's element, on [0, 1].
  double gaussXi(int q) const { return gaussXi_[q]; }

  // Nodal line fields. The field's nodes are beam A's nodes, except an end node that supports hold
  // beside a held node of another beam, both along the line between them (setInitial): its shape
  // function is merged into its neighbour's (the field is constant on that end element; a beam of one
  // element with both ends merged has one multiplier node). Its own multiplier would constrain the gap
  // where the supports of both beams may fix it already (rods held at the same ends), so the
  // constraints would be redundant and the multipliers undetermined. Elsewhere an end node keeps its
  // multiplier, so that a force at a free or singly held end (a short rod's clamped ends pressing a
  // long beam) is resolved. setInitial(initial) decides it from the supports and the initial
  // positions (ContactManager::initialize; null: every end merges) and lists each field node's
  // elements. fieldNode(element, side) is the node carrying the multipliers of the element's node
  // `side` (0, 1); fieldShares(p) the distinct field nodes of a Gauss point with their shape values N
  // (summing to 1) and their records among `points` (null where none exists).
  int fieldNode(int element, int side) const;
  void setInitial(const core::State* initial);
  // Local refinement. Where the contact zone is shorter than an element, the beams penetrate between
  // the field's nodes; the element's field is then refined (refineField): level l cuts it into 2^l
  // equal parts whose inner ends are field nodes of their own (interior nodes, numbered from
  // kInteriorNode: element, level and place). At a beam's end element the outer part's node merges
  // into its neighbour, as the end node does without refinement.
  static constexpr int kInteriorNode = 1 << 30;
  static constexpr int kMaxFieldLevel = 6;
  static bool interiorNode(int node) { return node >= kInteriorNode; }
  int fieldLevel(int pair, int edge, int element) const;
  // Where a field node is in `s` (an interior node: on the element's chord) and the beam node whose
  // rank evaluates its own rows.
  Vec3d fieldPosition(int node, const core::State& s) const;
  int fieldHome(int node) const;
  // After Newton has converged on an active set: refines the field of every element where a contact
  // zone ends (zoneEnds) with a Gauss point deeper than kResolveLine of the thinner inscribed radius
  // and one open by as much, up to kMaxFieldLevel. Returns whether it refined one (the points then
  // change at the next iteration).
  bool refineField(const PointMap& points, const core::State& s);
  // Back to the unrefined field: after a restore, and after a failed attempt at a step (`failed`: a
  // pair whose field was refined in it is refined at most one level less than that attempt reached for
  // the rest of the run, but not below the step's converged field until a retry at that level has
  // failed in the same step; a restart from a later checkpoint refines it fully again).
  void clearLevels(bool failed = false);
  // A step converged: the next failure of a pair retries at its converged field's level first.
  void stepCommitted() { retriedAtStart_.clear(); }
  // At the start of a step (`points` the last converged ones, at `s`): the refinement their interior
  // nodes show, where a contact zone still ends inside the element.
  void resumeLevels(const PointMap& points, const core::State& s);
  void setFieldLevel(int pair, int edge, int element, int level) { levels_[{pair, edge, element}] = level; }
  // A field node's share of its beam's reference length, int N_a ds over all of the beam's elements.
  double fieldLength(const PointKey& node) const;
  // The beams' compliance to the field's shortest mode at a field node of a pair
  // (ContactPoint::fieldCompliance).
  double fieldCompliance(const PointKey& node) const;
  struct FieldShare {
    int node = -1;
    double N = 0.0, slope = 0.0;  // N at the point's xi and dN / dxi
    const ContactPointRecord* record = nullptr;
  };
  std::vector<FieldShare> fieldShares(const ContactPointRecord& p, double xi, const PointMap& points) const;
  // Per field node: the weighted gap int N_a g_N ds / int N_a ds and the weight int N_a ds (Gauss
  // weights times lengths times the line points' blend weights) at `s`.
  struct NodeGap {
    double weighted = 0.0, weight = 0.0, full = 0.0;  // full: the weight without the blend
    double weightedSlip = 0.0;  // int N_a g_T2 ds / int N_a ds
    double weightedAcross = 0.0;  // int N_a g_T1 ds / int N_a ds (circles with friction)
  };
  std::map<PointKey, NodeGap> nodeGaps(const PointMap& points, const core::State& s) const;
  // The view a strategy gets of a line node (its weighted gap, its multipliers).
  ContactPoint nodeView(const ContactPointRecord& node, const ContactKinematics& k, const core::State& s) const;
  // A Gauss point of a nodal field: its nearer line node with multipliers, and that node's state (null:
  // none has any).
  const ContactPointRecord* fieldHost(const ContactPointRecord& p, const PointMap& points) const;
  const PointState* fieldState(const ContactPointRecord& p, const PointMap& points) const;
  // Evaluates a Gauss point of a nodal line field: residual and tangent over its block's dofs (the
  // point's, then its field nodes' multipliers).
  bool evaluateNodal(const ContactPointRecord& p, const ContactKinematics& k, const core::State& s,
                     const PointMap& points, std::vector<double>& f, std::vector<double>* K, PointResult* result) const;

  // What the steps showed, for the warnings: pairs with friction whose line points carried force and
  // measure no slip across the axes (rectangles, or the Per Line law: ContactGeometry::acrossFriction);
  // nodal line fields: pair -> deepest penetration, where; pair -> deepest overlap between Gauss
  // points, where.
  const std::set<int>& frictionless() const { return frictionless_; }
  const std::map<int, std::pair<double, Vec3d>>& unresolved() const { return unresolved_; }
  const std::map<int, std::pair<double, Vec3d>>& unseenBetween() const { return unseenBetween_; }
  // Line contact at a beam end of A where supports hold both beams along the normal and the gap they
  // hold is a penetration: pair -> that gap, where, the traction EI |g| / h^4 it takes to close it
  // within an element of length h (an exact constraint's share: nodal fields only, 0 otherwise), the
  // force per length the active points on A's end element carry beyond the line's mean traction
  // (every strategy: Penalty's eps_N |g|, or forces of point and end contact there), against the mean
  // traction (the largest such ratio over the steps).
  struct HeldEnd {
    double gap = 0.0, traction = 0.0, excess = 0.0, mean = 0.0;
    Vec3d at{};
    // Above 1: reported (kHeldEndTraction, kHeldEndExcess); the worst of the steps is kept.
    double severity() const;
  };
  const std::map<int, HeldEnd>& heldEnds() const { return heldEnds_; }
  // Notes a committed Gauss point (its kinematics `k` in `s`) and, after a step, records overlaps of
  // line contact between the Gauss points; the frictionless pairs of restored points.
  void noteCommitted(const ContactPointRecord& p, const ContactKinematics& k, const core::State& s);
  void checkResolution(const PointMap& points, const core::State& s);
  void noteRestored(const PointMap& points);

 private:
  // Rectangular sections in line contact: the two edges of A on its face towards B and B's face
  // towards A, from the elements' places and turns in `s`.
  std::pair<std::array<int, 2>, int> facing(int eA, int eB, const core::State& s) const;
  // Line contact's input of an edge of A on a face of B (faces 0..3 = +y, +z, -y, -z of the
  // section); of the segment of element eA (its edge `edge`) on element eB (its face `face`):
  // lineInput or faceInput with the planes of eB's nodes; of a Gauss point.
  LinePairInput faceInput(int eA, int edgeA, int eB, int faceB, const core::State& s) const;
  LinePairInput segmentInput(int pair, int eA, int eB, int edge, int face, const core::State& s) const;
  LinePairInput input(const ContactPointRecord& p, const core::State& s) const;
  // Offers the Gauss points of the segment of element ea (its edge `edge`) on element eb (its face
  // `face`; circles: 0, 0) that lie across that face: an edge of the pair's beam A with `inside` 0
  // (within the face and `band` of its half width beyond, `keptBand` for a known point), one of its
  // beam B (the roles swapped: ea of beam B) with `inside` the half width of B's face (inside the face
  // by more than `band`, or `keptBand`, of that) (findPoints).
  void offerSegment(int pi, int ea, int eb, int edge, int face, double inside, double band, double keptBand,
                    long long visit, const core::State& s, const PointMap& known, const CandidateOffer& offer) const;
  // A Gauss point's history (element parameters) and its slips across and along B at `cp` since
  // then (g_T1, g_T2), as segmentKinematics measures them (`in` its input at the state of `cp`).
  LineHistory history(const ContactPointRecord& p) const;
  std::array<double, 2> slip(const ContactPointRecord& p, const ClosestPoints& cp, const LinePairInput& in) const;
  // geometry() from the point's input at that state.
  ClosestPoints geometry(const ContactPointRecord& p, const LinePairInput& in, double* segment) const;
  // After a step (nodal fields): the gaps supports hold at beam ends (heldEnds).
  void checkHeldEnds(const PointMap& points, const core::State& s);
  // Whether a Gauss point's element pair has beam A's end `side` (0, 1) where supports hold both
  // beams along the normal (B's node at the same place); there, the closest points and A's end node.
  bool heldEnd(const ContactPointRecord& p, int side, const core::State& s, ClosestPoints* at = nullptr,
               int* end = nullptr) const;
  // Whether a pair has friction that its line points apply along the axes only (frictionless_).
  bool frictionAlongOnly(int pair) const;
  // Whether node `n`'s supports hold it along the unit `normal` (every free translation is across it:
  // the normal's component along it at most `ignored`).
  bool heldAlong(int n, const Vec3d& normal, double ignored = 1e-6) const;

  const ContactGeometry& geometry_;
  const ConstraintEnforcer& enforcer_;
  bool nodal_ = false;
  std::vector<double> gaussXi_, gaussWeight_;  // Gauss points on [0, 1], weights summing to 1
  // Per element: the reference normals of the segment planes at its two nodes (the mean unit axis of
  // the beam's elements meeting there).
  std::vector<std::array<Vec3d, 2>> segmentPlanes_;
  std::set<int> frictionless_;
  std::map<int, std::pair<double, Vec3d>> unresolved_, unseenBetween_;
  std::map<int, HeldEnd> heldEnds_;
  std::vector<std::array<bool, 2>> mergedEnds_;  // per beam, its first and last node: merged (setInitial)
  // Field node (a beam node) -> the elements its shape function reaches and its beam; beam -> its
  // largest bending stiffness (fieldLength, fieldCompliance).
  struct FieldElements {
    std::vector<int> elements;  // the elements the node's shape function reaches without refinement
    int beam = 0;
  };
  // (pair, edge, element) -> refinement level (absent: 0).
  std::map<std::tuple<int, int, int>, int> levels_;
  // (pair, edge, element) -> its deepest penetration (per thinner inscribed radius) when it was last
  // refined in this step.
  std::map<std::tuple<int, int, int>, double> refinedAt_;
  // pair -> the deepest refinement level allowed (absent: kMaxFieldLevel), lowered by failed attempts;
  // resumedLevel_: pair -> the deepest level of the field the step started from
  std::map<int, int> levelCap_, resumedLevel_;
  // pairs whose retry in this step already started capped at resumedLevel_ (cleared at a commit)
  std::set<int> retriedAtStart_;
  int levelCap(int pair) const {
    const auto it = levelCap_.find(pair);
    return it == levelCap_.end() ? kMaxFieldLevel : it->second;
  }
  // The field's parts of an element: (node at the part's start, node at its end, length).
  struct FieldPart {
    int from = 0, to = 0;
    double length = 0.0;
  };
  std::vector<FieldPart> fieldParts(int pair, int edge, int element) const;
  // The field node at j / 2^level of an element (j = 0 .. 2^level) whose field is at `level`.
  int fieldNodeAt(int element, int level, int j) const;
  // The elements of A where a contact zone may end (refineField), with their Gauss points' lowest and
  // highest gaps per thinner inscribed radius.
  std::map<std::tuple<int, int, int>, std::pair<double, double>> zoneEnds(const PointMap& points,
                                                                          const core::State& s) const;
  // The elements a field node's shape function reaches (an interior node: its own).
  std::vector<int> fieldNodeElements(int node) const;
  std::map<int, FieldElements> fieldElements_;
  std::vector<double> beamStiffness_;
};

// A held end is reported when closing its gap within one element would take more than this
// fraction of the field's mean traction, ...
constexpr double kHeldEndTraction = 1e-2;
// ... or when the points on A's end element carry more than this fraction of the line's mean
// traction beyond it (a measured force: a field constant on the end elements and the geometric
// nonlinearity leave about 1 % there where nothing is wrong; two rods pinned at the same x, 40
// elements, q = 0.01).
constexpr double kHeldEndExcess = 1.0;
inline double LineContact::HeldEnd::severity() const {
  return mean > 0.0 ? std::max(traction / (kHeldEndTraction * mean), excess / (kHeldEndExcess * mean)) : 0.0;
}

// A line point penetrating by more than this fraction of the thinner section's inscribed radius (a
// nodal multiplier field's point, or the gap between Gauss points beyond the deepest one's) is
// reported: the contact zone is not resolved (warnings()).
constexpr double kUnresolvedLine = 1e-3;
// The local refinement of a nodal field aims at penetrations below this fraction of the thinner
// section's inscribed radius (refineField).
constexpr double kResolveLine = 1e-4;
// A Newton step that would carry a line point deeper than this fraction of the thinner section's
// inscribed radius below its gap (or 0) is shortened to half that depth (ContactManager::stepBound).
constexpr double kLineStepDepth = 0.2;
// A point (or line node) whose blend weight (share of its full weight) is at most this is not
// judged after Newton and keeps no multipliers (its rows would carry nothing).
constexpr double kCarries = 1e-3;

}  // namespace bc::constraints
