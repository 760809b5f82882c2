#include "LineContact.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

#include "core/PointGrid.hpp"

namespace bc::constraints {

using elements::BeamElement;

LineContact::LineContact(const ContactGeometry& geometry, const ConstraintEnforcer& enforcer)
    : geometry_(geometry), enforcer_(enforcer) {
  nodal_ = geometry_.lineContact() && enforcer_.lineField() == ConstraintEnforcer::LineField::Nodal;
  // Gauss-Legendre points on [0, 1]: roots of P_n by Newton's method from the Chebyshev guesses.
  const int n = std::max(geometry_.options().lineGaussPoints, 1);
  for (int i = 0; i < n; ++i) {
    double x = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      if (n == 1) p0 = 1.0, p1 = x;
      dp = n * (x * p1 - p0) / (x * x - 1.0);
      const double step = p1 / dp;
      x -= step;
      if (std::abs(step) < 1e-16) break;
    }
    gaussXi_.push_back(0.5 * (1.0 - x));
    gaussWeight_.push_back(1.0 / ((1.0 - x * x) * dp * dp));  // (2 / ((1 - x^2) P_n'^2)) / 2
  }
  // Segment planes: at a node between two elements of a beam the mean of their unit axes, at an end
  // the end element's axis.
  const auto& elems = geometry_.beams().elements();
  std::map<std::pair<int, int>, int> byIndex;  // (beam, index) -> element
  for (std::size_t e = 0; e < elems.size(); ++e) byIndex[{elems[e].beam, elems[e].index}] = static_cast<int>(e);
  segmentPlanes_.resize(elems.size());
  for (std::size_t e = 0; e < elems.size(); ++e) {
    const Vec3d t = column(elems[e].data.T0, 0);
    for (int side = 0; side < 2; ++side) {
      const auto next = byIndex.find({elems[e].beam, elems[e].index + (side == 0 ? -1 : 1)});
      Vec3d m = t;
      if (next != byIndex.end()) m = m + column(elems[next->second].data.T0, 0);
      segmentPlanes_[e][side] = (1.0 / norm(m)) * m;
    }
  }
  // Each beam's largest bending stiffness.
  beamStiffness_.assign(geometry_.beams().beams().size(), 0.0);
  for (std::size_t e = 0; e < elems.size(); ++e)
    beamStiffness_[elems[e].beam] =
        std::max(beamStiffness_[elems[e].beam], std::max(elems[e].data.EIy, elems[e].data.EIz));
  setInitial(nullptr);
}

void LineContact::setInitial(const core::State* initial) {
  // A beam's end node merges into its neighbour where a node of another beam lies at the same place
  // along its axis (within 1e-3 of its end element) and within reach of contact (twice the two
  // sections' circumscribed radii), and the supports hold both along the line between their axes
  // (the contact's normal there): they may fix the gap the end's multiplier would constrain. (A node
  // held only across that line, as the angle sweep's inner nodes by uy, does not: a short beam's
  // clamped ends over such nodes of a long beam, merged, carried 22 % too little force.) Without the
  // initial positions (before initialize) every end merges. A penalized field's ends never merge (its
  // rows stay independent of the supports').
  const auto& elems = geometry_.beams().elements();
  const auto& beams = geometry_.beams().beams();
  const auto& held = geometry_.options().heldNodes;
  const bool penalized = enforcer_.lineFieldPenalized();
  mergedEnds_.assign(beams.size(), {!penalized, !penalized});
  if (initial && !penalized) {
    // The held nodes by place: a grid whose cells hold every reach (twice two circumscribed radii,
    // and 1e-3 of an element along the axis).
    double radius = 0.0, length = 0.0;
    for (std::size_t b = 0; b < beams.size(); ++b)
      radius = std::max(radius, geometry_.circumscribed(static_cast<int>(b)));
    for (const auto& e : elems) length = std::max(length, e.data.L0);
    core::PointGrid grid(std::max(4.0 * radius + 1e-3 * length, 1e-300));
    std::vector<int> beamOf(initial->numNodes(), -1);
    for (std::size_t b = 0; b < beams.size(); ++b)
      for (int n : beams[b].nodes) beamOf[n] = static_cast<int>(b);
    for (const auto& [m, fixed] : held) grid.insert(initial->position[m], m);
    for (std::size_t b = 0; b < beams.size(); ++b) {
      const auto& nodes = beams[b].nodes;
      for (int side = 0; side < 2 && nodes.size() >= 2; ++side) {
        const int end = side == 0 ? nodes.front() : nodes.back();
        const int inner = side == 0 ? nodes[1] : nodes[nodes.size() - 2];
        bool merged = false;
        const Vec3d x0 = initial->position[end], t = initial->position[inner] - x0;
        for (const int m : held.count(end) ? grid.near(x0) : std::vector<int>{}) {
          const int other = beamOf[m];
          if (other < 0 || other == static_cast<int>(b)) continue;
          const Vec3d d = initial->position[m] - x0;
          const double along = dot(d, t) / dot(t, t);
          const Vec3d across = d - along * t;
          const double reach = 2.0 * (geometry_.circumscribed(static_cast<int>(b)) + geometry_.circumscribed(other));
          // (Held along it: every component of the unit offset above 1e-2 fixed. The offset is the
          // normal only roughly: a beam turned by 0.08 degrees gives it an axial component of 1e-4,
          // which supports free along the axis do not hold and the contact normal does not have.)
          const double apart = norm(across);
          if (!(std::abs(along) <= 1e-3 && apart <= reach && apart > 0.0)) continue;
          const Vec3d normal = (1.0 / apart) * across;
          if ((merged = heldAlong(end, normal, 1e-2) && heldAlong(m, normal, 1e-2))) break;
        }
        mergedEnds_[b][side] = merged;
      }
    }
  }
  // Each field node's elements.
  fieldElements_.clear();
  if (nodal_)
    for (std::size_t e = 0; e < elems.size(); ++e)
      for (int side = 0; side < 2; ++side) {
        FieldElements& f = fieldElements_[fieldNode(static_cast<int>(e), side)];
        f.beam = elems[e].beam;
        if (f.elements.empty() || f.elements.back() != static_cast<int>(e)) f.elements.push_back(static_cast<int>(e));
      }
}

namespace {
// An interior node's number: element, level and place (j of 2^level) packed above kInteriorNode.
constexpr int kPlaces = 1 << LineContact::kMaxFieldLevel;
constexpr int kLevels = LineContact::kMaxFieldLevel + 1;
int interiorNumber(int element, int level, int j) {
  return LineContact::kInteriorNode + (element * kLevels + level) * kPlaces + j;
}
void interiorParts(int node, int& element, int& level, int& j) {
  const int code = node - LineContact::kInteriorNode;
  j = code % kPlaces;
  level = (code / kPlaces) % kLevels;
  element = code / (kPlaces * kLevels);
}
// The largest element a packed interior number can name.
constexpr int kRefinableElements = (INT_MAX - LineContact::kInteriorNode) / (kPlaces * kLevels);

// A Gauss point's index in its key: its index q among the Gauss points of its part of the segment, and
// the part (level l, part k of 2^l) as the slot 2^l - 1 + k (0 for an unrefined element, so those
// keep their index q).
constexpr int kGaussPerPart = 32;  // the deck's largest Line Gauss Points (30) and two end points
static_assert(kGaussPerPart * ((2 << LineContact::kMaxFieldLevel) - 1) <= PointKey::kGaussSlots,
              "a segment's Gauss points of every part must fit the key's slots");
int gaussIndex(int level, int part, int q) { return q + kGaussPerPart * ((1 << level) - 1 + part); }
int gaussOf(int index) { return index % kGaussPerPart; }
// The point at a free end of B inside a part of a nodal field (offerSegment): the last two indices of
// its part (the deck's Gauss points are at most kGaussPerPart - 2), at the covered piece's low or high
// bound.
constexpr int kEndAtLow = kGaussPerPart - 2, kEndAtHigh = kGaussPerPart - 1;
bool endSlot(int q) { return q >= kEndAtLow; }
void gaussPart(int index, int& level, int& part) {
  const int slot = index / kGaussPerPart;
  level = 0;
  while ((2 << level) - 1 <= slot) ++level;
  part = slot - ((1 << level) - 1);
}
// The segment's share of part k of 2^l of A's element: cut at the part's ends (constant bounds) where
// they lie inside it.
LineSegment partSegment(const LineSegment& seg, int level, int part) {
  if (level == 0) return seg;
  const double m = 1 << level, a = part / m, b = (part + 1) / m;
  LineSegment sub = seg;
  if (a > seg.lo) sub.lo = a, sub.loKind = -1;
  if (b < seg.hi) sub.hi = b, sub.hiKind = -1;
  if (!(sub.hi > sub.lo)) sub = LineSegment{};
  return sub;
}
LineSegment pointSegment(const ContactPointRecord& p, const LineSegment& seg) {
  int level = 0, part = 0;
  gaussPart(p.gauss(), level, part);
  return partSegment(seg, level, part);
}
}  // namespace

int LineContact::fieldLevel(int pair, int edge, int element) const {
  const auto it = levels_.find({pair, edge, element});
  return it == levels_.end() ? 0 : it->second;
}

int LineContact::fieldNodeAt(int element, int level, int j) const {
  const int m = 1 << level;
  if (m == 1) return fieldNode(element, j);
  const BeamElement& e = geometry_.beams().elements()[element];
  const int last = static_cast<int>(geometry_.beams().beams()[e.beam].nodes.size()) - 2;
  // At a beam's merged end the outer part's end merges into its inner neighbour (no multiplier there).
  if (j == 0 && e.index == 0 && mergedEnds_[e.beam][0]) j = 1;
  if (j == m && e.index == last && mergedEnds_[e.beam][1]) j = m - 1;
  if (j == 0) return fieldNode(element, 0);
  if (j == m) return fieldNode(element, 1);
  return interiorNumber(element, level, j);
}

std::vector<LineContact::FieldPart> LineContact::fieldParts(int pair, int edge, int element) const {
  const int level = fieldLevel(pair, edge, element), m = 1 << level;
  const double L = geometry_.beams().elements()[element].data.L0 / m;
  std::vector<FieldPart> parts;
  for (int j = 0; j < m; ++j) parts.push_back({fieldNodeAt(element, level, j), fieldNodeAt(element, level, j + 1), L});
  return parts;
}

Vec3d LineContact::fieldPosition(int node, const core::State& s) const {
  if (!interiorNode(node)) return s.position[node];
  int element = 0, level = 0, j = 0;
  interiorParts(node, element, level, j);
  const BeamElement& e = geometry_.beams().elements()[element];
  const double t = static_cast<double>(j) / (1 << level);
  return (1.0 - t) * s.position[e.node1] + t * s.position[e.node2];
}

int LineContact::fieldHome(int node) const {
  if (!interiorNode(node)) return node;
  int element = 0, level = 0, j = 0;
  interiorParts(node, element, level, j);
  return geometry_.beams().elements()[element].node1;
}

std::map<std::tuple<int, int, int>, std::pair<double, double>> LineContact::zoneEnds(const PointMap& points,
                                                                                     const core::State& s) const {
  // Per element of A (pair, edge, element): its Gauss points' lowest and highest gaps per thinner
  // inscribed radius. Kept are the elements where a contact zone may end: not a beam's end element,
  // not where supports hold both beams' ends (the gap they hold is no field's to close: heldEnds),
  // and beside an element, on A, whose points are all open by kResolveLine (or none touches). (A
  // zone along many elements whose gap waves about zero between the field's nodes, as a wire's on a
  // core whose helix the cubic elements follow only approximately, is the beams' discretization, not
  // the field's: refining it would constrain the cubic elements' gap more often than they can follow,
  // dependent rows and a singular matrix.)
  std::map<std::tuple<int, int, int>, std::pair<double, double>> range;
  std::set<std::tuple<int, int, int>> held;
  for (const auto& [key, p] : points) {
    if (!p.line() || p.elementA > kRefinableElements) continue;
    if (!(geometry_.blendWeightAt(p, s) > kCarries)) continue;
    const auto where = std::make_tuple(p.key.pair, p.edge(), p.elementA);
    if (held.count(where)) continue;
    if (heldEnd(p, 0, s) || heldEnd(p, 1, s)) {
      held.insert(where);
      continue;
    }
    // (Beyond the gap the strategy keeps under the point's traction: a penalty's penetration.)
    const double gap = (geometry(p, s).gap - enforcer_.lineFieldGap(p.result.active ? p.result.lambdaN : 0.0)) /
                       geometry_.thinner(p.key.pair);
    const auto [it, first] = range.try_emplace(where, gap, gap);
    if (!first) it->second = {std::min(it->second.first, gap), std::max(it->second.second, gap)};
  }
  const auto& elems = geometry_.beams().elements();
  const auto neighbour = [&](int e, int step) {
    const int n = e + step;
    return n >= 0 && n < static_cast<int>(elems.size()) && elems[n].beam == elems[e].beam &&
                   elems[n].index == elems[e].index + step
               ? n
               : -1;
  };
  const auto open = [&](int pair, int edge, int e) {
    if (held.count({pair, edge, e})) return false;
    const auto it = range.find({pair, edge, e});
    return it == range.end() || it->second.first > kResolveLine;
  };
  std::map<std::tuple<int, int, int>, std::pair<double, double>> ends;
  for (const auto& [where, r] : range) {
    const auto [pair, edge, e] = where;
    const int before = neighbour(e, -1), after = neighbour(e, 1);
    if (before < 0 || after < 0) continue;
    if (!open(pair, edge, before) && !open(pair, edge, after)) continue;
    // The zone may end inside the element while its deepest points lie in the neighbour on the other
    // side of their shared node, whose hat spans both: the field then spreads the node's traction
    // over the element's open points, and the beams penetrate less than kResolveLine in the element
    // itself. The neighbours' deepest gaps count as those of an element that touches. (The sweep's
    // crossing at 0.3 degrees on 20 / 12 elements: tractions on points open by 3.6e-4 of the radius,
    // no element both penetrating and open by 1e-4, the force 2.7 % below the converged one without a
    // warning.)
    // Likewise the zone may end at or just beyond a node, its element's points all penetrating and
    // the neighbour's open: the node's hat then weighs the open neighbour against the element, its
    // weighted gap is open, and no node holds the zone. An element that penetrates counts its
    // neighbours' most open gaps as its own. (The sweep's circles at 4 degrees on an 11-element
    // ground, the zone 9 long inside an element 9.1 long: the rod went 10 % of its radius into the
    // ground with no active point and no refinement.)
    auto widened = r;
    for (const int n : {before, after}) {
      if (held.count({pair, edge, n})) continue;
      const auto it = range.find({pair, edge, n});
      if (it == range.end()) continue;
      if (r.first < kResolveLine) widened.first = std::min(widened.first, it->second.first);  // (touches)
      if (r.first < -kResolveLine) widened.second = std::max(widened.second, it->second.second);  // (penetrates)
    }
    ends.emplace(where, widened);
  }
  return ends;
}

bool LineContact::refineField(const PointMap& points, const core::State& s) {
  // Refined are the elements where a contact zone ends (zoneEnds) in which some Gauss points
  // penetrate by more than kResolveLine of the thinner inscribed radius and some are open by as much.
  bool refined = false;
  for (const auto& [where, r] : zoneEnds(points, s)) {
    if (!(r.first < -kResolveLine && r.second > kResolveLine)) continue;
    if (fieldLevel(std::get<0>(where), std::get<1>(where), std::get<2>(where)) >= levelCap(std::get<0>(where)))
      continue;
    // A refinement must pay: the deepest penetration down by a quarter since the last one.
    const auto last = refinedAt_.find(where);
    if (last != refinedAt_.end() && !(r.first > 0.75 * last->second)) continue;
    refinedAt_[where] = r.first;
    ++levels_[where];
    refined = true;
  }
  return refined;
}

void LineContact::resumeLevels(const PointMap& points, const core::State& s) {
  // The refinement the interior nodes of the last converged points show, kept where a zone still
  // ends inside the element (it touches, within kResolveLine, and opens by as much) or an interior
  // node carries force: the zone's resolution carries over to the next step, and a zone that has
  // moved on leaves its elements. (Dropped while its interior nodes carried force, an element's
  // field lost that force at the next step's start: a rectangular rod on a ground, 20 elements,
  // 5 increments, started the increment after T = 0.8 with a residual of 0.41 where its load gives
  // 0.044, and stopped there.)
  levels_.clear();
  refinedAt_.clear();
  resumedLevel_.clear();
  std::set<std::tuple<int, int, int>> carrying;
  for (const auto& [key, p] : points) {
    if (!p.node() || !interiorNode(p.key.node)) continue;
    int element = 0, level = 0, j = 0;
    interiorParts(p.key.node, element, level, j);
    int& l = levels_[{p.key.pair, p.key.edge, element}];
    l = std::max(l, level);
    int& resumed = resumedLevel_[p.key.pair];
    resumed = std::max(resumed, level);
    if (p.result.active && p.result.lambdaN != 0.0) carrying.insert({p.key.pair, p.key.edge, element});
  }
  if (levels_.empty()) return;
  const auto ends = zoneEnds(points, s);
  for (auto it = levels_.begin(); it != levels_.end();) {
    const auto r = ends.find(it->first);
    const bool keep = (r != ends.end() && r->second.first < kResolveLine && r->second.second > kResolveLine) ||
                      carrying.count(it->first);
    it->second = std::min(it->second, levelCap(std::get<0>(it->first)));
    it = keep && it->second > 0 ? std::next(it) : levels_.erase(it);
  }
}

void LineContact::clearLevels(bool failed) {
  // A step that failed with a refined field is retried (cut) with the pair's field refined one level
  // less than the failed attempt reached, and so on for the rest of the run (down to unrefined): the
  // refined field may have constrained the beams' gap more often than their elements can follow (a
  // singular matrix) or kept changing the active set. (Before, the retry went on unrefined after two
  // failures: crossing circles at 4.5 degrees on 11 elements, whose zone no unrefined node sees,
  // then passed into each other with no force. The unresolved-zone warning tells what is left.)
  // The cap goes below the level of the field the step started from (`start`, its converged field)
  // only once a retry of this step capped at that level has failed too: below it the retry drops the
  // converged field's refined elements, their points and their force, and starts far from
  // equilibrium (a rectangular rod on a ground, 10 increments: a first residual of 0.55 where the
  // increment's load gives 0.07, Newton steps 1.2 long, the rod through the ground near its held
  // end). The frictional circles of the angle sweep at 4 and 5 degrees need that second step down.
  if (failed) {
    std::map<int, int> reached;
    for (const auto& [where, level] : levels_) {
      int& r = reached[std::get<0>(where)];
      r = std::max(r, level);
    }
    for (const auto& [pair, level] : reached) {
      if (level == 0) continue;
      const auto resumed = resumedLevel_.find(pair);
      const int start = resumed == resumedLevel_.end() ? 0 : resumed->second;
      int cap = level - 1;
      if (level > start) cap = std::max(cap, start);
      else if (retriedAtStart_.insert(pair).second) cap = start;
      levelCap_[pair] = std::min(levelCap(pair), cap);
    }
  }
  levels_.clear();
  refinedAt_.clear();
}

std::vector<int> LineContact::fieldNodeElements(int node) const {
  if (interiorNode(node)) {
    int element = 0, level = 0, j = 0;
    interiorParts(node, element, level, j);
    return {element};
  }
  const auto it = fieldElements_.find(node);
  return it != fieldElements_.end() ? it->second.elements : std::vector<int>{};
}

double LineContact::fieldLength(const PointKey& node) const {
  // int N_a ds: half of each part the node ends.
  const std::vector<int> elements = fieldNodeElements(node.node);
  double length = 0.0;
  for (int e : elements)
    for (const FieldPart& part : fieldParts(node.pair, node.edge, e))
      length += 0.5 * part.length * ((part.from == node.node) + (part.to == node.node));
  return length;
}

double LineContact::fieldCompliance(const PointKey& node) const {
  // A traction p sin(pi x / h) bends each beam by p (h / pi)^4 / EI, the two in opposite senses; h
  // the shortest part of the field at the node.
  const std::vector<int> elements = fieldNodeElements(node.node);
  if (elements.empty()) return 0.0;
  const auto& elems = geometry_.beams().elements();
  double shortest = 0.0, stiffness = 0.0;
  for (int e : elements) {
    const double h = elems[e].data.L0 / (1 << fieldLevel(node.pair, node.edge, e));
    shortest = shortest > 0.0 ? std::min(shortest, h) : h;
    stiffness = std::max(stiffness, std::max(elems[e].data.EIy, elems[e].data.EIz));
  }
  const auto& pr = geometry_.pairs()[node.pair];
  const int beam = elems[elements.front()].beam;
  const int other = beam == pr.beamA ? pr.beamB : pr.beamA;
  const double h = shortest / M_PI;
  return h * h * h * h * (1.0 / stiffness + 1.0 / beamStiffness_[other]);
}

std::pair<std::array<int, 2>, int> LineContact::facing(int eA, int eB, const core::State& s) const {
  // The faces that touch are those across the direction that separates the two sections most (or
  // lets them overlap least): of the four face normals of the two sections, the one along which the
  // centres lie furthest beyond the two sections' reach. (The direction between the axes alone took
  // the side faces of two flat beams crossing at 2 degrees where their axes lay further apart
  // sideways than up, and refused the deck for an overlap of those side faces.) Decided for the
  // element pair in one order, so that both ways round agree where two directions tie (squares).
  const auto& elems = geometry_.beams().elements();
  const bool swapped = eB < eA;
  const BeamElement &a = elems[swapped ? eB : eA], &b = elems[swapped ? eA : eB];
  // Between the axes' closest points (elements of a crossing that overlap along the axes only in
  // part lie apart sideways by the crossing's drift between their midpoints).
  const Vec3d &a1 = s.position[a.node1], &a2 = s.position[a.node2];
  const Vec3d &b1 = s.position[b.node1], &b2 = s.position[b.node2];
  const SegmentClosest c = segmentClosest(a1, a2, b1, b2);
  const Vec3d tA = a2 - a1;
  Vec3d d = (b1 + c.t * (b2 - b1)) - (a1 + c.s * tA);
  d = d - (dot(d, tA) / dot(tA, tA)) * tA;
  // Face f of a section: outward normal +e2, +e3, -e2, -e3 for f = 0..3 (current: R_1 T0).
  const auto normal = [&](const BeamElement& e, int f) {
    return (f < 2 ? 1.0 : -1.0) * (s.rotation[e.node1] * column(e.data.T0, 1 + f % 2));
  };
  const auto reach = [&](const BeamElement& e, const Vec3d& u) {
    return sectionReach(geometry_.beams().beams()[e.beam].section, s.rotation[e.node1] * column(e.data.T0, 0),
                        normal(e, 0), normal(e, 1), u);
  };
  const auto toward = [&](const BeamElement& e, const Vec3d& u) {
    int face = 0;
    for (int f = 1; f < 4; ++f)
      if (dot(normal(e, f), u) > dot(normal(e, face), u)) face = f;
    return face;
  };
  Vec3d best{};
  double most = -1e300;
  for (const BeamElement* e : {&a, &b})
    for (int f = 0; f < 2; ++f) {
      Vec3d u = normal(*e, f);
      if (dot(u, d) < 0.0) u = -1.0 * u;
      const double separation = dot(u, d) - reach(a, u) - reach(b, u);
      if (separation > most + 1e-12 * (1.0 + std::abs(most))) {  // (ties keep the first: A's, then B's)
        most = separation;
        best = u;
      }
    }
  int faceA = toward(a, best), faceB = toward(b, -1.0 * best);
  if (swapped) std::swap(faceA, faceB);
  // A's edges on its face (lines 0..3 at (+y,+z), (-y,+z), (-y,-z), (+y,-z)).
  static const std::array<int, 2> edgesOf[4] = {{0, 3}, {0, 1}, {1, 2}, {2, 3}};
  return {edgesOf[faceA], faceB};
}

LinePairInput LineContact::faceInput(int eA, int edgeA, int eB, int faceB, const core::State& s) const {
  LinePairInput in = geometry_.lineInput(eA, edgeA, eB, 0, s);
  const BeamElement& b = geometry_.beams().elements()[eB];
  const auto& sec = geometry_.beams().beams()[b.beam].section;
  const Vec3d axis = column(b.data.T0, 1 + faceB % 2);  // e2 or e3
  const double sign = faceB < 2 ? 1.0 : -1.0;
  const double half = 0.5 * (faceB % 2 == 0 ? sec.width : sec.height);  // along the face normal
  const double across = 0.5 * (faceB % 2 == 0 ? sec.height : sec.width);  // the face's half width
  in.oB = (sign * half) * axis;
  in.nB = sign * axis;
  in.halfWidthB = across;
  in.face = true;
  in.radiusSum = 0.0;
  return in;
}

LinePairInput LineContact::input(const ContactPointRecord& p, const core::State& s) const {
  LinePairInput in = segmentInput(p.key.pair, p.elementA, p.elementB, p.edge(), p.face(), s);
  // (circles with friction: the surfaces' slip as the sections turn, from the point's normal at the
  // last converged state; rectangles' edges turn with their sections; without friction the slip is
  // not used, and the turn's four vectors would only cost)
  if (!in.face && geometry_.pairs()[p.key.pair].friction > 0.0) {
    setTurnSlip(in, geometry_.lineInput(p.elementA, 0, p.elementB, 0, geometry_.reference()), -1.0 * p.normal,
                p.xiPrev - geometry_.beams().elements()[p.elementA].index,
                p.etaPrev - geometry_.beams().elements()[p.elementB].index);
    in.acrossSlip = geometry_.acrossFriction(p.key.pair);
  }
  return in;
}

LinePairInput LineContact::segmentInput(int pair, int eA, int eB, int edge, int face, const core::State& s) const {
  LinePairInput in =
      geometry_.rectangles(pair) ? faceInput(eA, edge, eB, face, s) : geometry_.lineInput(eA, 0, eB, 0, s);
  in.sB1 = segmentPlanes_[eB][0];
  in.sB2 = segmentPlanes_[eB][1];
  return in;
}

LineHistory LineContact::history(const ContactPointRecord& p) const {
  const auto& elems = geometry_.beams().elements();
  return {p.xiPrev - elems[p.elementA].index, p.etaPrev - elems[p.elementB].index, p.etaRate};
}

std::array<double, 2> LineContact::slip(const ContactPointRecord& p, const ClosestPoints& cp,
                                        const LinePairInput& in) const {
  const double etaPrev = history(p).etaPrevAt(cp.xi);
  const std::array<double, 2> surface = surfaceSlips(in, cp.xi, etaPrev, cp.eta, -1.0 * cp.normal);
  return {surface[0], (cp.eta - etaPrev) * cp.slipMetric + surface[1]};
}

bool LineContact::endPoint(const ContactPointRecord& p) { return p.line() && endSlot(gaussOf(p.gauss())); }

double LineContact::pointXi(const ContactPointRecord& p) const {
  const int q = gaussOf(p.gauss());
  return q == kEndAtLow ? 0.0 : q == kEndAtHigh ? 1.0 : gaussXi_[q];
}

double LineContact::weight(const ContactPointRecord& p, double segment) const {
  const double L0 = geometry_.beams().elements()[p.elementA].data.L0;
  if (endSlot(gaussOf(p.gauss()))) {
    // (a point: the half part's length, int N ds of a hat over one part, whatever the segment)
    int level = 0, part = 0;
    gaussPart(p.gauss(), level, part);
    return 0.5 * L0 / (1 << level);
  }
  return gaussWeight_[gaussOf(p.gauss())] * L0 * segment;
}

double LineContact::weightRate(const ContactPointRecord& p) const {
  return endSlot(gaussOf(p.gauss())) ? 0.0 : weight(p, 1.0);
}

void LineContact::findPoints(int pi, int ea, int eb, long long visit, const core::State& s, const PointMap& known,
                             const CandidateOffer& offer) const {
  // The Gauss points of the segment of A's element that lies between the planes of B's element's
  // nodes (segments of neighbouring elements of B share their plane, so they tile A's line and
  // no Gauss point straddles a node of B or lies beyond B's end).
  if (!geometry_.rectangles(pi)) return offerSegment(pi, ea, eb, 0, 0, 0.0, 0.0, 0.0, visit, s, known, offer);
  // Rectangular sections: two parallel faces touch on the strip where they overlap across, and the
  // two lines that bound it carry the contact. Each bounding line is an edge of A lying on B's face
  // or an edge of B lying on A's face, whichever lies inside the other's face; so both beams' two
  // edges facing the other beam are tried: A's on B's face (Gauss points on A's segments between
  // B's node planes), B's on A's face (points with the roles swapped: on B's segments between A's
  // node planes, their elementA of beam B). On each side of the strip, the edges of A and B there
  // lie apart across by m (B's edge inside A's face by m, A's beyond B's face by as much: m < 0 where
  // A's edge is the inner one), and one of them carries the side at every m, with a band of B's
  // half width between 1e-3 and 5 % where the edge that carries keeps it (so that Newton's iterates
  // near the switch do not swap the carrier back and forth):
  //   A's point where m <= 1e-3, or m <= 5 % and the point is known, or m <= 5 % and A's edge
  //   alone has points on this side of the element pair;
  //   B's point where m > 5 %, or m > 1e-3 and the point is known, or m > 1e-3 and A's edge has
  //   no points on this side of the element pair.
  // Applied to the points it chose, the rule chooses them again, and at no m do both edges carry.
  // Before, the band was decided per point alone (A's new points to 1e-3, B's new points beyond
  // 5 %): where neither had points yet and m lay in the band (equal widths offset across by 1 % of
  // the half width, or a rod turned by 1 degree about its axis), no edge carried that side: the
  // upper beam lay on one line and twisted, "complete".
  const auto [edgesA, faceB] = facing(ea, eb, geometry_.reference());
  const auto [edgesB, faceA] = facing(eb, ea, geometry_.reference());
  const auto& elems = geometry_.beams().elements();
  const auto& secB = geometry_.beams().beams()[elems[eb].beam].section;
  const double halfB = 0.5 * (faceB % 2 == 0 ? secB.height : secB.width);  // B's face's half width
  // The side of the strip an edge bounds (0, 1): its place across B's face (in the reference) from
  // the other element's axis. Each of the four edges' sides once per call.
  const core::State& ref = geometry_.reference();
  const Vec3d axisB = ref.position[elems[eb].node2] - ref.position[elems[eb].node1];
  const Vec3d across = cross(axisB, ref.rotation[elems[eb].node1] * column(elems[eb].data.T0, 1 + faceB % 2));
  const auto side = [&](int e, int edge, int other) {
    const LinePairInput in = geometry_.lineInput(e, edge, other, 0, ref);
    const Vec3d p = 0.5 * (in.xA1 + in.xA2) + 0.5 * (in.RA1 * in.oA + in.RA2 * in.oA);
    const Vec3d o1 = ref.position[elems[other].node1], d = ref.position[elems[other].node2] - o1;
    const Vec3d c = o1 + (dot(p - o1, d) / dot(d, d)) * d;
    return dot(p - c, across) >= 0.0 ? 1 : 0;
  };
  const std::array<int, 2> sideA{side(ea, edgesA[0], eb), side(ea, edgesA[1], eb)};
  const std::array<int, 2> sideB{side(eb, edgesB[0], ea), side(eb, edgesB[1], ea)};
  // Whether any point of element a's edge on element b's face is known.
  const auto carries = [&](int a, int b, int edge, int face) {
    const PointKey first = PointKey::gaussPoint(pi, std::numeric_limits<int>::min(), b, edge, face,
                                                static_cast<int>(PointKey::kGaussSlots));
    const PointKey last = PointKey::gaussPoint(pi, std::numeric_limits<int>::max(), b, edge, face, 0);
    for (auto it = known.lower_bound(first); it != known.end() && !(last < it->first); ++it)
      if (it->first.kind == PointKey::Kind::Gauss && it->first.elementA == a) return true;
    return false;
  };
  std::array<bool, 2> heldByA{false, false}, heldByB{false, false};
  for (int i = 0; i < 2; ++i) {
    if (carries(ea, eb, edgesA[i], faceB)) heldByA[sideA[i]] = true;
    if (carries(eb, ea, edgesB[i], faceA)) heldByB[sideB[i]] = true;
  }
  constexpr double kBand = 1e-3, kKeptBand = 0.05;
  for (int i = 0; i < 2; ++i) {
    const int k = sideA[i];
    offerSegment(pi, ea, eb, edgesA[i], faceB, 0.0, heldByA[k] && !heldByB[k] ? kKeptBand : kBand, kKeptBand, visit, s,
                 known, offer);
  }
  for (int i = 0; i < 2; ++i)
    offerSegment(pi, eb, ea, edgesB[i], faceA, halfB, heldByA[sideB[i]] ? kKeptBand : kBand, kBand, visit, s, known,
                 offer);
}

void LineContact::offerSegment(int pi, int ea, int eb, int edge, int face, double inside, double band, double keptBand,
                               long long visit, const core::State& s, const PointMap& known,
                               const CandidateOffer& offer) const {
  const LinePairInput in = segmentInput(pi, ea, eb, edge, face, s);
  // (A sliver of a segment, where A's element ends at B's node within round-off, carries nothing.)
  constexpr double kSliver = 1e-9;
  const LineSegment seg = lineSegment(in);
  if (!(seg.length() > kSliver)) return;
  // The planes partition A's line where its points project onto B about along B's axis (nearly
  // parallel lines close together). Where the segment's points project far beyond B's element
  // instead (lines further apart than their elements are long, at an angle: neighbouring wires
  // of a strand, element pairs several elements apart), the pair is not in line contact.
  const double mid = lineProjection(in, seg.lo + 0.5 * seg.length()).eta;
  if (!(mid > -0.5 && mid < 1.5)) return;
  // Two ends pushed into each other (end-to-end contact's): the segment runs from one beam's free end
  // to the plane of the other's, and is shorter than the sections overlap across (inscribed radii
  // less the axes' distance). Line points there would see the sides deep in each other (circles
  // whose axes meet: no normal at all); two beams lapped side by side overlap along more than across.
  const auto& elems = geometry_.beams().elements();
  const auto& A = elems[ea];
  const auto& B = elems[eb];
  const auto freeBound = [&](int kind, double at) {
    if (kind < 0) return (at == 0.0 && geometry_.freeEnd(A.node1)) || (at == 1.0 && geometry_.freeEnd(A.node2));
    return geometry_.freeEnd(kind == 0 ? B.node1 : B.node2);
  };
  if (freeBound(seg.loKind, seg.lo) && freeBound(seg.hiKind, seg.hi) && (seg.loKind < 0) != (seg.hiKind < 0)) {
    const LinePairInput axes = geometry_.axisInput(ea, eb, s);
    const ClosestPoints lo = lineProjection(axes, seg.lo), hi = lineProjection(axes, seg.hi);
    const double across = geometry_.inscribed(A.beam) + geometry_.inscribed(B.beam) -
                          lineProjection(axes, seg.lo + 0.5 * seg.length()).distance;
    if (norm(hi.pA - lo.pA) < across) return;
  }
  // A refined field's element (nodal fields) has Gauss points of its own in each part of the segment
  // (the segment cut at the parts' ends): each part integrates its hat functions as the whole element
  // does unrefined.
  const int level = nodal_ ? fieldLevel(pi, edge, ea) : 0;
  // The free ends of B along A's line: this segment's free bounds and those of B's end elements'
  // segments (B's mesh finer than A's: a part of A's field that B's end cuts may hold segments of
  // several elements of B, and each must give the part's points the same nodes).
  struct Cut {
    double at = 0.0;
    int element = 0;  // B's element whose segment ends there
  };
  std::vector<Cut> lowCuts, highCuts;  // B covering A's line above the end / below it
  if (nodal_) {
    const auto freeCuts = [&](const LineSegment& sg, int e) {
      const BeamElement& E = elems[e];
      if (sg.loKind >= 0 && geometry_.freeEnd(sg.loKind == 0 ? E.node1 : E.node2)) lowCuts.push_back({sg.lo, e});
      if (sg.hiKind >= 0 && geometry_.freeEnd(sg.hiKind == 0 ? E.node1 : E.node2)) highCuts.push_back({sg.hi, e});
    };
    freeCuts(seg, eb);
    const int firstB = eb - B.index;
    const int lastB = firstB + static_cast<int>(geometry_.beams().beams()[B.beam].nodes.size()) - 2;
    for (int e : {firstB, lastB}) {
      if (e == eb || (e == lastB && lastB == firstB)) continue;
      const LineSegment o = lineSegment(segmentInput(pi, ea, e, edge, face, s));
      if (o.length() > kSliver) freeCuts(o, e);
    }
  }
  for (int part = 0; part < (1 << level); ++part) {
    const LineSegment sub = partSegment(seg, level, part);
    if (!(sub.length() > kSliver)) continue;
    // Where a free end of B cuts the part, the end's force is a point force (B's end pressed onto A,
    // a clamped end onto a deflecting beam) that a linear field over the part cannot hold: the node
    // beyond the end carries a point at the end (its row the gap there: exact for such a force), and
    // the part's Gauss points carry the part's other node, constant over the piece (fieldShares).
    // Before, the part's hats were stretched over the piece: the node beyond stood at the end with
    // a linear traction, and from B's end 8 % into A's element on Lagrange multipliers were 8.5 %
    // low (penetrating by 1.6e-3 at the end, the refinement that would resolve it failing on a
    // singular matrix) and Augmented Lagrange 1.2 % low without a warning; with slivers (A's axial
    // motion under B's end lying on A's node) the node beyond had a row at nearly the place of its
    // neighbour's, near singular. B shorter than the part (both ends in it) keeps the part's hats.
    // A's own free end, its node keeping a multiplier (setInitial), is such an end too: the beams'
    // force there is a point force at the end (a short beam's clamped ends pressing a long one: 36 %
    // low with the end node merged, 18 % with the end element's hats). Its point is at A's end where
    // B covers it, else at B's end inside the part.
    // (A penalized field's nodes carry springs on the gap, not constraints: hats to the end, restricted to
    // what B covers, hold a penalty's traction eps_N g there as anywhere; a point at the end would add
    // a spring of half an element.)
    int endCut = 0;
    bool endHere = false;  // this segment holds the end: it offers the end's point
    if (nodal_ && !enforcer_.lineFieldPenalized()) {
      const double m = 1 << level, a = part / m, b = (part + 1) / m;
      const Cut* low = nullptr;
      const Cut* high = nullptr;
      for (const Cut& c : lowCuts)
        if (c.at > a && c.at < b && (c.element == eb || c.at <= sub.lo)) low = &c;
      for (const Cut& c : highCuts)
        if (c.at < b && c.at > a && (c.element == eb || c.at >= sub.hi)) high = &c;
      const bool ownLow = part == 0 && freeBound(-1, 0.0);
      const bool ownHigh = part == (1 << level) - 1 && freeBound(-1, 1.0);
      endCut = (low || ownLow) && (high || ownHigh) ? 0 : low || ownLow ? 1 : high || ownHigh ? 2 : 0;
      // (At an end element of A, where the part's outer node merges into its inner neighbour, one
      // multiplier would carry both the point and the piece: the part keeps its field.)
      if (endCut && fieldNodeAt(ea, level, part) == fieldNodeAt(ea, level, part + 1)) endCut = 0;
      const Cut* cut = endCut == 1 ? low : endCut == 2 ? high : nullptr;
      if (endCut && !cut)  // A's own end: its point where this segment reaches it
        endHere = endCut == 1 ? seg.lo == 0.0 : seg.hi == 1.0;
      // B's end within kOnNode of the part of one of its nodes counts as on that node (a known cut
      // within half of it): the node's hat holds the end, as where B's end lies exactly on it, and a
      // piece that short carries nothing. B's ends placed on A's nodes at 25 and 85 of the sweep's
      // deck moved off them by round-off (1e-9 of an element) with A's axial motion, and the cut
      // came and went between Newton's iterations: the active set cycled at first contact.
      if (cut) {
        constexpr double kOnNode = 1e-6;
        const int slot = endCut == 1 ? kEndAtLow : kEndAtHigh;
        endHere = cut->element == eb;
        const bool knownCut =
            known.count(PointKey::gaussPoint(pi, ea, cut->element, edge, face, gaussIndex(level, part, slot))) > 0;
        const double onNode = knownCut ? 0.5 * kOnNode : kOnNode;
        const double fromOuter = (endCut == 1 ? cut->at - a : b - cut->at) * m, piece = sub.length() * m;
        if (endHere && piece < onNode) continue;
        if (fromOuter < onNode) endCut = 0, endHere = false;
      }
    }
    const int points = (int)gaussXi_.size();
    for (int q = 0; q < points + (endHere ? 1 : 0); ++q) {
      const int slot = q < points ? q : endCut == 1 ? kEndAtLow : kEndAtHigh;
      const double at = q < points ? sub.lo + sub.length() * gaussXi_[q] : endCut == 1 ? sub.lo : sub.hi;
      const ClosestPoints cp = lineProjection(in, at);
      const PointKey key = PointKey::gaussPoint(pi, ea, eb, edge, face, gaussIndex(level, part, slot));
      if (!in.face && !(cp.distance > 1e-3 * in.radiusSum)) continue;  // (as above, at this point)
      if (in.face) {
        // Across the face (findPoints): an edge of the pair's A (inside 0) within the face's half
        // width and `band` of it beyond (`keptBand` for a known point); an edge of the pair's B
        // (inside: B's face's half width) inside the face by more than `band` (`keptBand`) of that.
        const double d = known.count(key) > 0 ? keptBand : band;
        const double reach = inside > 0.0 ? in.halfWidthB - inside * d : in.halfWidthB * (1.0 + d);
        if (std::abs(cp.lateral) > reach) continue;
      }
      offer(key, Candidate{ea, eb, cp, endCut}, 0.0, -visit);  // the last visit wins
    }
  }
}

namespace {
// A line point keeps its side (lineKinematics): where the axes have passed through each other since
// the normal `kept`, the gap is the deep one beyond the other axis and the normal turns round.
void keepSide(const LinePairInput& in, ClosestPoints& cp, const Vec3d& kept) {
  if (!(lineSide(in, cp, kept) < 0.0)) return;
  const double radiusSum = cp.distance - cp.gap;
  cp.gap = -cp.distance - radiusSum;
  cp.normal = -1.0 * cp.normal;
}
}  // namespace

ClosestPoints LineContact::geometry(const ContactPointRecord& p, const core::State& s, double* segment) const {
  return geometry(p, input(p, s), segment);
}

ClosestPoints LineContact::geometry(const ContactPointRecord& p, const LinePairInput& in, double* segment) const {
  const LineSegment seg = lineSegment(in);
  const LineSegment sub = pointSegment(p, seg);
  if (segment) *segment = sub.length();
  ClosestPoints cp = lineProjection(in, sub.lo + sub.length() * pointXi(p));
  cp.sinAngle = 1.0;  // a line point is defined at any angle
  keepSide(in, cp, p.normal);
  return cp;
}

ContactKinematics LineContact::kinematics(const ContactPointRecord& p, const core::State& s, Variations order) const {
  const LinePairInput in = input(p, s);
  return segmentKinematics(in, pointSegment(p, lineSegment(in)), pointXi(p), history(p), p.normal, order);
}

ContactKinematics LineContact::values(const ContactPointRecord& p, const ClosestPoints& cp, double segment,
                                      const core::State& s) const {
  ContactKinematics k;
  k.xi = cp.xi;
  k.eta = cp.eta;
  k.segment = segment;
  k.normal.value = cp.gap;
  const LinePairInput in = input(p, s);
  const std::array<double, 2> slips = slip(p, cp, in);
  k.tangent1.value = slips[0];
  k.tangent2.value = slips[1];
  const Vec3d tA = (in.xA2 + in.RA2 * in.oA) - (in.xA1 + in.RA1 * in.oA);
  const Vec3d tB = (in.xB2 + in.RB2 * in.oB) - (in.xB1 + in.RB1 * in.oB);
  k.axesCosine = dot(tA, tB) / (norm(tA) * norm(tB));
  return k;
}

int LineContact::fieldNode(int element, int side) const {
  const BeamElement& e = geometry_.beams().elements()[element];
  const auto& nodes = geometry_.beams().beams()[e.beam].nodes;
  const int last = static_cast<int>(nodes.size()) - 1;
  const bool first = mergedEnds_[e.beam][0], end = mergedEnds_[e.beam][1];
  int i = e.index + side;
  if (last == 1 && first && end) i = 0;  // one element, both ends merged: one field node
  else if (i == 0 && first) i = 1;
  else if (i == last && end) i = last - 1;
  return nodes[i];
}

namespace {
// The part, of m, of an element's field that `xi` lies in (beyond the element: its end part).
int partOf(double xi, int m) { return std::max(0, std::min(m - 1, static_cast<int>(std::floor(xi * m)))); }
}  // namespace

std::vector<LineContact::FieldShare> LineContact::fieldShares(const ContactPointRecord& p, double xi,
                                                              const PointMap& points) const {
  // The part of the (refined) field the point lies in (its Gauss points are its part's: offerSegment
  // cuts the segment at the parts' ends, so p.xi of the last update of the points, the matrix graph's,
  // is inside it), its two nodes' hat functions at `xi` (beyond the part's ends, their lines).
  std::vector<FieldShare> shares;
  const int level = fieldLevel(p.key.pair, p.edge(), p.elementA), m = 1 << level;
  const int part = partOf(p.xi, m);
  // A part that a free end of B cuts (offerSegment): the point at the end on the node beyond it, the
  // piece's Gauss points on the other node (N = 1, no slope).
  const int beyond = p.endCut == 1 ? 0 : 1;
  const int only = !p.endCut ? -1 : endSlot(gaussOf(p.gauss())) ? beyond : 1 - beyond;
  const double t = xi * m - part;
  for (int side = 0; side < 2; ++side) {
    if (only >= 0 && side != only) continue;
    const int node = fieldNodeAt(p.elementA, level, part + side);
    const double N = only >= 0 ? 1.0 : side == 0 ? 1.0 - t : t, slope = only >= 0 ? 0.0 : (side == 0 ? -m : m);
    if (!shares.empty() && shares.back().node == node) {
      shares.back().N += N;
      shares.back().slope += slope;
      continue;
    }
    FieldShare f;
    f.node = node;
    f.N = N;
    f.slope = slope;
    const auto it = points.find(PointKey::lineNode(p.key.pair, p.edge(), node));
    if (it != points.end()) f.record = &it->second;
    shares.push_back(f);
  }
  return shares;
}

std::map<PointKey, LineContact::NodeGap> LineContact::nodeGaps(const PointMap& points, const core::State& s) const {
  std::map<PointKey, NodeGap> gaps;
  for (const auto& [key, p] : points) {
    if (!p.line()) continue;
    double segment = 0.0;
    const LinePairInput in = input(p, s);
    const ClosestPoints cp = geometry(p, in, &segment);
    const double length = weight(p, segment);
    const double w = length * geometry_.blendWeightAt(p, s);
    const double gap = w > 0.0 ? cp.gap : 0.0;
    const std::array<double, 2> slipped = w > 0.0 ? slip(p, cp, in) : std::array<double, 2>{0.0, 0.0};
    for (const FieldShare& f : fieldShares(p, cp.xi, points)) {
      NodeGap& g = gaps[PointKey::lineNode(p.key.pair, p.edge(), f.node)];
      g.weighted += w * f.N * gap;
      g.weightedAcross += w * f.N * slipped[0];
      g.weightedSlip += w * f.N * slipped[1];
      g.weight += w * f.N;
      g.full += length * f.N;
    }
  }
  for (auto& [key, g] : gaps)
    if (g.weight > 0.0) {
      g.weighted /= g.weight;
      g.weightedSlip /= g.weight;
      g.weightedAcross /= g.weight;
    }
  return gaps;
}

ContactPoint LineContact::nodeView(const ContactPointRecord& node, const ContactKinematics& k,
                                   const core::State& s) const {
  ContactPoint view{k, geometry_.pairs()[node.key.pair].friction, geometry_.options().frictionLaw,
                    pointMultipliers(node, s), 1.0};
  view.measured[0] = geometry_.acrossFriction(node.key.pair);
  view.fieldCompliance = fieldCompliance(node.key);
  return view;
}

const ContactPointRecord* LineContact::fieldHost(const ContactPointRecord& p, const PointMap& points) const {
  // The field node with the largest share among those that have multipliers.
  const ContactPointRecord* host = nullptr;
  double best = -1.0;
  for (const FieldShare& f : fieldShares(p, p.xi, points))
    if (f.record && f.record->extraCount > 0 && f.N > best) {
      host = f.record;
      best = f.N;
    }
  return host;
}

const PointState* LineContact::fieldState(const ContactPointRecord& p, const PointMap& points) const {
  const ContactPointRecord* host = fieldHost(p, points);
  return host ? &*host->state : nullptr;
}

bool LineContact::evaluateNodal(const ContactPointRecord& p, const ContactKinematics& k, const core::State& s,
                                const PointMap& points, std::vector<double>& f, std::vector<double>* K,
                                PointResult* result) const {
  // lambda = N_a Lambda_a + N_b Lambda_b; the point's displacement rows see that lambda, and its
  // normal row is mapped on the nodes' with the same N (block = E^T point E with E the interpolation).
  // A node's friction rows (q >= 1) are the point's rows evaluated with that node's own state and
  // multipliers, tested with N_a: a sticking node's weighted slip int N_a g_T ds = 0, a slipping node's
  // int N_a ds (s Lambda_T,a + mu Lambda_N,a) = 0 (the slip rows lumped on the node). Every node's
  // multipliers then lie in the Coulomb cone (a slipping one on it, a sticking one inside by its stick
  // test), and so does every interpolated lambda, a convex combination of them (docs/contact.md, "The
  // Coulomb cone on lines"). The Gauss point xi moves with its segment, so N does too: the tangent also
  // holds the rows E'^T f xi' and the columns (d f / d lambda) (N' Lambda) xi'.
  const ContactPointRecord* hostRecord = fieldHost(p, points);
  const PointState* host = hostRecord ? &*hostRecord->state : nullptr;
  if (!host || !enforcer_.contributes(k.normal.value, *host)) return false;
  const int m = enforcer_.multipliers(*host);
  std::vector<double> lambda(m, 0.0), lambdaSlope(m, 0.0);  // lambda and d lambda / d xi
  std::vector<std::vector<std::pair<int, double>>> to(kPairDofs + m);  // point dof -> (block dof, factor)
  std::vector<std::pair<int, double>> slopes;  // (block row of a node's q = 0, dN / dxi)
  for (int i = 0; i < kPairDofs; ++i) to[i].push_back({i, 1.0});
  int slot = kPairDofs;
  const std::vector<FieldShare> shares = fieldShares(p, k.xi, points);
  for (const FieldShare& n : shares) {
    if (!n.record || n.record->extraCount == 0) continue;
    if (n.record->extraCount != m)
      throw std::logic_error(enforcer_.type() +
                             ": the two line nodes of a Gauss point own different numbers of multipliers");
    const double* values = &s.extra[n.record->extraOffset];
    for (int q = 0; q < m; ++q) {
      lambda[q] += n.N * values[q];
      lambdaSlope[q] += n.slope * values[q];
      to[kPairDofs + q].push_back({slot + q, n.N});
    }
    slopes.push_back({slot, n.slope});
    slot += m;
  }
  const int np = kPairDofs + m, nb = slot;
  std::vector<double> fp(np, 0.0), Kp(K ? std::size_t(np) * np : 0, 0.0);
  ContactPoint view = geometry_.strategyView(p, k, s);
  view.lambda = lambda.data();
  view.fieldCompliance = fieldCompliance(hostRecord->key);
  const PointResult r = enforcer_.evaluate(view, *host, fp.data(), K ? Kp.data() : nullptr);
  if (result) *result = r;
  // (Rows of the interpolated evaluation taken: the displacement rows and the normal row. A penalized
  // field's normal rows are each node's own, as its friction rows are: int N_a (g_N - Lambda_a /
  // eps_N) ds, the springs' compliance lumped on the node, so that Lambda_a = eps_N g_a, g_a the gap
  // weighted over what B covers of the node's elements: a node acts exactly where its weighted gap
  // is closed, and its traction has that gap's sign.)
  const bool lumped = enforcer_.lineFieldPenalized();
  const auto interpolated = [&](int i) { return i < kPairDofs || (i == kPairDofs && !lumped); };
  f.assign(nb, 0.0);
  for (int i = 0; i < np; ++i)
    if (interpolated(i))
      for (const auto& [bi, ci] : to[i]) f[bi] += ci * fp[i];
  if (K) {
    // d lambda / d u = lambdaSlope xi': into the point's displacement columns.
    for (int i = 0; i < np; ++i) {
      double dfdxi = 0.0;
      for (int q = 0; q < m; ++q) dfdxi += Kp[std::size_t(np) * i + kPairDofs + q] * lambdaSlope[q];
      if (dfdxi != 0.0)
        for (int j = 0; j < kPairDofs; ++j) Kp[std::size_t(np) * i + j] += dfdxi * k.xiR[j];
    }
    K->assign(std::size_t(nb) * nb, 0.0);
    for (int i = 0; i < np; ++i) {
      if (!interpolated(i)) continue;
      for (int j = 0; j < np; ++j) {
        const double v = Kp[std::size_t(np) * i + j];
        if (v == 0.0) continue;
        for (const auto& [bi, ci] : to[i])
          for (const auto& [bj, cj] : to[j]) (*K)[std::size_t(nb) * bi + bj] += ci * cj * v;
      }
    }
    // The nodes' normal rows N_a f_lambda: d N_a / d u = slope xi'.
    for (const auto& [row, slope] : slopes)
      if (!lumped)
        for (int j = 0; j < kPairDofs; ++j) (*K)[std::size_t(nb) * row + j] += slope * fp[kPairDofs] * k.xiR[j];
  }
  // Each node's friction rows (and a penalized field's normal row) from its own state and multipliers
  // (lambda = Lambda_a, no slope).
  std::vector<double> fn(np), Kn(K ? std::size_t(np) * np : 0);
  int at = kPairDofs;
  for (const FieldShare& n : shares) {
    if (!n.record || n.record->extraCount == 0) continue;
    std::fill(fn.begin(), fn.end(), 0.0);
    std::fill(Kn.begin(), Kn.end(), 0.0);
    ContactPoint own = view;
    own.lambda = &s.extra[n.record->extraOffset];
    own.fieldCompliance = fieldCompliance(n.record->key);
    enforcer_.evaluate(own, *n.record->state, fn.data(), K ? Kn.data() : nullptr);
    for (int q = lumped ? 0 : 1; q < m; ++q) {
      const int row = kPairDofs + q;
      f[at + q] += n.N * fn[row];
      if (!K) continue;
      for (int j = 0; j < kPairDofs; ++j)
        (*K)[std::size_t(nb) * (at + q) + j] += n.N * Kn[std::size_t(np) * row + j] + n.slope * fn[row] * k.xiR[j];
      for (int c = 0; c < m; ++c)
        (*K)[std::size_t(nb) * (at + q) + at + c] += n.N * Kn[std::size_t(np) * row + kPairDofs + c];
    }
    at += m;
  }
  return true;
}

void LineContact::noteCommitted(const ContactPointRecord& p, const ContactKinematics& k, const core::State& s) {
  if (!p.line() || !p.result.active) return;
  if (frictionAlongOnly(p.key.pair)) frictionless_.insert(p.key.pair);
  if (!nodal_) return;
  // The field enforces gaps weighted over beam A's elements: between its nodes the beams may
  // penetrate. Beyond kUnresolvedLine of the thinner section's inscribed radius the contact zone is
  // not resolved.
  // (Beyond the gap the strategy keeps under the point's traction: a penalty's penetration.)
  const double radius = geometry_.thinner(p.key.pair);
  const double depth = enforcer_.lineFieldGap(p.result.lambdaN) - k.normal.value;
  if (depth > kUnresolvedLine * radius) {
    auto& worst = unresolved_[p.key.pair];
    if (depth > worst.first) {
      const ClosestPoints at = geometry(p, s);
      worst = {depth, geometry_.touching(p, at)};
    }
  }
}

void LineContact::noteRestored(const PointMap& points) {
  for (const auto& [key, p] : points)
    if (p.line() && frictionAlongOnly(p.key.pair)) frictionless_.insert(p.key.pair);
}

bool LineContact::frictionAlongOnly(int pair) const {
  return geometry_.pairs()[pair].friction > 0.0 && !geometry_.acrossFriction(pair);
}

bool LineContact::heldAlong(int n, const Vec3d& normal, double ignored) const {
  const auto& held = geometry_.options().heldNodes;
  const auto it = held.find(n);
  if (it == held.end()) return false;
  for (int c = 0; c < 3; ++c)
    if (!it->second[c] && std::abs(normal[c]) > ignored) return false;
  return true;
}

bool LineContact::heldEnd(const ContactPointRecord& p, int side, const core::State& s, ClosestPoints* at,
                          int* end) const {
  const auto& elems = geometry_.beams().elements();
  const BeamElement &a = elems[p.elementA], &b = elems[p.elementB];
  const int last = static_cast<int>(geometry_.beams().beams()[a.beam].nodes.size()) - 2;  // A's last element
  if ((side == 0 && a.index != 0) || (side == 1 && a.index != last)) return false;
  const int endA = side == 0 ? a.node1 : a.node2;
  // B's node at the same place along the axes (within 1e-3 of A's element).
  const Vec3d t = s.position[a.node2] - s.position[a.node1];
  int endB = -1;
  for (int nb : {b.node1, b.node2})
    if (std::abs(dot(s.position[nb] - s.position[endA], t)) <= 1e-3 * dot(t, t)) endB = nb;
  if (endB < 0) return false;
  const LinePairInput in = input(p, s);
  ClosestPoints cp = lineProjection(in, static_cast<double>(side));
  if (!heldAlong(endA, cp.normal) || !heldAlong(endB, cp.normal)) return false;
  keepSide(in, cp, p.normal);
  if (at) *at = cp;
  if (end) *end = endA;
  return true;
}

void LineContact::checkHeldEnds(const PointMap& points, const core::State& s) {
  // Two beams held by supports at the same place (two rods pinned at the same x) keep their gap
  // there: when they bend, their slope turns the contact normal, and the gap the supports hold
  // becomes -2 r (1 - cos theta), a penetration the contact cannot remove (its first variation in the
  // free motions vanishes: the force there is not determined by the beams). A rigid line constraint
  // (a nodal field: its weighted gaps are zero) closes the gap within the field's first element of
  // length h, which takes tractions of about EI |g| / h^4 (E I the softer beam's): they grow as the
  // elements are refined, and so do the errors of the total force and the reactions. A penalty law
  // takes the same gap with a force eps_N |g|; point and end contact there (rectangles' corners at
  // the held ends) with whatever their constraint needs. Both show as force on A's end element
  // beyond the line's mean traction, which is measured for every strategy.
  const auto& elems = geometry_.beams().elements();
  // The line's mean traction, pair -> (sum |lambda_N|, sum of lengths) of its active Gauss points off
  // A's end elements (where the held ends' forces are), and of all of them (a line of end elements).
  struct Load {
    double inner = 0.0, innerLength = 0.0, all = 0.0, allLength = 0.0;
    double mean() const { return innerLength > 0.0 ? inner / innerLength : (allLength > 0.0 ? all / allLength : 0.0); }
  };
  std::map<int, Load> load;
  for (const auto& [key, p] : points) {
    if (!p.line() || !p.result.active || p.length <= 0.0) continue;
    const BeamElement& a = elems[p.elementA];
    const int last = static_cast<int>(geometry_.beams().beams()[a.beam].nodes.size()) - 2;
    Load& l = load[p.key.pair];
    l.all += std::abs(p.result.lambdaN);
    l.allLength += p.length;
    if (a.index == 0 || a.index == last) continue;
    l.inner += std::abs(p.result.lambdaN);
    l.innerLength += p.length;
  }
  // (The end's gap is the same for every Gauss point of an element pair's line: judged once. A
  // Gauss point whether it acts or not: the held end's force may sit at point or end contact.)
  std::set<std::tuple<int, int, int, int, int>> judged;  // (pair, element A, element B, edge, face)
  for (const auto& [key, p] : points) {
    if (!p.line()) continue;
    if (!judged.insert({p.key.pair, p.elementA, p.elementB, p.edge(), p.face()}).second) continue;
    const BeamElement &a = elems[p.elementA], &b = elems[p.elementB];
    for (int side = 0; side < 2; ++side) {
      ClosestPoints cp;
      int endA = -1;
      if (!heldEnd(p, side, s, &cp, &endA) || !(cp.gap < 0.0)) continue;
      const double EI = std::min({a.data.EIy, a.data.EIz, b.data.EIy, b.data.EIz});
      const double h = a.data.L0;
      const double traction = nodal_ ? EI * std::abs(cp.gap) / (h * h * h * h) : 0.0;
      const auto l = load.find(p.key.pair);
      const double mean = l != load.end() ? l->second.mean() : 0.0;
      // The force of the pair's active points (of every kind) on A's end element, per its length.
      const Vec3d x0 = s.position[endA], inward = s.position[endA == a.node1 ? a.node2 : a.node1] - x0;
      double zone = 0.0;
      for (const auto& [other, q] : points) {
        if (q.key.pair != p.key.pair || q.node() || !q.result.active) continue;
        const double along = dot(q.position - x0, inward) / dot(inward, inward);
        if (along >= -1e-6 && along <= 1.0) zone += std::abs(q.result.lambdaN);
      }
      const double excess = std::max(zone / h - mean, 0.0);
      HeldEnd held{cp.gap, traction, excess, mean, s.position[endA]};
      if (!(held.severity() > 1.0)) continue;
      HeldEnd& worst = heldEnds_[p.key.pair];
      if (held.severity() > worst.severity()) worst = held;
    }
  }
}

void LineContact::checkResolution(const PointMap& points, const core::State& state) {
  checkHeldEnds(points, state);
  // The Gauss points of line contact see the gap only where they are. Where the contact zone of an
  // element pair is shorter than their spacing (axes crossing at a small angle) the beams can overlap
  // between them, unseen. Per element pair (and, for rectangles, edge of A) with line points that
  // carry weight: the gap sampled along A's line (kSamples points, projected on B's) against the
  // deepest Gauss point's.
  constexpr int kSamples = 64;
  // (pair, element A, element B, edge of A, face of B; 0, 0 for circles) -> lowest Gauss gap
  std::map<std::tuple<int, int, int, int, int>, double> deepest;
  for (const auto& [key, p] : points) {
    if (!p.line()) continue;
    if (!(geometry_.blendWeightAt(p, state) > kCarries)) continue;
    const auto k = std::make_tuple(p.key.pair, p.elementA, p.elementB, p.edge(), p.face());
    const double gap = geometry(p, state).gap;
    const auto it = deepest.find(k);
    deepest[k] = it == deepest.end() ? gap : std::min(it->second, gap);
  }
  for (const auto& [k, gauss] : deepest) {
    const auto [pi, ea, eb, edge, face] = k;
    const double radius = geometry_.thinner(pi);
    // Rectangles: along A's edge against B's face, where the edge lies across it.
    const LinePairInput in = segmentInput(pi, ea, eb, edge, face, state);
    const LineSegment seg = lineSegment(in);
    for (int i = 0; i <= kSamples && seg.length() > 0.0; ++i) {
      const ClosestPoints cp = lineProjection(in, seg.lo + seg.length() * i / kSamples);
      if (in.face && std::abs(cp.lateral) > in.halfWidthB) continue;
      const double unseen = std::min(gauss, 0.0) - cp.gap;
      if (!(unseen > kUnresolvedLine * radius)) continue;
      auto& worst = unseenBetween_[pi];
      if (unseen > worst.first) worst = {unseen, geometry_.touching(pi, ea, cp)};
    }
  }
}

}  // namespace bc::constraints
