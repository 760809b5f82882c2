// The beams and contact pairs as the contact sees them: each beam's contact lines (the four edges of
// a rectangular section, offsets +-b/2 e2 +-h/2 e3 from the axis, or the axis of a circular one,
// whose radius enters the gap), the elements' neighbourhoods (shared and pinned nodes, free ends),
// the last converged state, and the all-angle blend of point and line contact. The search, point
// contact, line contact and the points' life cycle all read it.
#pragma once
#include <array>
#include <map>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

#include "ConstraintEnforcer.hpp"
#include "ContactKinematics.hpp"
#include "ContactPointRecord.hpp"
#include "core/State.hpp"
#include "elements/BeamSet.hpp"

namespace bc::constraints {

struct ContactPairSpec {
  int beamA = 0, beamB = 0;
  double friction = 0.0;
  std::string name;
};

struct ContactOptions {
  double searchMargin = 0.0;  // added to the bounding boxes [length]
  double minimumSinAngle = 1e-3;  // lines closer to parallel are skipped (point contact undefined)
  // Point contact's lines: the elements' straight chords, or their Hermite curves (C1 across nodes).
  bool hermitePointAxes = false;
  bool allowInitialPenetration = false;
  FrictionLaw frictionLaw = FrictionLaw::IsotropicCoulomb;
  // All-angle contact of two circular beams (radians): line contact (Gauss points along the line,
  // frictionless) below lineAngle, point contact above pointAngle, a C1 blend of the two between;
  // lineAngle 0 switches line contact off. Gauss points per element of beam A.
  double lineAngle = 5.0 * M_PI / 180.0;
  double pointAngle = 15.0 * M_PI / 180.0;
  int lineGaussPoints = 6;
  // Pairs of distinct nodes joined without sharing a node (pinned joints): elements meeting there
  // are no contact candidates, like elements that share a node.
  std::vector<std::pair<int, int>> joinedNodes;
  // Nodes whose dofs supports fix, with the fixed components (ux, uy, uz, rx, ry, rz): the
  // line-contact check of gaps that supports hold (LineContact::checkHeldEnds), and whether the slip
  // across the axes moves (ContactGeometry::movesAcross).
  std::map<int, std::array<bool, 6>> heldNodes;
};

// A candidate of the narrow phase for a point key: the element pair it lies on and the closest
// points of its lines there.
struct Candidate {
  int elementA, elementB;
  ClosestPoints cp;
  // A Gauss point of a nodal line field on a part of the field that a free end of the other beam cuts
  // (LineContact::offerSegment): 1 where the end is the covered piece's low bound, 2 its high bound.
  int endCut = 0;
};
// How the narrow phase offers a candidate: with how far outside its elements' centres it lies and
// an order (ContactSearch::detect keeps, per key, the lowest (outside, order)).
using CandidateOffer = std::function<void(const PointKey&, const Candidate&, double, long long)>;

// Gives closest points the normal orientation `sigma` (n = sigma t_B x t_A / |t_B x t_A|) and the gap
// that goes with it.
inline void orient(ClosestPoints& cp, double sigma, double radiusSum) {
  if (sigma == cp.sigma) return;
  cp.normal = -1.0 * cp.normal;
  cp.sigma = sigma;
  cp.gap = dot(cp.pB - cp.pA, cp.normal) - radiusSum;
}
// The unit vector t_B x t_A / |t_B x t_A| (the normal before its orientation sigma).
inline Vec3d lineCross(const ClosestPoints& cp) { return cp.sigma * cp.normal; }

// How far a section reaches from its centre along the unit direction u: a rectangle whose width lies
// along e2 and height along e3, or a disc normal to e1.
inline double sectionReach(const elements::CrossSection& sec, const Vec3d& e1, const Vec3d& e2, const Vec3d& e3,
                           const Vec3d& u) {
  if (sec.shape == elements::CrossSection::Shape::Rectangle)
    return 0.5 * sec.width * std::abs(dot(u, e2)) + 0.5 * sec.height * std::abs(dot(u, e3));
  const double c = dot(u, e1);
  return sec.radius * std::sqrt(std::max(0.0, 1.0 - c * c));
}

class ContactGeometry {
 public:
  // `lineContact`: the strategy enforces lines (and the options switch line contact on).
  ContactGeometry(std::shared_ptr<const elements::BeamSet> beams, std::vector<ContactPairSpec> pairs,
                  ContactOptions options, bool lineContact);

  const elements::BeamSet& beams() const { return *beams_; }
  const std::vector<ContactPairSpec>& pairs() const { return pairs_; }
  const ContactOptions& options() const { return options_; }
  // The last converged state (orientation of new points, swept search, blend of element pairs).
  const core::State& reference() const { return reference_; }
  // (A new reference closes the gates opened within the increment: openGates.)
  void setReference(const core::State& s) {
    reference_ = s;
    closeGates();
  }

  // The contact pair of beams (a, b), in this order, or -1.
  int pairOf(int a, int b) const {
    const auto it = pairIndex_.find(beamPairKey(a, b));
    return it == pairIndex_.end() ? -1 : it->second;
  }
  // Nodes pinned together (options().joinedNodes, either order).
  bool joined(int a, int b) const { return joined_.count({a, b}) > 0; }
  // A node at a beam end that no other element or pin uses.
  bool freeEnd(int node) const { return freeEnd_.count(node) > 0; }
  // The radius of the largest circle in a beam's section, and the smaller of a pair's two.
  double inscribed(int beam) const { return inscribed_[beam]; }
  // The radius of the smallest circle about the axis holding a beam's section.
  double circumscribed(int beam) const { return circumscribed_[beam]; }
  double thinner(int pair) const { return std::min(inscribed_[pairs_[pair].beamA], inscribed_[pairs_[pair].beamB]); }
  int lineCount(int beam) const { return static_cast<int>(lines_[beam].size()); }
  bool rectangles(int pair) const;
  // A Gauss point of rectangles' line contact on an edge of the pair's beam B against beam A's face:
  // its roles are swapped (its elementA is an element of beam B, its elementB one of beam A).
  // An end point of the pair's beam B's end: the same.
  bool swapped(const ContactPointRecord& p) const {
    return (p.line() && beams_->elements()[p.key.elementA].beam != pairs_[p.key.pair].beamA) ||
           (p.end() && p.key.endOfB());
  }
  // The point's elements on the pair's beams A and B, whatever its roles.
  std::array<int, 2> pairElements(const ContactPointRecord& p) const {
    return swapped(p) ? std::array<int, 2>{p.elementB, p.elementA} : std::array<int, 2>{p.elementA, p.elementB};
  }

  // The input of closest points of line lA of element eA and line lB of element eB in `s`, and that
  // of the two elements' axes.
  LinePairInput lineInput(int eA, int lA, int eB, int lB, const core::State& s) const;
  LinePairInput axisInput(int eA, int eB, const core::State& s) const;
  // The axes point contact takes for elements eA and eB (Point Contact Axes): the chords (no
  // reference tangents), or the smoothed Hermite axes, the curves' reference tangents of the two
  // elements at their nodes, a node of two elements (inside a beam, or two beams joined end to end)
  // shared by both (the bisector of their initial directions) where they meet at no more than
  // kCornerAngle; at a free end, at a node of three or more elements and at a corner each element's
  // own direction.
  void pointContactAxes(LinePairInput& in, int eA, int eB) const;
  static constexpr double kCornerAngle = 45.0 * M_PI / 180.0;
  // The angle at which element e's axis meets its neighbour's at its node 1 (end 0) or 2 (end 1) on
  // the smoothed axes: 0 where the node is smoothed, the initial angle at a corner, 0 at a beam end.
  double smoothedKink(int e, int end) const { return kinkLeft_[e][end]; }
  double beamCoordinate(int element, double xi) const;
  // Whether xi lies on the element (beyond a shared node: within a little of it), and within one
  // element length of it (not beyond its beam's ends).
  bool withinElement(int element, double xi) const;
  bool nearElement(int element, double xi) const;
  std::array<core::GlobalDof, kPairDofs> pointDofs(const ContactPointRecord& p) const;

  // All-angle contact: whether the pair blends point and line contact (the strategy enforces lines;
  // both sections circular or both rectangular); the angles (radians) below which a pair is in line
  // contact and above which in point contact; the angle of two elements' axes in `s`; whether an
  // element pair has line points / point contacts (by its angle at the last converged state, with
  // margins beyond the blend so a pair that turns within an increment has both); and the blend
  // weight of a point at its axes' cosine (point contact zeta, line point 1 - zeta), with its
  // gradient in the 24 dofs from the cosine's first variation.
  bool lineContact() const { return lineContact_; }
  bool blends(int pair) const;
  std::pair<double, double> blendAngles(int pair) const;
  double axisAngle(int elementA, int elementB, const core::State& s) const;
  bool inLineContact(int pair, int elementA, int elementB) const;
  bool inPointContact(int pair, int elementA, int elementB) const;
  // Element pairs whose angle in the converged state `s` gives them line points or point contacts
  // that their angle at the last converged state did not (a pair that turned past the margins within
  // the increment): they have both for the rest of the increment, and the contact manager runs
  // another pass, so that no converged state lacks the points its own angles call for. Returns how
  // many were opened. (An end lying on a face within the rectangles' blend, 0.057 to 0.115 degrees,
  // whose pair turned from below 0.03 degrees to above 0.057 in the increment of first contact had
  // no end point, and Penalty's answer depended on the increments by 2.7 %.)
  int openGates(const std::vector<std::tuple<int, int, int>>& elementPairs, const core::State& s);
  void closeGates() {
    lineGates_.clear();
    pointGates_.clear();
  }
  double blendWeight(const ContactPointRecord& p, double cosine, const double* cosineR, Vector24* gradient) const;
  // The blend weight at the axes' angle in `s` (without variations).
  double blendWeightAt(const ContactPointRecord& p, const core::State& s) const {
    return blendWeight(p, std::cos(axisAngle(p.elementA, p.elementB, s)), nullptr, nullptr);
  }
  // Where two lines touch (reported positions): midway between the two surfaces along the normal.
  // A's line is an axis of radius r_A or an edge; B's closest point on a face lies on the face's
  // centre line, so the midpoint of the two closest points put a rectangle's face contact half a
  // face width off its edge. A point's: an end point's or end-to-end point's is the midpoint of its
  // two closest points (the end's centre and the other's).
  Vec3d touching(int pair, int elementA, const ClosestPoints& cp) const {
    const double radiusA = rectangles(pair) ? 0.0 : inscribed(beams_->elements()[elementA].beam);
    return cp.pA + (radiusA + 0.5 * cp.gap) * cp.normal;
  }
  Vec3d touching(const ContactPointRecord& p, const ClosestPoints& cp) const {
    if (p.key.corner()) return cp.pA + (0.5 * cp.gap) * cp.normal;  // (the normal u points from the corner to B)
    if (p.end() || p.key.endToEnd()) return 0.5 * (cp.pA + cp.pB);
    return touching(p.key.pair, p.elementA, cp);
  }
  // A point of a blended pair whose weight is zero in `s`: it carries nothing there.
  bool carriesNothing(const ContactPointRecord& p, const core::State& s) const {
    return blends(p.key.pair) && blendWeightAt(p, s) == 0.0;
  }

  // The point as its strategy sees it, with kinematics `k` in `state`.
  ContactPoint strategyView(const ContactPointRecord& p, const ContactKinematics& k, const core::State& state) const;
  // Whether a pair's line points have friction across the axes: circles with the isotropic law.
  // Rectangles' edges measure no slip across; with the Per Line law the two laws, along and across,
  // would bound each component by mu N and let the force reach sqrt(2) mu N, so line points keep
  // the law along the axes alone.
  bool acrossFriction(int pair) const;
  // Whether a line point's slip across the axes (g_T1, circles) moves with a dof that no support
  // fixes: where supports hold every node of both elements across the axes and against their twist (a
  // model kept in a plane), its row would fix nothing (a singular matrix), and friction across has
  // nothing to act on. (Kinematics without variations: true.)
  bool movesAcross(const ContactPointRecord& p, const ContactKinematics& k) const;
  // The views' frictionRelaxation (ContactPoint): 10^n after n retries of Newton solves whose slip
  // directions cycled.
  void setFrictionRelaxation(double factor) { frictionRelaxation_ = factor; }
  // Line contact enforced on a nodal field (Lagrange multipliers, Augmented Lagrange): blendWeight.
  void setNodalLineField(bool nodal) { nodalLineField_ = nodal; }

 private:
  struct Line {
    double cy = 0.0, cz = 0.0;  // offset in the section's (y, z)
    double radius = 0.0;
  };
  std::shared_ptr<const elements::BeamSet> beams_;
  std::vector<ContactPairSpec> pairs_;
  ContactOptions options_;
  double frictionRelaxation_ = 1.0;
  bool nodalLineField_ = false;
  bool lineContact_ = false;
  core::State reference_;
  std::set<std::tuple<int, int, int>> lineGates_, pointGates_;  // (pair, element A, element B): openGates
  std::vector<std::vector<Line>> lines_;  // per beam
  std::set<std::pair<int, int>> joined_;  // options_.joinedNodes, both orders
  // (beam A, beam B) -> index into pairs_ (hashed: the search looks a pair up for every two
  // elements whose boxes overlap, 10^5 pairs on the 316 x 316 crossed layers).
  static std::uint64_t beamPairKey(int a, int b) { return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b); }
  std::unordered_map<std::uint64_t, int> pairIndex_;
  std::set<int> freeEnd_;  // nodes at a beam end that no other element or pin uses
  std::vector<double> inscribed_;  // per beam: radius of the largest circle in its section
  std::vector<double> circumscribed_;  // per beam: radius of the smallest circle about its section
  // Per element: the unit reference tangents of its smoothed axis at its two nodes (pointContactAxes), and
  // the kink left there (smoothedKink).
  std::vector<std::array<Vec3d, 2>> nodeTangents_;
  std::vector<std::array<double, 2>> kinkLeft_;
};

}  // namespace bc::constraints
