#include "ContactManager.hpp"

#include <mpi.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <set>
#include <sstream>
#include <stdexcept>
#include <type_traits>
#include <unordered_map>

#include <Teuchos_CommHelpers.hpp>

#include "core/Checkpoint.hpp"
#include "core/Faults.hpp"
#include "core/Parameters.hpp"

namespace bc::constraints {

namespace {
// A point (or line node) whose blend weight (share of its full weight) is at most this is not
// judged after Newton and keeps no multipliers (its rows would carry nothing).
constexpr double kCarries = 1e-3;
// A line point penetrating by more than this fraction of the thinner section's inscribed radius (a
// nodal multiplier field's point, or the gap between Gauss points beyond the deepest one's) is
// reported: the contact zone is not resolved (warnings()).
constexpr double kUnresolved = 1e-3;
// An active point penetrating by more than this fraction of the thinner section's inscribed radius
// is reported: at that depth the sections overlap visibly, and a penalty law is far from contact.
constexpr double kDeep = 0.05;
}  // namespace

using core::GlobalDof;
using elements::BeamElement;
using elements::CrossSection;
using Key = PointKey;

ContactManager::ContactManager(std::shared_ptr<const elements::BeamSet> beams, std::vector<ContactPairSpec> pairs,
                               std::unique_ptr<ConstraintEnforcer> enforcer, ContactOptions options)
    : beams_(std::move(beams)), pairs_(std::move(pairs)), enforcer_(std::move(enforcer)), options_(options) {
  for (std::size_t i = 0; i < pairs_.size(); ++i) pairIndex_[beamPairKey(pairs_[i].beamA, pairs_[i].beamB)] = static_cast<int>(i);
  lineContact_ = enforcer_->lineField() != ConstraintEnforcer::LineField::None && options_.lineAngle > 0.0 &&
                 options_.lineGaussPoints > 0;
  nodalLines_ = lineContact_ && enforcer_->lineField() == ConstraintEnforcer::LineField::Nodal;
  // Gauss-Legendre points on [0, 1]: roots of P_n by Newton's method from the Chebyshev guesses.
  const int n = std::max(options_.lineGaussPoints, 1);
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
  for (const auto& [a, b] : options_.joinedNodes) {
    joined_.insert({a, b});
    joined_.insert({b, a});
  }
  std::map<int, int> uses;  // elements per node (a free end has one, and no pin)
  for (const auto& e : beams_->elements()) {
    ++uses[e.node1];
    ++uses[e.node2];
  }
  for (const auto& [node, n] : uses)
    if (n == 1 && std::none_of(joined_.begin(), joined_.end(), [&](const auto& j) { return j.first == node; }))
      freeEnd_.insert(node);
  for (const auto& b : beams_->beams()) {
    inscribed_.push_back(b.section.shape == CrossSection::Shape::Rectangle
                             ? 0.5 * std::min(b.section.width, b.section.height)
                             : b.section.radius);
    std::vector<Line> lines;
    if (b.section.shape == CrossSection::Shape::Rectangle) {
      const double y = 0.5 * b.section.width, z = 0.5 * b.section.height;
      lines = {{y, z, 0.0}, {-y, z, 0.0}, {-y, -z, 0.0}, {y, -z, 0.0}};
    } else {
      lines = {{0.0, 0.0, b.section.radius}};
    }
    lines_.push_back(lines);
  }
  // Segment planes: at a node between two elements of a beam the mean of their unit axes, at an end
  // the end element's axis.
  const auto& elems = beams_->elements();
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
  for (const auto& p : pairs_) {
    const bool rA = beams_->beams()[p.beamA].section.shape == CrossSection::Shape::Rectangle;
    const bool rB = beams_->beams()[p.beamB].section.shape == CrossSection::Shape::Rectangle;
    if (rA != rB)
      throw core::InputError("contact pair \"" + p.name +
                             "\": contact between a rectangular and a circular section is not supported");
  }
}

double ContactManager::beamCoordinate(int element, double xi) const {
  return beams_->elements()[element].index + xi;
}

bool ContactManager::blends(int pair) const {
  // Both circular, or both rectangular (a mixed pair is refused at construction).
  return lineContact_;
}

std::pair<double, double> ContactManager::blendAngles(int pair) const {
  // Circular sections: the deck's angles. Rectangular ones: their edges' point contact holds down to
  // small angles (crossings at 0.1 .. 12 degrees complete), while the face contact's edges, which see
  // only B's face, miss B's edges on A's face at a crossing (crossings at 4 .. 12 degrees failed at
  // first contact with the deck's angles): line contact only where the edges are parallel within
  // Parallel Line Tolerance, and the blend up to twice that angle.
  if (!rectangles(pair)) return {options_.lineAngle, options_.pointAngle};
  const double parallel = std::asin(std::min(1.0, options_.minimumSinAngle));
  return {parallel, 2.0 * parallel};
}

bool ContactManager::rectangles(int pair) const {
  return beams_->beams()[pairs_[pair].beamA].section.shape == CrossSection::Shape::Rectangle;
}

std::pair<std::array<int, 2>, int> ContactManager::facing(int eA, int eB, const core::State& s) const {
  const BeamElement &a = beams_->elements()[eA], &b = beams_->elements()[eB];
  const Vec3d mA = 0.5 * (s.position[a.node1] + s.position[a.node2]);
  const Vec3d mB = 0.5 * (s.position[b.node1] + s.position[b.node2]);
  const Vec3d tA = s.position[a.node2] - s.position[a.node1];
  Vec3d d = mB - mA;
  d = d - (dot(d, tA) / dot(tA, tA)) * tA;
  // Face f of a section: outward normal +e2, +e3, -e2, -e3 for f = 0..3 (current: R_1 T0).
  const auto best = [&](const BeamElement& e, const Vec3d& towards) {
    int face = 0;
    double most = -1e300;
    for (int f = 0; f < 4; ++f) {
      const Vec3d n = (f < 2 ? 1.0 : -1.0) * (s.rotation[e.node1] * column(e.data.T0, 1 + f % 2));
      if (dot(n, towards) > most) {
        most = dot(n, towards);
        face = f;
      }
    }
    return face;
  };
  const int faceA = best(a, d), faceB = best(b, -1.0 * d);
  // A's edges on its face (lines 0..3 at (+y,+z), (-y,+z), (-y,-z), (+y,-z)).
  static const std::array<int, 2> edgesOf[4] = {{0, 3}, {0, 1}, {1, 2}, {2, 3}};
  return {edgesOf[faceA], faceB};
}

LinePairInput ContactManager::faceInput(int eA, int edgeA, int eB, int faceB, const core::State& s) const {
  LinePairInput in = lineInput(eA, edgeA, eB, 0, s);
  const BeamElement& b = beams_->elements()[eB];
  const auto& sec = beams_->beams()[b.beam].section;
  const Vec3d axis = column(b.data.T0, 1 + faceB % 2);  // e2 or e3
  const double sign = faceB < 2 ? 1.0 : -1.0;
  const double half = 0.5 * (faceB % 2 == 0 ? sec.width : sec.height);   // along the face normal
  const double across = 0.5 * (faceB % 2 == 0 ? sec.height : sec.width);  // the face's half width
  in.oB = (sign * half) * axis;
  in.nB = sign * axis;
  in.halfWidthB = across;
  in.face = true;
  in.radiusSum = 0.0;
  return in;
}

LinePairInput ContactManager::lineContactInput(const Point& p, const core::State& s) const {
  return segmentInput(p.key.pair, p.elementA, p.elementB, p.edge(), p.face(), s);
}

LinePairInput ContactManager::segmentInput(int pair, int eA, int eB, int edge, int face, const core::State& s) const {
  LinePairInput in = rectangles(pair) ? faceInput(eA, edge, eB, face, s) : lineInput(eA, 0, eB, 0, s);
  in.sB1 = segmentPlanes_[eB][0];
  in.sB2 = segmentPlanes_[eB][1];
  return in;
}

LineHistory ContactManager::lineHistory(const Point& p) const {
  const auto& elems = beams_->elements();
  return {p.xiPrev - elems[p.elementA].index, p.etaPrev - elems[p.elementB].index, p.etaRate};
}

double ContactManager::lineSlip(const Point& p, const ClosestPoints& cp, const core::State& s) const {
  const BeamElement& eB = beams_->elements()[p.elementB];
  return (cp.eta - lineHistory(p).etaPrevAt(cp.xi)) * norm(s.position[eB.node2] - s.position[eB.node1]);
}

double ContactManager::axisAngle(int elementA, int elementB, const core::State& s) const {
  const BeamElement &a = beams_->elements()[elementA], &b = beams_->elements()[elementB];
  const Vec3d tA = s.position[a.node2] - s.position[a.node1], tB = s.position[b.node2] - s.position[b.node1];
  return std::acos(std::min(1.0, std::abs(dot(tA, tB)) / (norm(tA) * norm(tB))));
}

bool ContactManager::inLineContact(int pair, int elementA, int elementB) const {
  // Line points exist up to a margin beyond the point-contact angle (their weight is 0 there), so a
  // pair whose angle closes within an increment finds them.
  if (!blends(pair)) return false;
  const auto [lo, hi] = blendAngles(pair);
  return axisAngle(elementA, elementB, reference_) < hi + 0.5 * (hi - lo);
}

bool ContactManager::inPointContact(int pair, int elementA, int elementB) const {
  if (!blends(pair)) return true;
  return axisAngle(elementA, elementB, reference_) > 0.5 * blendAngles(pair).first;
}

double ContactManager::blendWeight(const Point& p, double cosine, const double* cosineR, Vector24* gradient) const {
  // zeta(alpha) = (1 - cos(pi (alpha - alpha_l) / (alpha_p - alpha_l))) / 2 between the two angles,
  // 0 below alpha_l, 1 above alpha_p: C1 in alpha. A point contact carries zeta, a line point 1 - zeta.
  if (gradient) gradient->fill(0.0);
  if (!blends(p.key.pair)) return 1.0;
  const auto [lo, hi] = blendAngles(p.key.pair);
  const double c = std::min(1.0, std::abs(cosine));
  const double alpha = std::acos(c);
  double zeta = 1.0, dzeta = 0.0;  // zeta and d zeta / d alpha
  if (alpha <= lo) {
    zeta = 0.0;
  } else if (alpha < hi) {
    const double k = M_PI / (hi - lo);
    zeta = 0.5 * (1.0 - std::cos(k * (alpha - lo)));
    dzeta = 0.5 * k * std::sin(k * (alpha - lo));
  }
  const double sign = p.line() ? -1.0 : 1.0;
  if (gradient && dzeta != 0.0 && c < 1.0) {
    // d alpha / d cosine = -sign(cosine) / sqrt(1 - cosine^2)
    const double dAlpha = -(cosine >= 0.0 ? 1.0 : -1.0) / std::sqrt(1.0 - c * c);
    for (int i = 0; i < kPairDofs; ++i) (*gradient)[i] = sign * dzeta * dAlpha * cosineR[i];
  }
  return p.line() ? 1.0 - zeta : zeta;
}

double ContactManager::lineWeight(const Point& p, double segment) const {
  return gaussWeight_[p.gauss()] * beams_->elements()[p.elementA].data.L0 * segment;
}

bool ContactManager::withinElement(int element, double xi) const {
  // At a node shared with a neighbour the closest point may fall just outside both elements when
  // the beam is bent there with its convex side towards the other line (the projections onto the
  // two straight elements miss each other). Up to kKinkReach of an element length beyond a shared
  // node is accepted; the candidate most inside its element wins, so no point is counted twice.
  // At the beam's own ends the point must lie on the element.
  constexpr double kExact = 1e-9, kKinkReach = 0.05;
  const BeamElement& e = beams_->elements()[element];
  const int last = static_cast<int>(beams_->beams()[e.beam].nodes.size()) - 2;
  const double below = e.index > 0 ? kKinkReach : kExact;
  const double above = e.index < last ? kKinkReach : kExact;
  return xi >= -below && xi <= 1.0 + above;
}

LinePairInput ContactManager::lineInput(int eA, int lA, int eB, int lB, const core::State& s) const {
  const BeamElement& a = beams_->elements()[eA];
  const BeamElement& b = beams_->elements()[eB];
  const Line& la = lines_[a.beam][lA];
  const Line& lb = lines_[b.beam][lB];
  LinePairInput in;
  in.xA1 = s.position[a.node1]; in.xA2 = s.position[a.node2];
  in.xB1 = s.position[b.node1]; in.xB2 = s.position[b.node2];
  in.RA1 = s.rotation[a.node1]; in.RA2 = s.rotation[a.node2];
  in.RB1 = s.rotation[b.node1]; in.RB2 = s.rotation[b.node2];
  in.oA = la.cy * column(a.data.T0, 1) + la.cz * column(a.data.T0, 2);
  in.oB = lb.cy * column(b.data.T0, 1) + lb.cz * column(b.data.T0, 2);
  in.radiusSum = la.radius + lb.radius;
  in.dA = a.data.L0 * column(a.data.T0, 0);
  in.dB = b.data.L0 * column(b.data.T0, 0);
  return in;
}

namespace {
// Gives closest points the normal orientation `sigma` (n = sigma t_B x t_A / |t_B x t_A|) and the gap
// that goes with it.
void orient(ClosestPoints& cp, double sigma, double radiusSum) {
  if (sigma == cp.sigma) return;
  cp.normal = -1.0 * cp.normal;
  cp.sigma = sigma;
  cp.gap = dot(cp.pB - cp.pA, cp.normal) - radiusSum;
}
// The unit vector t_B x t_A / |t_B x t_A| (the normal before its orientation sigma).
Vec3d lineCross(const ClosestPoints& cp) { return cp.sigma * cp.normal; }
}  // namespace

void ContactManager::forEachElementPair(const core::State& s,
                                        const std::function<void(int, int, int)>& visit) const {
  const auto& elems = beams_->elements();
  std::vector<char> inPairs(beams_->beams().size(), 0);
  for (const auto& p : pairs_) inPairs[p.beamA] = inPairs[p.beamB] = 1;
  // The elements of beams in contact pairs: the only ones boxed, gridded and searched.
  std::vector<int> boxedElements;
  for (std::size_t e = 0; e < elems.size(); ++e)
    if (inPairs[elems[e].beam]) boxedElements.push_back(static_cast<int>(e));
  // Bounding boxes of the elements of beams in contact pairs, swept from the last converged state
  // to `s`: a pair that one increment carries through each other is still a candidate, with no
  // search margin tuned to the increment.
  struct Box { Vec3d lo, hi; };
  std::vector<Box> boxes(elems.size());
  double cell = 0.0;
  for (const int e : boxedElements) {
    const BeamElement& el = elems[e];
    const auto& sec = beams_->beams()[el.beam].section;
    const double reach = (sec.shape == CrossSection::Shape::Rectangle
                              ? 0.5 * std::hypot(sec.width, sec.height)
                              : sec.radius) + options_.searchMargin;
    Box b;
    for (int k = 0; k < 3; ++k) {
      b.lo[k] = std::min({s.position[el.node1][k], s.position[el.node2][k], reference_.position[el.node1][k],
                          reference_.position[el.node2][k]}) - reach;
      b.hi[k] = std::max({s.position[el.node1][k], s.position[el.node2][k], reference_.position[el.node1][k],
                          reference_.position[el.node2][k]}) + reach;
      cell = std::max(cell, b.hi[k] - b.lo[k]);
    }
    boxes[e] = b;
  }
  // Uniform grid of cell size = largest box extent: a box overlaps at most 2 x 2 x 2 cells. Over
  // the boxes' bounding box it is stored densely (each cell's elements one after another) when that
  // takes at most 8 cells per element, else hashed (sparse fibre sets): at 4 x 10^4 contact points of
  // the crossed layers the hashed cells' lookups were the search's own hot spot.
  constexpr double kHuge = std::numeric_limits<double>::max();
  Vec3d lo{{kHuge, kHuge, kHuge}}, hi{{-kHuge, -kHuge, -kHuge}};
  const std::size_t boxed = boxedElements.size();
  bool finite = std::isfinite(cell) && cell > 0.0;
  for (const int e : boxedElements) {
    for (int k = 0; k < 3; ++k) {
      finite = finite && std::isfinite(boxes[e].lo[k]) && std::isfinite(boxes[e].hi[k]);
      lo[k] = std::min(lo[k], boxes[e].lo[k]);
      hi[k] = std::max(hi[k], boxes[e].hi[k]);
    }
  }
  if (boxed == 0) return;
  // (Not finite: a diverged state, its boxes' cells hashed as before and no index out of the grid.)
  long long dims[3] = {1, 1, 1};
  double cells = 1.0;
  for (int k = 0; k < 3 && finite; ++k) {
    dims[k] = static_cast<long long>(std::floor((hi[k] - lo[k]) / cell)) + 1;
    cells *= double(dims[k]);
  }
  const bool dense = finite && cells <= 8.0 * double(boxed) + 64.0;
  if (!finite) lo = Vec3d{};
  auto range = [&](const Box& b, int k) {
    return std::make_pair((long long)std::floor((b.lo[k] - lo[k]) / cell), (long long)std::floor((b.hi[k] - lo[k]) / cell));
  };
  auto cellKey = [&](long long i, long long j, long long k) {
    return dense ? (i * dims[1] + j) * dims[2] + k : (i * 73856093LL) ^ (j * 19349663LL) ^ (k * 83492791LL);
  };
  // Each element's cells, by the callback.
  const auto forEachCell = [&](const Box& b, const auto& fn) {
    const auto [i0, i1] = range(b, 0);
    const auto [j0, j1] = range(b, 1);
    const auto [k0, k1] = range(b, 2);
    for (long long i = i0; i <= i1; ++i)
      for (long long j = j0; j <= j1; ++j)
        for (long long k = k0; k <= k1; ++k) fn(cellKey(i, j, k));
  };
  std::vector<int> cellStart, cellElements;  // dense: cell c's elements at [cellStart[c], cellStart[c + 1])
  std::unordered_map<long long, std::vector<int>> grid;  // hashed
  if (dense) {
    cellStart.assign(static_cast<std::size_t>(cells) + 1, 0);
    for (const int e : boxedElements) forEachCell(boxes[e], [&](long long c) { ++cellStart[c + 1]; });
    for (std::size_t c = 1; c < cellStart.size(); ++c) cellStart[c] += cellStart[c - 1];
    cellElements.resize(cellStart.back());
    std::vector<int> next(cellStart.begin(), cellStart.end() - 1);
    for (const int e : boxedElements) forEachCell(boxes[e], [&](long long c) { cellElements[next[c]++] = e; });
  } else {
    for (const int e : boxedElements) forEachCell(boxes[e], [&](long long c) { grid[c].push_back(e); });
  }
  // Element pairs (pair, element of its beam A, element of its beam B) whose boxes overlap, found
  // from each element's cells (not by looping over every pair and element: with All Pairs of n
  // beams that is n^2 / 2 pairs), then visited pair by pair in element order.
  // A cell lists its elements in increasing order, and a beam's elements are numbered one after
  // another, so the elements of ea's own beam (never in a pair with it) are one run of each cell,
  // skipped by bisection: where elements are short against the sections, a cell holds thousands of
  // one beam's elements, and testing them all made the search quadratic (`check` of Example 1 with
  // 10^4 elements on beam 1: 5.7 s, 88 % of it in these tests; 2 x 10^4: 4 times that).
  const std::size_t numBeams = beams_->beams().size();
  std::vector<int> beamFirst(numBeams, std::numeric_limits<int>::max()), beamLast(numBeams, -1),
      beamCount(numBeams, 0);
  for (const int e : boxedElements) {
    const int b = elems[e].beam;
    beamFirst[b] = std::min(beamFirst[b], e);
    beamLast[b] = std::max(beamLast[b], e);
    ++beamCount[b];
  }
  bool runs = true;
  for (std::size_t b = 0; b < numBeams; ++b) runs = runs && (beamCount[b] == 0 || beamLast[b] - beamFirst[b] + 1 == beamCount[b]);
  std::vector<std::tuple<int, int, int>> found;
  std::vector<int> seenBy(elems.size(), -1);  // seenBy[eb] == ea: (ea, eb) found already
  for (const int ea : boxedElements) {
    const Box& A = boxes[ea];
    const int own = elems[ea].beam;
    const auto visitRun = [&](const int* begin, const int* end) {
      for (const int* it = begin; it != end; ++it) {
        const int eb = *it;
        // The boxes first: most elements of a cell are not in a pair with ea's beam or do not reach
        // ea's box, and the box test costs less than the pair's lookup.
        const Box& B = boxes[eb];
        bool overlap = true;
        for (int c = 0; c < 3; ++c) overlap = overlap && A.lo[c] <= B.hi[c] && B.lo[c] <= A.hi[c];
        if (!overlap) continue;
        if (seenBy[eb] == ea) continue;
        const auto pairIt = pairIndex_.find(beamPairKey(elems[ea].beam, elems[eb].beam));
        if (pairIt == pairIndex_.end()) continue;
        seenBy[eb] = ea;
        // Elements that share a node (beams joined there) or whose nodes are pinned together do
        // not contact each other.
        const BeamElement &A0 = elems[ea], &B0 = elems[eb];
        bool joined = false;
        for (int na : {A0.node1, A0.node2})
          for (int nb : {B0.node1, B0.node2}) joined = joined || na == nb || joined_.count({na, nb});
        if (!joined) found.emplace_back(pairIt->second, ea, eb);
      }
    };
    const auto visitCell = [&](const int* begin, const int* end) {
      if (!runs) return visitRun(begin, end);
      const int* from = std::lower_bound(begin, end, beamFirst[own]);
      const int* to = std::upper_bound(from, end, beamLast[own]);
      visitRun(begin, from);
      visitRun(to, end);
    };
    forEachCell(A, [&](long long c) {
      if (dense) {
        visitCell(cellElements.data() + cellStart[c], cellElements.data() + cellStart[c + 1]);
      } else {
        const auto it = grid.find(c);
        if (it != grid.end()) visitCell(it->second.data(), it->second.data() + it->second.size());
      }
    });
  }
  std::stable_sort(found.begin(), found.end(),
                   [](const auto& a, const auto& b) { return std::get<0>(a) < std::get<0>(b); });
  for (const auto& [pi, ea, eb] : found) visit(pi, ea, eb);
}

std::vector<std::tuple<int, int, int>> ContactManager::candidates(const core::State& s) const {
  std::vector<std::tuple<int, int, int>> found;
  forEachElementPair(s, [&](int pi, int ea, int eb) { found.emplace_back(pi, ea, eb); });
  std::sort(found.begin(), found.end());
  return found;
}

bool ContactManager::nearElement(int element, double xi) const {
  // Within one element length of the element and not beyond its beam's ends.
  const BeamElement& e = beams_->elements()[element];
  const int count = static_cast<int>(beams_->beams()[e.beam].nodes.size()) - 1;
  const double b = e.index + xi;
  return xi >= -1.0 && xi <= 2.0 && b >= -1e-9 && b <= count + 1e-9;
}

double ContactManager::referenceSigma(int eA, int lA, int eB, int lB, const ClosestPoints& cp) const {
  // The orientation of a newly found point: in the last converged state (no interpenetration there)
  // the normal points from beam A to beam B; carried to the current lines by continuity of their
  // cross product. Without it a beam carried through the other within one increment would be
  // found on the far side and pushed on through. Where the lines did not overlap in the last
  // converged state (closest points beyond the elements), the current side is taken.
  const ClosestPoints ref = closestPoints(lineInput(eA, lA, eB, lB, reference_));
  if (ref.sinAngle < options_.minimumSinAngle || !nearElement(eA, ref.xi) || !nearElement(eB, ref.eta))
    return cp.sigma;
  return dot(lineCross(ref), lineCross(cp)) >= 0.0 ? ref.sigma : -ref.sigma;
}

std::map<Key, ContactManager::Candidate> ContactManager::detect(const core::State& s) const {
  std::vector<std::tuple<int, int, int>> visits;
  forEachElementPair(s, [&](int pi, int ea, int eb) { visits.emplace_back(pi, ea, eb); });
  // A key's candidate is the one offered with the lowest (outside, visit): for a point contact the
  // candidate most central in its elements, the first visited of equals; for a line Gauss point the
  // last visited (offered with outside 0 and -visit). The choice does not depend on which rank
  // evaluated which visit, so the ranks' shares merge into the whole search's result.
  struct Offer {
    Candidate candidate;
    double outside;
    long long visit;
  };
  std::map<Key, Offer> chosen;
  const auto offer = [&chosen](const Key& key, const Candidate& c, double outside, long long visit) {
    const auto it = chosen.find(key);
    if (it == chosen.end())
      chosen.emplace(key, Offer{c, outside, visit});
    else if (outside < it->second.outside || (!(it->second.outside < outside) && visit < it->second.visit))
      it->second = Offer{c, outside, visit};
  };
  const int ranks = comm_.is_null() ? 1 : comm_->getSize(), me = comm_.is_null() ? 0 : comm_->getRank();
  const std::size_t first = visits.size() * me / ranks, last = visits.size() * (me + 1) / ranks;
  const auto share = [&] {
    for (std::size_t v = first; v < last; ++v) {
      const auto& [pi, ea, eb] = visits[v];
      narrowPhase(pi, ea, eb, static_cast<long long>(v), s, offer);
    }
  };
  if (ranks == 1) {
    share();
  } else {
    // A failure in one rank's share is thrown on every rank (the first failing rank's error).
    core::collectively(*comm_, share);
    const MPI_Comm raw = core::rawMpiComm(*comm_);
    // Every rank's choices to every rank, merged by the same rule.
    struct Record {
      Key key;
      int elementA, elementB;
      double outside;
      long long visit;
      ClosestPoints cp;
    };
    static_assert(std::is_trivially_copyable_v<Record>, "records travel as bytes");
    std::vector<Record> mine;
    mine.reserve(chosen.size());
    for (const auto& [key, o] : chosen)
      mine.push_back(Record{key, o.candidate.elementA,
                            o.candidate.elementB, o.outside, o.visit, o.candidate.cp});
    // The byte counts as 64-bit integers, so that every rank takes the same decision on their total.
    const long long bytes = static_cast<long long>(mine.size() * sizeof(Record));
    std::vector<long long> sizes(ranks);
    MPI_Allgather(&bytes, 1, MPI_LONG_LONG, sizes.data(), 1, MPI_LONG_LONG, raw);
    std::vector<int> counts(ranks), offsets(ranks);
    long long total = 0;
    for (int r = 0; r < ranks; ++r) total += sizes[r];
    if (total > std::numeric_limits<int>::max())
      throw std::runtime_error("contact search: the candidates (" + std::to_string(total) +
                               " bytes) exceed what one exchange between the ranks carries (2 GB)");
    for (int r = 0, at = 0; r < ranks; ++r) offsets[r] = at, counts[r] = static_cast<int>(sizes[r]), at += counts[r];
    std::vector<Record> all(static_cast<std::size_t>(total) / sizeof(Record));
    MPI_Allgatherv(mine.data(), static_cast<int>(bytes), MPI_BYTE, all.data(), counts.data(), offsets.data(),
                   MPI_BYTE, raw);
    chosen.clear();
    for (const Record& r : all)
      offer(r.key, Candidate{r.elementA, r.elementB, r.cp}, r.outside, r.visit);
  }
  std::map<Key, Candidate> found;
  for (auto& [key, o] : chosen) found.emplace_hint(found.end(), key, std::move(o.candidate));
  return found;
}

void ContactManager::narrowPhase(int pi, int ea, int eb, long long visit, const core::State& s,
                                 const std::function<void(const Key&, const Candidate&, double, long long)>& offer)
    const {
  const auto& pair = pairs_[pi];
  if (inLineContact(pi, ea, eb)) {
    // The Gauss points of the segment of A's element that lies between the planes of B's element's
    // nodes (segments of neighbouring elements of B share their plane, so they tile A's line and
    // no Gauss point straddles a node of B or lies beyond B's end).
    // Rectangular sections: on each of A's two edges facing B, against B's face facing A, where
    // the edge lies across that face.
    std::vector<std::pair<int, int>> lines = {{0, 0}};  // (edge of A, face of B)
    if (rectangles(pi)) {
      const auto [edges, face] = facing(ea, eb, reference_);
      lines = {{edges[0], face}, {edges[1], face}};
    }
    for (const auto& [edge, face] : lines) {
      const LinePairInput in = segmentInput(pi, ea, eb, edge, face, s);
      // (A sliver of a segment, where A's element ends at B's node within round-off, carries nothing.)
      constexpr double kSliver = 1e-9;
      const LineSegment seg = lineSegment(in);
      if (!(seg.length() > kSliver)) continue;
      // The planes partition A's line where its points project onto B about along B's axis (nearly
      // parallel lines close together). Where the segment's points project far beyond B's element
      // instead (lines further apart than their elements are long, at an angle: neighbouring wires
      // of a strand, element pairs several elements apart), the pair is not in line contact.
      const double mid = lineProjection(in, seg.lo + 0.5 * seg.length()).eta;
      if (!(mid > -0.5 && mid < 1.5)) continue;
      for (int q = 0; q < (int)gaussXi_.size(); ++q) {
        const ClosestPoints cp = lineProjection(in, seg.lo + seg.length() * gaussXi_[q]);
        const Key key = Key::gaussPoint(pi, ea, eb, edge, face, q);
        // Across B's face: a new point within 1e-3 of its width beyond the face's edge, a known one
        // while within 5 % (equal widths put A's edges exactly on B's face edges, where a sharp
        // bound would drop and take up points from one iterate to the next).
        if (in.face && std::abs(cp.lateral) > in.halfWidthB * (points_.count(key) ? 1.05 : 1.001)) continue;
        offer(key, Candidate{ea, eb, cp}, 0.0, -visit);  // the last visit wins
      }
    }
  }
  if (!inPointContact(pi, ea, eb)) return;
  for (int la = 0; la < (int)lines_[pair.beamA].size(); ++la)
    for (int lb = 0; lb < (int)lines_[pair.beamB].size(); ++lb) {
      const LinePairInput in = lineInput(ea, la, eb, lb, s);
      ClosestPoints cp = closestPoints(in);
      if (cp.sinAngle < options_.minimumSinAngle) continue;
      if (!withinElement(ea, cp.xi) || !withinElement(eb, cp.eta)) continue;
      const Key key = Key::contact(pi, la, lb);
      // The normal's orientation: carried by a known point, else from the last converged state.
      const auto known = points_.find(key);
      orient(cp, known != points_.end() ? known->second.sigma : referenceSigma(ea, la, eb, lb, cp),
             in.radiusSum);
      // Only lines on the sides facing each other.
      if (dot(cp.pA - cp.cA, cp.normal) < -1e-12 || dot(cp.pB - cp.cB, cp.normal) > 1e-12) continue;
      if (in.radiusSum == 0.0 && (dot(cp.pA - cp.cA, cp.normal) <= 0 || dot(cp.pB - cp.cB, cp.normal) >= 0))
        continue;
      // A known point stays on its element pair while its closest points lie within the
      // elements or up to kStay of an element length beyond a shared node; it is handed to a
      // neighbour only beyond that, so a point at a node cannot flip between elements from one
      // iteration to the next. Otherwise the candidate most central in its elements wins.
      constexpr double kStay = 0.05;
      double out = std::max(std::abs(cp.xi - 0.5), std::abs(cp.eta - 0.5));
      if (known != points_.end() && known->second.elementA == ea && known->second.elementB == eb &&
          out <= 0.5 + kStay)
        out = -1.0;
      offer(key, Candidate{ea, eb, cp}, out, visit);
    }
}

void ContactManager::initialize(core::State& state) {
  numNodes_ = state.numNodes();
  reference_ = state;
  const auto cands = detect(state);
  points_.clear();
  for (const auto& [key, c] : cands) {
    if (c.cp.gap < -1e-9 * std::max(1.0, c.cp.distance) && !options_.allowInitialPenetration) {
      const auto& pair = pairs_[key.pair];
      std::ostringstream s;
      s << "beams \"" << beams_->beams()[pair.beamA].name << "\" and \"" << beams_->beams()[pair.beamB].name
        << "\" overlap at the start: gap " << c.cp.gap << " at (" << c.cp.pA[0] << ", " << c.cp.pA[1] << ", "
        << c.cp.pA[2] << "); move them apart or set \"Contact/Allow Initial Penetration\" to true";
      throw core::InputError(s.str());
    }
  }
  checkNoUnseenContact(state, true);
  prepareIteration(state);
  committed_ = points_;
}

bool ContactManager::prepareIteration(core::State& state) {
  const auto cands = detect(state);
  std::map<Key, Point> next;
  bool changed = false;
  // Line points of the last converged state by (pair, element of A, edge, face): the donors of the
  // history of new line points.
  std::map<std::tuple<int, int, int, int>, std::vector<const Point*>> donors;
  bool donorsFound = false;
  for (const auto& [key, c] : cands) {
    auto it = points_.find(key);
    Point p;
    if (it != points_.end()) {
      p = it->second;
      changed = changed || p.elementA != c.elementA || p.elementB != c.elementB;
    } else {
      changed = true;
      p.key = key;
      p.state = PointStateHolder(enforcer_->newPointState());
      p.sigma = c.cp.sigma;
      p.xiPrev = beamCoordinate(c.elementA, c.cp.xi);
      p.etaPrev = beamCoordinate(c.elementB, c.cp.eta);
      p.etaRate = c.cp.etaRate;
      if (p.line()) {
        // A new Gauss point of a segment (its segment appeared, or moved so that the point left its
        // neighbour's): its material point of A had its history at the nearest line point of the
        // same element and line of A at the last converged state. It takes that point's strategy
        // state and normal, and its projection then, extrapolated along B by the donor's d eta / d xi.
        if (!donorsFound) {
          for (const auto& [k, d] : committed_)
            if (d.line()) donors[{d.key.pair, d.key.elementA, d.edge(), d.face()}].push_back(&d);
          donorsFound = true;
        }
        const auto list = donors.find({p.key.pair, p.key.elementA, p.edge(), p.face()});
        const Point* donor = nullptr;
        if (list != donors.end())
          for (const Point* d : list->second)
            if (!donor || std::abs(d->xiPrev - p.xiPrev) < std::abs(donor->xiPrev - p.xiPrev)) donor = d;
        if (donor) {
          p.state = donor->state;
          std::copy(donor->compliance, donor->compliance + 3, p.compliance);
          p.normal = donor->normal;
          p.etaRate = donor->etaRate;
          p.etaPrev = LineHistory{donor->xiPrev, donor->etaPrev, donor->etaRate}.etaPrevAt(p.xiPrev);
        }
      }
    }
    p.elementA = c.elementA;
    p.elementB = c.elementB;
    p.xi = c.cp.xi;
    // A new line point's side: its normal at the last converged state (where the beams had not
    // passed through each other), so a point found after they did has a deeply negative gap.
    if (p.line() && dot(p.normal, p.normal) == 0.0) p.normal = pointGeometry(p, reference_).normal;
    next[key] = p;
  }
  if (nodalLines_) {
    // The line nodes of the Gauss points (kept with their state, or new).
    for (const auto& [key, p] : next)
      if (p.line())
        for (int n : {fieldNode(p.elementA, 0), fieldNode(p.elementA, 1)})
          if (!next.count(Key::lineNode(p.key.pair, p.edge(), n))) {
            const Key nk = Key::lineNode(p.key.pair, p.edge(), n);
            const auto it = points_.find(nk);
            Point q;
            if (it != points_.end()) {
              q = it->second;
            } else {
              changed = true;
              q.key = nk;
              q.elementA = q.elementB = p.elementA;
              q.state = PointStateHolder(enforcer_->newPointState());
            }
            next[nk] = q;
          }
  }
  changed = changed || next.size() != points_.size();
  points_ = std::move(next);
  // Multipliers whose rows carry nothing now have nothing to determine them: a line node whose Gauss
  // points left the other beam or carry no weight, a point contact whose blend weight is 0. They are
  // given up here (the state starts afresh); those that carry almost nothing are given up between
  // passes (acceptSolution), at the state the active set is judged at.
  const auto gaps = nodalLines_ ? nodeGaps(state) : std::map<Key, NodeGap>{};
  for (auto& [key, p] : points_) {
    if (p.line() || enforcer_->multipliers(*p.state) == 0) continue;
    bool idle = false;
    if (p.node()) {
      const auto g = gaps.find(key);
      idle = g == gaps.end() || !(g->second.weight > 0.0);
    } else if (blends(p.key.pair)) {
      idle = !(blendWeight(p, std::cos(axisAngle(p.elementA, p.elementB, state)), nullptr, nullptr) > 0.0);
    }
    if (idle) p.state = PointStateHolder(enforcer_->newPointState());
  }
  giveCompliance(state);
  return layoutMultipliers(state) || changed;
}

void ContactManager::giveCompliance(const core::State& state) {
  if (!compliance_) return;
  std::vector<Point*> waiting;
  std::vector<core::SparseLoad> loads;
  std::vector<double> weights;
  for (auto& [key, p] : points_) {
    if (p.node() || !enforcer_->wantsCompliance(*p.state)) continue;
    const ContactKinematics k = kinematics(p, state, Variations::First);
    const auto d = pointDofs(p);
    for (const GapDerivatives* g : {&k.normal, &k.tangent1, &k.tangent2})
      loads.push_back({std::vector<GlobalDof>(d.begin(), d.end()), std::vector<double>(g->R.begin(), g->R.end())});
    // The manager weights a line point's force by the length it stands for (a whole segment's share here).
    weights.push_back(p.line() ? lineWeight(p, 1.0) : 1.0);
    waiting.push_back(&p);
  }
  if (waiting.empty()) return;
  std::vector<double> c;
  try {
    c = compliance_(reference_, loads);
  } catch (const std::runtime_error& e) {
    throw core::InputError(enforcer_->type() + ": automatic penalty parameters need the beams' compliance at the "
                           "contact points, but " + e.what() + "; give the penalty parameters as numbers");
  }
  for (std::size_t i = 0; i < waiting.size(); ++i) {
    for (int k = 0; k < 3; ++k) waiting[i]->compliance[k] = weights[i] * c[3 * i + k];
    handCompliance(*waiting[i]);
  }
}

void ContactManager::handCompliance(Point& p) const {
  const double c[3] = {p.compliance[0], tangentialRelaxation_ * p.compliance[1],
                       tangentialRelaxation_ * p.compliance[2]};
  enforcer_->setCompliance(*p.state, c);
}

namespace {
core::ExtraUnknowns::Key extraKey(const ContactManager::Point& p) {
  const auto c = p.key.code();
  return {c.begin(), c.end()};
}
}  // namespace

bool ContactManager::layoutMultipliers(core::State& state) {
  std::map<core::ExtraUnknowns::Key, int> wanted;
  for (const auto& [key, p] : points_)
    wanted[extraKey(p)] = nodalLines_ && p.line() ? 0 : enforcer_->multipliers(*p.state);
  const bool changed = state.extra.request(kExtraOwner, wanted);
  for (auto& [key, p] : points_) {
    const auto* block = state.extra.find(kExtraOwner, extraKey(p));
    p.extraOffset = block ? block->offset : -1;
    p.extraCount = block ? block->size : 0;
  }
  return changed;
}

const double* ContactManager::multipliers(const Point& p, const core::State& state, int* count) const {
  const auto* block = state.extra.find(kExtraOwner, extraKey(p));
  if (count) *count = block ? block->size : 0;
  return block ? &state.extra[block->offset] : nullptr;
}

ContactPoint ContactManager::strategyView(const Point& p, const ContactKinematics& k, const core::State& state) const {
  // Line points have friction along the axes (their g_T2); across the axes no slip is measured.
  ContactPoint view{k, pairs_[p.key.pair].friction, options_.frictionLaw, multipliers(p, state),
                    blendWeight(p, k.axesCosine, nullptr, nullptr)};
  if (p.line()) view.measured[0] = false;
  return view;
}

std::vector<GlobalDof> ContactManager::blockDofs(const Point& p) const {
  const auto d = pointDofs(p);
  std::vector<GlobalDof> dofs(d.begin(), d.end());
  for (int j = 0; j < p.extraCount; ++j) dofs.push_back(GlobalDof(core::kDofsPerNode) * numNodes_ + p.extraOffset + j);
  if (nodalLines_ && p.line())
    for (const FieldShare& n : fieldShares(p, p.xi))
      if (n.record)
        for (int j = 0; j < n.record->extraCount; ++j)
          dofs.push_back(GlobalDof(core::kDofsPerNode) * numNodes_ + n.record->extraOffset + j);
  return dofs;
}

int ContactManager::fieldNode(int element, int side) const {
  const BeamElement& e = beams_->elements()[element];
  const auto& nodes = beams_->beams()[e.beam].nodes;
  const int last = static_cast<int>(nodes.size()) - 1;
  int i = e.index + side;
  if (last == 1) i = 0;  // one element: one field node
  else if (i == 0) i = 1;
  else if (i == last) i = last - 1;
  return nodes[i];
}

std::vector<ContactManager::FieldShare> ContactManager::fieldShares(const Point& p, double xi) const {
  std::vector<FieldShare> shares;
  for (int side = 0; side < 2; ++side) {
    const int node = fieldNode(p.elementA, side);
    const double N = side == 0 ? 1.0 - xi : xi, slope = side == 0 ? -1.0 : 1.0;
    if (!shares.empty() && shares.back().node == node) {
      shares.back().N += N;
      shares.back().slope += slope;
      continue;
    }
    FieldShare f;
    f.node = node;
    f.N = N;
    f.slope = slope;
    const auto it = points_.find(Key::lineNode(p.key.pair, p.edge(), node));
    if (it != points_.end()) f.record = &it->second;
    shares.push_back(f);
  }
  return shares;
}

std::map<Key, ContactManager::NodeGap> ContactManager::nodeGaps(const core::State& s) const {
  std::map<Key, NodeGap> gaps;
  for (const auto& [key, p] : points_) {
    if (!p.line()) continue;
    double segment = 0.0;
    const ClosestPoints cp = pointGeometry(p, s, &segment);
    const double length = lineWeight(p, segment);
    const double w = length * blendWeight(p, std::cos(axisAngle(p.elementA, p.elementB, s)), nullptr, nullptr);
    const double gap = w > 0.0 ? cp.gap : 0.0;
    const double slip = w > 0.0 ? lineSlip(p, cp, s) : 0.0;
    for (const FieldShare& f : fieldShares(p, cp.xi)) {
      NodeGap& g = gaps[Key::lineNode(p.key.pair, p.edge(), f.node)];
      g.weighted += w * f.N * gap;
      g.weightedSlip += w * f.N * slip;
      g.weight += w * f.N;
      g.full += length * f.N;
    }
  }
  for (auto& [key, g] : gaps)
    if (g.weight > 0.0) {
      g.weighted /= g.weight;
      g.weightedSlip /= g.weight;
    }
  return gaps;
}

ContactPoint ContactManager::nodeView(const Point& node, const ContactKinematics& k, const core::State& s) const {
  ContactPoint view{k, pairs_[node.key.pair].friction, options_.frictionLaw, multipliers(node, s), 1.0};
  view.measured[0] = false;  // as its Gauss points: slip along the axes only
  return view;
}

const PointState* ContactManager::actingState(const Point& p) const {
  if (!(nodalLines_ && p.line())) return &*p.state;
  // The field node with the largest share among those that have multipliers.
  const Point* host = nullptr;
  double best = -1.0;
  for (const FieldShare& f : fieldShares(p, p.xi))
    if (f.record && f.record->extraCount > 0 && f.N > best) {
      host = f.record;
      best = f.N;
    }
  return host ? &*host->state : nullptr;
}

bool ContactManager::evaluateNodal(const Point& p, const ContactKinematics& k, const core::State& s,
                                   std::vector<double>& f, std::vector<double>* K, PointResult* result) const {
  // lambda = N_a Lambda_a + N_b Lambda_b; the point's multiplier rows and columns are mapped on the
  // nodes' with the same N (block = E^T point E with E the interpolation). The Gauss point xi moves
  // with its segment, so N does too: the tangent also holds the rows E'^T f xi' and the columns
  // (d f / d lambda) (N' Lambda) xi'.
  const PointState* host = actingState(p);
  if (!host || !enforcer_->contributes(k.normal.value, *host)) return false;
  const int m = enforcer_->multipliers(*host);
  std::vector<double> lambda(m, 0.0), lambdaSlope(m, 0.0);  // lambda and d lambda / d xi
  std::vector<std::vector<std::pair<int, double>>> to(kPairDofs + m);  // point dof -> (block dof, factor)
  std::vector<std::pair<int, double>> slopes;                          // (block row of a node's q = 0, dN / dxi)
  for (int i = 0; i < kPairDofs; ++i) to[i].push_back({i, 1.0});
  int slot = kPairDofs;
  for (const FieldShare& n : fieldShares(p, k.xi)) {
    if (!n.record || n.record->extraCount == 0) continue;
    if (n.record->extraCount != m)
      throw std::logic_error(enforcer_->type() + ": the two line nodes of a Gauss point own different numbers of multipliers");
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
  ContactPoint view = strategyView(p, k, s);
  view.lambda = lambda.data();
  const PointResult r = enforcer_->evaluate(view, *host, fp.data(), K ? Kp.data() : nullptr);
  if (result) *result = r;
  f.assign(nb, 0.0);
  for (int i = 0; i < np; ++i)
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
    for (int i = 0; i < np; ++i)
      for (int j = 0; j < np; ++j) {
        const double v = Kp[std::size_t(np) * i + j];
        if (v == 0.0) continue;
        for (const auto& [bi, ci] : to[i])
          for (const auto& [bj, cj] : to[j]) (*K)[std::size_t(nb) * bi + bj] += ci * cj * v;
      }
    // The nodes' rows N_a f_lambda: d N_a / d u = slope xi'.
    for (const auto& [row, slope] : slopes)
      for (int q = 0; q < m; ++q)
        for (int j = 0; j < kPairDofs; ++j)
          (*K)[std::size_t(nb) * (row + q) + j] += slope * fp[kPairDofs + q] * k.xiR[j];
  }
  return true;
}

std::array<GlobalDof, kPairDofs> ContactManager::pointDofs(const Point& p) const {
  const auto& a = beams_->elements()[p.elementA];
  const auto& b = beams_->elements()[p.elementB];
  const int nodes[4] = {a.node1, a.node2, b.node1, b.node2};
  std::array<GlobalDof, kPairDofs> d;
  for (int n = 0; n < 4; ++n)
    for (int k = 0; k < 6; ++k) d[6 * n + k] = GlobalDof(core::kDofsPerNode) * nodes[n] + k;
  return d;
}

ContactKinematics ContactManager::kinematics(const Point& p, const core::State& state, Variations order) const {
  if (p.line()) {
    const LinePairInput in = lineContactInput(p, state);
    return segmentKinematics(in, lineSegment(in), gaussXi_[p.gauss()], lineHistory(p), p.normal, order);
  }
  const LinePairInput in = lineInput(p.elementA, p.key.lineA, p.elementB, p.key.lineB, state);
  const double xiPrev = p.xiPrev - beams_->elements()[p.elementA].index;
  const double etaPrev = p.etaPrev - beams_->elements()[p.elementB].index;
  return contactKinematics(in, p.sigma, xiPrev, etaPrev, order);
}

ContactKinematics ContactManager::judgedKinematics(const Point& p, const core::State& state) const {
  if (!p.line()) return kinematics(p, state, Variations::First);
  double segment = 0.0;
  const ClosestPoints cp = pointGeometry(p, state, &segment);
  const PointState* acting = actingState(p);
  if (acting && enforcer_->contributes(cp.gap, *acting)) return kinematics(p, state, Variations::First);
  // The values segmentKinematics would give, without their variations.
  ContactKinematics k;
  k.xi = cp.xi;
  k.eta = cp.eta;
  k.segment = segment;
  k.normal.value = cp.gap;
  k.tangent2.value = lineSlip(p, cp, state);
  const LinePairInput in = lineContactInput(p, state);
  const Vec3d tA = (in.xA2 + in.RA2 * in.oA) - (in.xA1 + in.RA1 * in.oA);
  const Vec3d tB = (in.xB2 + in.RB2 * in.oB) - (in.xB1 + in.RB1 * in.oB);
  k.axesCosine = dot(tA, tB) / (norm(tA) * norm(tB));
  return k;
}

bool ContactManager::evaluatesHere(const Point& p, const std::vector<GlobalDof>& dofs, const OwnsDof& owns) {
  // The rank of element A's first node or of element B's, alternating with the element pair: where
  // the two beams of a crossing lie on different ranks (layers, yarns), each rank takes about half
  // of the points. The choice depends only on the pair of elements, so a point keeps its rank (and
  // its rows in that rank's overlap of the matrix graph) while it lives.
  const unsigned mix = 2654435761u * static_cast<unsigned>(p.elementA) ^ static_cast<unsigned>(p.elementB);
  return owns(dofs[(mix >> 7) & 1u ? 12 : 0]);
}

void ContactManager::connectivity(const OwnsDof& owns, std::vector<std::vector<GlobalDof>>& blocks) const {
  for (const auto& [key, p] : points_) {
    const auto d = blockDofs(p);
    if (evaluatesHere(p, d, owns)) blocks.push_back(d);
  }
}

void ContactManager::evaluate(const core::State& state, const OwnsDof& owns, core::AssemblySink& sink,
                              bool tangent) const {
  std::vector<double> f, K;
  // Compares a slipping point's friction force with the last tangent assembly's (failureHint).
  const auto watchFriction = [&](const Key& key, const PointResult& r) {
    if (!tangent || !r.active || !(r.slip[0] || r.slip[1])) return;
    FrictionWatch& w = frictionWatch_[key];
    if (w.force[0] * r.lambdaT[0] + w.force[1] * r.lambdaT[1] < 0.0) ++w.reversals;
    w.force = {r.lambdaT[0], r.lambdaT[1]};
  };
  for (const auto& [key, p] : points_) {
    if (p.node()) continue;  // a line node's rows come from its Gauss points
    const auto d = blockDofs(p);
    if (!evaluatesHere(p, d, owns)) continue;
    // The full kinematics (with their derivatives) only where the point acts.
    const PointState* acting = actingState(p);
    if (!acting || !enforcer_->contributes(pointGeometry(p, state).gap, *acting)) continue;
    // A point of a blended pair whose weight is zero now carries nothing (the angle, cheap, first).
    if (blends(p.key.pair) &&
        blendWeight(p, std::cos(axisAngle(p.elementA, p.elementB, state)), nullptr, nullptr) == 0.0)
      continue;
    const ContactKinematics k = kinematics(p, state);
    const int n = static_cast<int>(d.size());
    if (nodalLines_ && p.line()) {
      if (!evaluateNodal(p, k, state, f, tangent ? &K : nullptr, nullptr)) continue;
    } else {
      f.assign(n, 0.0);
      K.assign(std::size_t(n) * n, 0.0);
      watchFriction(key, enforcer_->evaluate(strategyView(p, k, state), *p.state, f.data(), tangent ? K.data() : nullptr));
    }
    // Weighted by the blend between point and line contact (w(u), its gradient in the tangent:
    // K <- w K + f (x) grad w) and, for a line point, by the length it stands for (which moves with
    // its segment's bounds).
    Vector24 gradient;
    double w = blendWeight(p, k.axesCosine, k.axesCosineR.data(), &gradient);
    if (p.line()) {
      const double length = lineWeight(p, k.segment), perSegment = lineWeight(p, 1.0);
      for (int i = 0; i < kPairDofs; ++i) gradient[i] = gradient[i] * length + w * perSegment * k.segmentR[i];
      w *= length;
    }
    if (tangent)
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
          K[std::size_t(n) * i + j] = w * K[std::size_t(n) * i + j] + (j < kPairDofs ? f[i] * gradient[j] : 0.0);
    for (double& v : f) v *= w;
    sink.add(d.data(), n, f.data(), tangent ? K.data() : nullptr);
  }
}



namespace {
constexpr int kCyclingReversals = 3;  // reversals of a point's friction force within a Newton solve
}  // namespace

std::string ContactManager::failureHint(const Teuchos::Comm<int>& comm) const {
  // Slip directions that flip back and forth at many points: the friction force's jump across zero
  // slip is steeper than the beams can follow, and Newton cycles between mirror images.
  int local[2] = {static_cast<int>(frictionWatch_.size()), 0}, global[2] = {0, 0};
  for (const auto& [key, w] : frictionWatch_) local[1] += w.reversals >= kCyclingReversals;
  Teuchos::reduceAll(comm, Teuchos::REDUCE_SUM, 2, local, global);
  if (global[1] < 2 || global[1] < global[0] / 4) return "";
  std::ostringstream s;
  s << global[1] << " of " << global[0] << " slipping contact points reversed their friction force "
    << kCyclingReversals << " times or more in this Newton solve (slip directions cycling): the strategy's "
    << "tangential stiffness (Tangential Penalty Parameter, or Friction Complementarity Parameter with Lagrange "
       "multipliers) may be too stiff for these beams; a smaller value helps";
  // Points with parameters chosen from the compliance: restoreStep lowers them for the retry.
  const bool automatic =
      std::any_of(points_.begin(), points_.end(), [](const auto& kv) { return kv.second.compliance[0] > 0.0; });
  if (automatic && relaxations_ < kMaxRelaxations) {
    cycling_ = true;
    s << "; the automatic Tangential Penalty Parameters are lowered tenfold for the retry";
  }
  return s.str();
}

void ContactManager::checkNoUnseenContact(const core::State& state, bool atStart) const {
  // Contacts the point model cannot see: two beams whose axes come closer than the sum of their
  // sections' inscribed radii (so they surely overlap) where no contact point can exist:
  //  - at a free beam end (the closest points of the two lines lie beyond it, so no element pair
  //    has them inside both elements): an end pressed into the side of another beam;
  //  - nearly parallel (sine of the angle below "Parallel Line Tolerance"): point contact is
  //    undefined there.
  // A state with such an overlap is not a solution: the increment fails (a run cannot complete with
  // it), and at the start the deck is refused.
  const auto& elems = beams_->elements();
  forEachElementPair(state, [&](int pi, int ea, int eb) {
    const auto& pair = pairs_[pi];
    if (inLineContact(pi, ea, eb)) return;  // line contact sees parallel beams and their ends
    const double reach = inscribed_[pair.beamA] + inscribed_[pair.beamB];
    const BeamElement &A = elems[ea], &B = elems[eb];
    const Vec3d &a1 = state.position[A.node1], &a2 = state.position[A.node2];
    const Vec3d &b1 = state.position[B.node1], &b2 = state.position[B.node2];
    const SegmentClosest c = segmentClosest(a1, a2, b1, b2);
    if (!(c.distance < reach * (1.0 - 1e-9))) return;
    const double sine = norm(cross(a2 - a1, b2 - b1)) / (norm(a2 - a1) * norm(b2 - b1));
    const bool endA = (c.s == 0.0 && freeEnd_.count(A.node1)) || (c.s == 1.0 && freeEnd_.count(A.node2));
    const bool endB = (c.t == 0.0 && freeEnd_.count(B.node1)) || (c.t == 1.0 && freeEnd_.count(B.node2));
    const bool parallel = sine < options_.minimumSinAngle;
    if (!parallel && !endA && !endB) return;
    const Vec3d at = a1 + c.s * (a2 - a1);
    std::ostringstream s;
    s << "beams \"" << beams_->beams()[pair.beamA].name << "\" and \"" << beams_->beams()[pair.beamB].name
      << "\" overlap near (" << at[0] << ", " << at[1] << ", " << at[2] << "), axes " << c.distance << " apart, ";
    if (parallel) {
      s << "lying nearly parallel (sine of their angle " << sine
        << " below Contact/Parallel Line Tolerance): point contact cannot model this contact, and line contact "
           "is available only between two circular or two rectangular sections";
      if (!lineContact_)
        s << " with a strategy that enforces lines and Contact/Line Contact Angle > 0 (" << enforcer_->type()
          << " here does not)";
    } else {
      s << "at the free end of beam \"" << beams_->beams()[endA ? pair.beamA : pair.beamB].name
        << "\": contact at a beam end is not modelled (a contact point needs the closest points of the two lines "
           "within both beams)";
    }
    if (atStart) throw core::InputError(s.str() + "; move the beams apart");
    throw std::runtime_error(s.str());
  });
}

void ContactManager::checkNoPassThrough(const core::State& state) const {
  // Beams passed through each other when the axes of two of their elements crossed between the last
  // converged state and this one (the signed distance of the axes, oriented by continuity of
  // t_B x t_A, changed sign while the closest points lay on both elements in both states) and no
  // active contact point of the pair near those elements holds them. A point that carries its normal
  // from before is legal however deep it penetrates (a soft penalty); a crossing that no point
  // saw is not a solution: the increment fails (and is cut), never a silent result.
  forEachElementPair(state, [&](int pi, int ea, int eb) {
    const LinePairInput now = axisInput(ea, eb, state), before = axisInput(ea, eb, reference_);
    const ClosestPoints cur = closestPoints(now), ref = closestPoints(before);
    if (cur.sinAngle < options_.minimumSinAngle || ref.sinAngle < options_.minimumSinAngle) return;
    if (!withinElement(ea, cur.xi) || !withinElement(eb, cur.eta) || !nearElement(ea, ref.xi) ||
        !nearElement(eb, ref.eta))
      return;
    const Vec3d cRef = lineCross(ref), cCur = lineCross(cur);
    const double sideRef = dot(ref.cB - ref.cA, cRef);
    const double sideCur = dot(cur.cB - cur.cA, cCur) * (dot(cRef, cCur) >= 0.0 ? 1.0 : -1.0);
    if (sideRef * sideCur > 0.0 || (sideRef == 0.0 && sideCur == 0.0)) return;
    const auto& elems = beams_->elements();
    for (const auto& [key, p] : points_) {
      if (p.key.pair != pi || std::abs(elems[p.elementA].index - elems[ea].index) > 1 ||
          std::abs(elems[p.elementB].index - elems[eb].index) > 1)
        continue;
      if (p.node()) continue;
      const PointState* acting = actingState(p);
      const ContactKinematics k = kinematics(p, state, Variations::First);
      if (acting && enforcer_->contributes(k.normal.value, *acting) && k.normal.value < 0.0) return;
    }
    const auto& pair = pairs_[pi];
    std::ostringstream s;
    s << "beams \"" << beams_->beams()[pair.beamA].name << "\" and \"" << beams_->beams()[pair.beamB].name
      << "\" passed through each other near (" << cur.cA[0] << ", " << cur.cA[1] << ", " << cur.cA[2]
      << ") with no contact point holding them (smaller increments help)";
    throw std::runtime_error(s.str());
  });
}

LinePairInput ContactManager::axisInput(int eA, int eB, const core::State& s) const {
  LinePairInput in = lineInput(eA, 0, eB, 0, s);
  in.oA = in.oB = Vec3d{};
  in.radiusSum = 0.0;
  return in;
}

bool ContactManager::acceptSolution(core::State& state) {
  ++passes_;
  worstViolation_ = 0.0;
  bool all = true;
  // A point whose blend weight is at most kCarries carries (almost) nothing: the strategy does not judge it.
  // With a nodal line field the line nodes are judged, on their weighted gaps, not the Gauss points.
  std::vector<bool> carries;
  const auto gaps = nodalLines_ ? nodeGaps(state) : std::map<Key, NodeGap>{};
  // The kinematics a point is judged by (values and first variations), and whether it carries. The
  // second stage computes them again (from the same states: it runs only when no acceptNormal
  // changed one) rather than keeping them: with its (zero) second variations a ContactKinematics
  // takes 15 kB, and writing 150 MB of them for 10^4 points cost 80 us per point.
  const auto judged = [&](const Key& key, const Point& p, bool& carriesHere) {
    ContactKinematics k;
    if (p.node()) {
      const auto g = gaps.find(key);
      carriesHere = g != gaps.end() && g->second.weight > kCarries * g->second.full;
      if (carriesHere) {
        k.normal.value = g->second.weighted;
        k.tangent2.value = g->second.weightedSlip;
      }
      return k;
    }
    k = judgedKinematics(p, state);
    // (A line point on a sliver of a segment carries almost nothing either.)
    carriesHere = !(nodalLines_ && p.line()) && blendWeight(p, k.axesCosine, nullptr, nullptr) > kCarries &&
                  (!p.line() || k.segment > kCarries);
    return k;
  };
  const auto view = [&](const Point& p, const ContactKinematics& k) {
    return p.node() ? nodeView(p, k, state) : strategyView(p, k, state);
  };
  carries.reserve(points_.size());
  for (auto& [key, p] : points_) {
    bool carriesHere = false;
    const ContactKinematics k = judged(key, p, carriesHere);
    carries.push_back(carriesHere);
    if (carriesHere) {
      all = enforcer_->acceptNormal(view(p, k), *p.state) && all;
    } else if (!p.line() && enforcer_->multipliers(*p.state) > 0) {
      // Multipliers of a point or line node that carries (almost) nothing: given up.
      p.state = PointStateHolder(enforcer_->newPointState());
      all = false;
    }
  }
  if (all) {
    std::size_t i = 0;
    for (auto& [key, p] : points_) {
      if (carries[i]) {
        bool carriesHere = false;
        const ContactKinematics k = judged(key, p, carriesHere);
        all = enforcer_->acceptPoint(view(p, k), *p.state, worstViolation_) && all;
      }
      ++i;
    }
  }
  if (all) {
    checkNoPassThrough(state);
    checkNoUnseenContact(state, false);
  }
  if (passes_ == 1) violations_.clear();
  violations_.push_back(worstViolation_);
  if (!all && passes_ >= enforcer_->maximumPasses()) {
    std::ostringstream s;
    s << enforcer_->type() << ": constraints not met after " << passes_ << " passes (largest violation "
      << worstViolation_ << ")";
    throw std::runtime_error(s.str());
  }
  return all;
}

void ContactManager::commitStep(const core::State& state) {
  frictionWatch_.clear();
  const auto gaps = nodalLines_ ? nodeGaps(state) : std::map<Key, NodeGap>{};
  for (auto& [key, p] : points_) {
    if (p.node()) {  // a line node: its multipliers (reported through its Gauss points)
      ContactKinematics k;
      const auto g = gaps.find(key);
      if (g != gaps.end()) {
        k.normal.value = g->second.weighted;
        k.tangent2.value = g->second.weightedSlip;
      }
      const ContactPoint view = nodeView(p, k, state);
      p.result = enforcer_->reportedForces(view, *p.state);
      enforcer_->commitPoint(view, *p.state);
      p.gap = k.normal.value;
      p.position = state.position[p.key.node];
      continue;
    }
    const ContactKinematics k = judgedKinematics(p, state);
    const ContactPoint view = strategyView(p, k, state);
    if (nodalLines_ && p.line()) {
      std::vector<double> f;
      p.result = PointResult{};
      evaluateNodal(p, k, state, f, nullptr, &p.result);
    } else {
      p.result = enforcer_->reportedForces(view, *p.state);
      enforcer_->commitPoint(view, *p.state);
    }
    {  // reported as applied: times the blend weight and, for a line point, its length
      p.length = p.line() ? lineWeight(p, k.segment) : 0.0;
      const double w = blendWeight(p, k.axesCosine, nullptr, nullptr) * (p.line() ? p.length : 1.0);
      p.result.lambdaN *= w;
      for (double& t : p.result.lambdaT) t *= w;
      if (w == 0.0) p.result.active = false;
      if (p.line() && p.result.active && pairs_[p.key.pair].friction > 0.0) frictionlessLines_.insert(p.key.pair);
      if (nodalLines_ && p.line() && p.result.active) {
        // The field enforces gaps weighted over beam A's elements: between its nodes the beams may
        // penetrate. Beyond kUnresolved of the thinner section's inscribed radius the contact zone is not resolved.
        const auto& pair = pairs_[p.key.pair];
        const double radius = std::min(inscribed_[pair.beamA], inscribed_[pair.beamB]);
        if (-k.normal.value > kUnresolved * radius) {
          auto& worst = unresolvedLines_[p.key.pair];
          if (-k.normal.value > worst.first) {
            const ClosestPoints at = pointGeometry(p, state);
            worst = {-k.normal.value, 0.5 * (at.pA + at.pB)};
          }
        }
      }
    }
    p.gap = k.normal.value;
    const ClosestPoints cp = pointGeometry(p, state);
    if (p.result.active) {
      const auto& pair = pairs_[p.key.pair];
      const double depth = -cp.gap, inscribed = std::min(inscribed_[pair.beamA], inscribed_[pair.beamB]);
      if (depth > kDeep * inscribed) {
        auto& worst = deepPoints_[p.key.pair];
        if (depth > worst.first) worst = {depth, 0.5 * (cp.pA + cp.pB)};
      }
    }
    p.position = 0.5 * (cp.pA + cp.pB);
    p.normal = cp.normal;
    // The force on beam B is what the multipliers apply through the residual lambda_q R_q on B's
    // nodal translations (dofs 12-14 and 18-20), with the opposite sign (the residual holds the
    // internal side); split along the normal and in the tangent plane.
    const GapDerivatives* g[3] = {&k.normal, &k.tangent1, &k.tangent2};
    const double lam[3] = {p.result.lambdaN, p.result.lambdaT[0], p.result.lambdaT[1]};
    Vec3d force{};
    for (int q = 0; q < 3; ++q)
      for (int a = 0; a < 3; ++a) force[a] -= lam[q] * (g[q]->R[12 + a] + g[q]->R[18 + a]);
    p.normalForce = dot(force, cp.normal) * cp.normal;
    p.tangentialForce = force - p.normalForce;
    p.xiPrev = beamCoordinate(p.elementA, k.xi);
    p.etaPrev = beamCoordinate(p.elementB, k.eta);
    if (p.line()) p.etaRate = cp.etaRate;
  }
  checkLineResolution(state);
  committed_ = points_;
  reference_ = state;
  lastPasses_ = passes_;
  passes_ = 0;
}

void ContactManager::saveCommitted(core::CheckpointOut& out) const {
  out.label("contact").word(enforcer_->type()).integer(static_cast<long long>(committed_.size())).integer(lastPasses_);
  out.real(tangentialRelaxation_).integer(relaxations_);
  // The strategy's point state, field by field (name and value).
  struct Writer : StateFields {
    core::CheckpointOut& out;
    explicit Writer(core::CheckpointOut& o) : out(o) {}
    void real(const char* name, double& v) override { out.word(name).real(v); }
    void flag(const char* name, bool& v) override { out.word(name).integer(v ? 1 : 0); }
  } writer(out);
  for (const auto& [key, p] : committed_) {
    const auto code = p.key.code();
    out.label("point").integer(code[0]).integer(code[1]).integer(code[2]).integer(p.elementA).integer(p.elementB);
    out.real(p.sigma).real(p.xiPrev).real(p.etaPrev).real(p.etaRate).real(p.length);
    for (int a = 0; a < 3; ++a) out.real(p.normal[a]);
    for (int a = 0; a < 3; ++a) out.real(p.compliance[a]);
    (*p.state).fields(writer);
  }
}

void ContactManager::loadCommitted(core::CheckpointIn& in, const core::State& committed) {
  in.label("contact");
  if (in.word() != core::CheckpointOut::token(enforcer_->type())) in.fail("it was written with another enforcement strategy");
  const long long n = in.integer();
  const long long lastPasses = in.integer();
  tangentialRelaxation_ = in.real();
  const long long relaxations = in.integer();
  if (n < 0 || lastPasses < 0 || lastPasses > INT_MAX || relaxations < 0 || relaxations > INT_MAX)
    in.fail("its contact counters are negative or too large (points " + std::to_string(n) + ", passes " +
            std::to_string(lastPasses) + ", relaxations " + std::to_string(relaxations) + ")");
  lastPasses_ = static_cast<int>(lastPasses);
  relaxations_ = static_cast<int>(relaxations);
  // The tangential penalties are relaxed by a factor 10 each time (restoreStep), from 1.
  double relaxation = 1.0;
  for (int k = 0; k < relaxations_ && std::isfinite(relaxation); ++k) relaxation *= 10.0;
  if (tangentialRelaxation_ != relaxation)
    in.fail("its tangential relaxation factor " + core::shortest(tangentialRelaxation_) + " is not 10^" +
            std::to_string(relaxations_) + " (its count of relaxations)");
  const int elements = static_cast<int>(beams_->elements().size());
  struct Reader : StateFields {
    core::CheckpointIn& in;
    explicit Reader(core::CheckpointIn& i) : in(i) {}
    void name(const char* expected) {
      if (in.word() != core::CheckpointOut::token(expected))
        in.fail(std::string("a contact point's state lacks \"") + expected + "\" (another strategy version?)");
    }
    void real(const char* n, double& v) override { name(n); v = in.real(); }
    void flag(const char* n, bool& v) override { name(n); v = in.integer() != 0; }
  } reader(in);
  committed_.clear();
  for (long long i = 0; i < n; ++i) {
    in.label("point");
    Point p;
    const int pair = static_cast<int>(in.integer());
    const long long lineA = in.integer();
    p.key = PointKey::fromCode(pair, lineA, static_cast<int>(in.integer()));
    p.elementA = static_cast<int>(in.integer());
    p.elementB = static_cast<int>(in.integer());
    if (p.key.pair < 0 || p.key.pair >= static_cast<int>(pairs_.size()) || p.elementA < 0 || p.elementA >= elements ||
        p.elementB < 0 || p.elementB >= elements)
      in.fail("contact point " + std::to_string(i + 1) + " refers to a pair or element the deck does not have (pair " +
              std::to_string(p.key.pair) + " of " + std::to_string(pairs_.size()) + ", elements " +
              std::to_string(p.elementA) + " and " + std::to_string(p.elementB) + " of " + std::to_string(elements) +
              ")");
    // Its elements belong to the beams of its pair.
    const auto onPair = [&](int e) {
      const int beam = beams_->elements()[e].beam;
      return beam == pairs_[p.key.pair].beamA || beam == pairs_[p.key.pair].beamB;
    };
    if (!onPair(p.elementA) || !onPair(p.elementB))
      in.fail("contact point " + std::to_string(i + 1) + " joins elements " + std::to_string(p.elementA) + " and " +
              std::to_string(p.elementB) + ", which are not on the beams of its contact pair \"" +
              pairs_[p.key.pair].name + "\"");
    if (committed_.count(p.key))
      in.fail("contact point " + std::to_string(i + 1) + " is there twice (it is damaged)");
    p.sigma = in.real();
    if (p.sigma != 1.0 && p.sigma != -1.0)
      in.fail("contact point " + std::to_string(i + 1) + " has the normal orientation " + core::shortest(p.sigma) +
              " (it is +1 or -1)");
    p.xiPrev = in.real();
    p.etaPrev = in.real();
    p.etaRate = in.real();
    p.length = in.real();
    for (int a = 0; a < 3; ++a) p.normal[a] = in.real();
    for (int a = 0; a < 3; ++a) p.compliance[a] = in.real();
    p.xi = p.xiPrev - beams_->elements()[p.elementA].index;
    p.state = PointStateHolder(enforcer_->newPointState());
    (*p.state).fields(reader);
    const auto* block = committed.extra.find(kExtraOwner, extraKey(p));
    p.extraOffset = block ? block->offset : -1;
    p.extraCount = block ? block->size : 0;
    if (p.extraCount != enforcer_->multipliers(*p.state))
      in.fail("a contact point's multipliers do not match its state");
    committed_[p.key] = p;
  }
  // Every contact multiplier in the state belongs to one of these points.
  std::size_t blocks = 0, withBlock = 0;
  for (const auto& [id, block] : committed.extra.blocks()) blocks += id.first == kExtraOwner ? 1 : 0;
  for (const auto& [key, p] : committed_) withBlock += p.extraOffset >= 0 ? 1 : 0;
  if (blocks != withBlock)
    in.fail("its state holds contact multipliers of " + std::to_string(blocks) + " points, its contact history " +
            std::to_string(withBlock) + " points with multipliers");
  points_ = committed_;
  marked_ = committed_;
  reference_ = committed;
  // (The line-contact warnings are not in the checkpoint: they are renewed from the steps that
  // follow, and the frictionless one also from the restored points.)
  for (const auto& [key, p] : committed_)
    if (p.line() && pairs_[p.key.pair].friction > 0.0) frictionlessLines_.insert(p.key.pair);
  passes_ = 0;
}

ClosestPoints ContactManager::pointGeometry(const Point& p, const core::State& s, double* segment) const {
  if (p.line()) {
    const LinePairInput in = lineContactInput(p, s);
    const LineSegment seg = lineSegment(in);
    if (segment) *segment = seg.length();
    ClosestPoints cp = lineProjection(in, seg.lo + seg.length() * gaussXi_[p.gauss()]);
    cp.sinAngle = 1.0;  // a line point is defined at any angle
    if (lineSide(in, cp, p.normal) < 0.0) {  // it keeps its side (lineKinematics)
      const double radiusSum = cp.distance - cp.gap;
      cp.gap = -cp.distance - radiusSum;
      cp.normal = -1.0 * cp.normal;
    }
    return cp;
  }
  const LinePairInput in = lineInput(p.elementA, p.key.lineA, p.elementB, p.key.lineB, s);
  ClosestPoints cp = closestPoints(in);
  orient(cp, p.sigma, in.radiusSum);
  return cp;
}

double ContactManager::stepBound(const core::State& state, const std::vector<double>& du) const {
  // A point open at this iterate whose gap would cross its activation gap at the full step: the step
  // stops where it has crossed by a tenth of its present distance (linear interpolation of the gap),
  // so the point is active, with a small force, at the next iterate and the next Newton step sees its
  // stiffness. Without this a stiff penalty spring that the linearized step ignores meets a
  // penetration of the whole step and Newton cycles.
  double bound = 1.0;
  std::unique_ptr<core::State> next;
  for (const auto& [key, p] : points_) {
    if (p.node()) continue;
    const double activation = enforcer_->activationGap(*p.state);
    if (!std::isfinite(activation)) return 1.0;
    // Not for line points: each stands for a short length (a soft spring), and at a contact zone's
    // edge many of them hover at zero gap; bounding the step on each made Newton crawl (two parallel
    // rods pressed together: 10 steps with, 15 with cuts, without the bound).
    if (p.line()) continue;
    const double a0 = pointGeometry(p, state).gap - activation;
    if (!(a0 > 0.0)) continue;
    if (!next) {
      next = std::make_unique<core::State>(state);
      next->applyIncrement(du);
    }
    const ClosestPoints then = pointGeometry(p, *next);
    if (then.sinAngle < options_.minimumSinAngle) continue;
    const double a1 = then.gap - activation;
    if (a1 >= -0.1 * a0) continue;
    bound = std::min(bound, 1.1 * a0 / (a0 - a1));
  }
  return bound;
}

void ContactManager::restoreStep() {
  if (cycling_) {
    tangentialRelaxation_ *= 10.0;
    ++relaxations_;
    for (auto& [key, p] : committed_)
      if (p.compliance[0] > 0.0) handCompliance(p);
  }
  cycling_ = false;
  points_ = committed_;
  passes_ = 0;
  frictionWatch_.clear();
}

std::string ContactManager::tableHeader() const {
  return "pair,line_A,line_B,beam_A_coordinate,beam_B_coordinate,x,y,z,gap,normal_force,tangential_force_1,"
         "tangential_force_2,state_1,state_2,active,normal_x,normal_y,normal_z,normal_force_x,normal_force_y,"
         "normal_force_z,tangential_force_x,tangential_force_y,tangential_force_z,tangential_force,element_A,element_B,"
         "line_traction,normal_penalty,tangential_penalty";
}

std::vector<std::string> ContactManager::tableRows() const {
  std::vector<std::string> rows;
  for (const auto& [key, p] : committed_) {
    if (p.node()) continue;
    std::ostringstream s;
    s.precision(12);
    const auto state = [&](int i) { return !p.result.active ? "open" : (p.result.slip[i] ? "slip" : "stick"); };
    const auto code = p.key.code();
    s << pairs_[p.key.pair].name << "," << code[1] << "," << code[2] << "," << p.xiPrev << "," << p.etaPrev << ","
      << p.position[0] << "," << p.position[1] << "," << p.position[2] << "," << p.gap << ","
      << -p.result.lambdaN << "," << p.result.lambdaT[0] << "," << p.result.lambdaT[1] << "," << state(0) << ","
      << state(1) << "," << (p.result.active ? 1 : 0);
    for (const Vec3d* v : {&p.normal, &p.normalForce, &p.tangentialForce})
      for (int a = 0; a < 3; ++a) s << "," << (*v)[a];
    s << "," << norm(p.tangentialForce);
    // The segment (the elements, within their beams, the point lies on) and, for a line point, its
    // normal force per unit length of line A (0 for point contacts).
    const auto& elems = beams_->elements();
    s << "," << elems[p.elementA].index << "," << elems[p.elementB].index << ","
      << (p.line() && p.length > 0.0 ? -p.result.lambdaN / p.length : 0.0);
    // The penalty parameters the strategy used at the point (0: none, or the point carried no force).
    s << "," << p.result.penalty[0] << "," << p.result.penalty[1];
    rows.push_back(s.str());
  }
  return rows;
}

void ContactManager::appendVtk(const core::State&, core::VtkMesh& mesh) const {
  // In every step's file, also without contact.
  mesh.pointVectors["contact force"];
  mesh.pointScalars["line traction"];
  mesh.pointScalars["segment element A"];
  mesh.pointScalars["segment element B"];
  mesh.pointVectors["contact normal force"];
  mesh.pointVectors["contact tangential force"];
  mesh.pointVectors["contact normal"];
  mesh.pointScalars["contact gap"];
  mesh.pointScalars["contact pair"];
  mesh.pointScalars["contact slip lines"];
  const auto& elems = beams_->elements();
  for (const auto& [key, p] : committed_) {
    if (!p.result.active || p.node()) continue;
    const int point = mesh.addPoint(p.position, Vec3d{});
    mesh.setPointVector("contact force", point, p.normalForce + p.tangentialForce);
    mesh.setPointVector("contact normal force", point, p.normalForce);
    mesh.setPointVector("contact tangential force", point, p.tangentialForce);
    mesh.setPointVector("contact normal", point, p.normal);
    mesh.setPointScalar("contact gap", point, p.gap);
    mesh.setPointScalar("contact pair", point, p.key.pair);
    // 0: both lines stick, 1 or 2: that many slip.
    mesh.setPointScalar("contact slip lines", point, (p.result.slip[0] ? 1 : 0) + (p.result.slip[1] ? 1 : 0));
    mesh.setPointScalar("line traction", point, p.line() && p.length > 0.0 ? -p.result.lambdaN / p.length : 0.0);
    mesh.setPointScalar("segment element A", point, elems[p.elementA].index);
    mesh.setPointScalar("segment element B", point, elems[p.elementB].index);
    mesh.cellTypes.push_back(1);  // VTK_VERTEX
    mesh.cells.push_back({point});
    mesh.cellBeam.push_back(-1);
    mesh.cellElement.push_back(-1);
  }
}

void ContactManager::checkLineResolution(const core::State& state) {
  // The Gauss points of line contact see the gap only where they are. Where the contact zone of an
  // element pair is shorter than their spacing (axes crossing at a small angle) the beams can overlap
  // between them, unseen. Per element pair (and, for rectangles, edge of A) with line points that
  // carry weight: the gap sampled along A's line (kSamples points, projected on B's) against the
  // deepest Gauss point's.
  constexpr int kSamples = 64;
  // (pair, element A, element B, edge of A, face of B; 0, 0 for circles) -> lowest Gauss gap
  std::map<std::tuple<int, int, int, int, int>, double> deepest;
  for (const auto& [key, p] : points_) {
    if (!p.line()) continue;
    if (!(blendWeight(p, std::cos(axisAngle(p.elementA, p.elementB, state)), nullptr, nullptr) > kCarries)) continue;
    const auto k = std::make_tuple(p.key.pair, p.elementA, p.elementB, p.edge(), p.face());
    const double gap = pointGeometry(p, state).gap;
    const auto it = deepest.find(k);
    deepest[k] = it == deepest.end() ? gap : std::min(it->second, gap);
  }
  for (const auto& [k, gauss] : deepest) {
    const auto [pi, ea, eb, edge, face] = k;
    const auto& pair = pairs_[pi];
    const double radius = std::min(inscribed_[pair.beamA], inscribed_[pair.beamB]);
    // Rectangles: along A's edge against B's face, where the edge lies across it.
    const LinePairInput in = segmentInput(pi, ea, eb, edge, face, state);
    const LineSegment seg = lineSegment(in);
    for (int i = 0; i <= kSamples && seg.length() > 0.0; ++i) {
      const ClosestPoints cp = lineProjection(in, seg.lo + seg.length() * i / kSamples);
      if (in.face && std::abs(cp.lateral) > in.halfWidthB) continue;
      const double unseen = std::min(gauss, 0.0) - cp.gap;
      if (!(unseen > kUnresolved * radius)) continue;
      auto& worst = unseenBetween_[pi];
      if (unseen > worst.first) worst = {unseen, 0.5 * (cp.pA + cp.pB)};
    }
  }
}

std::vector<std::string> ContactManager::warnings() const {
  std::vector<std::string> w;
  if (relaxations_ > 0) {
    std::ostringstream s;
    s << "the automatic Tangential Penalty Parameters were lowered by a factor " << tangentialRelaxation_
      << " after Newton solves failed with slip directions cycling: a sticking friction force may be off by more "
         "than the Tangential Target Error (by 1 / (1 + eps_T c_T) of it with the lowered eps_T, contact_points.csv "
         "gives each point's eps_T)";
    w.push_back(s.str());
  }
  for (const auto& [pair, worst] : deepPoints_) {
    const auto& pr = pairs_[pair];
    const double inscribed = std::min(inscribed_[pr.beamA], inscribed_[pr.beamB]);
    std::ostringstream s;
    s << "contact pair \"" << pr.name << "\": the beams penetrated each other by up to " << worst.first << " ("
      << 100.0 * worst.first / inscribed << " % of the thinner section's inscribed radius) near (" << worst.second[0]
      << ", " << worst.second[1] << ", " << worst.second[2] << "), more than " << 100.0 * kDeep
      << " %: the sections overlap visibly there, so the forces are those of a soft contact law, not of contact; "
         "raise the Normal Penalty Parameter (or use Augmented Lagrange or Lagrange Multiplier)";
    w.push_back(s.str());
  }
  for (const auto& [pair, worst] : unseenBetween_) {
    std::ostringstream s;
    s << "contact pair \"" << pairs_[pair].name << "\": between the Gauss points of line contact the beams "
      << "overlapped by up to " << worst.first << " more than at any Gauss point, near (" << worst.second[0] << ", "
      << worst.second[1] << ", " << worst.second[2] << ") (more than " << kUnresolved
      << " of the thinner section's inscribed radius): the contact zone there is shorter than the Gauss points' spacing (axes "
         "crossing at a small angle), so part of the contact was not seen; raise Contact/Line Gauss Points or "
         "refine beam \"" << beams_->beams()[pairs_[pair].beamA].name << "\"";
    w.push_back(s.str());
  }
  for (const auto& [pair, worst] : unresolvedLines_) {
    std::ostringstream s;
    s << "contact pair \"" << pairs_[pair].name << "\": " << enforcer_->type()
      << " enforces line contact on gaps weighted over the elements of beam \""
      << beams_->beams()[pairs_[pair].beamA].name << "\", and between its nodes the beams penetrated by up to "
      << worst.first << " near (" << worst.second[0] << ", " << worst.second[1] << ", " << worst.second[2]
      << "), more than " << kUnresolved
      << " of the thinner section's inscribed radius: the contact zone there is short against the elements (beams crossing at a "
         "small angle, or a beam end on the other beam), so the contact force is not resolved; refine beam \""
      << beams_->beams()[pairs_[pair].beamA].name << "\" or use Penalty or Augmented Lagrange";
    w.push_back(s.str());
  }
  for (int pair : frictionlessLines_) {
    std::ostringstream s;
    s << "contact pair \"" << pairs_[pair].name << "\" has friction coefficient " << pairs_[pair].friction
      << ", and its beams were in line contact (nearly parallel): ";
    s << "friction acted along the axes only; sliding across them (perpendicular to both axes) is frictionless";
    w.push_back(s.str());
  }
  return w;
}

std::string ContactManager::progressSummary() const {
  int active = 0, stick = 0, slip = 0;
  for (const auto& [key, p] : committed_) {
    if (!p.result.active || p.node()) continue;
    ++active;
    for (int i = 0; i < 2; ++i) (p.result.slip[i] ? slip : stick)++;
  }
  std::ostringstream s;
  s << "contact " << active << " (stick " << stick << ", slip " << slip << " lines)";
  if (enforcer_->maximumPasses() > 1) s << ", passes " << lastPasses_;
  return s.str();
}

}  // namespace bc::constraints
