#include "ContactSearch.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <type_traits>
#include <unordered_map>

#include "LineContact.hpp"
#include "core/Faults.hpp"
#include "core/Parameters.hpp"

namespace bc::constraints {

using elements::BeamElement;
using elements::CrossSection;

namespace {

struct Box {
  Vec3d lo, hi;
};

// Uniform grid of cell size = largest box extent: a box overlaps at most 2 x 2 x 2 cells. Over the
// boxes' bounding box it is stored densely (each cell's elements one after another) when that takes
// at most 8 cells per element, else hashed (sparse fibre sets): at 4 x 10^4 contact points of the
// crossed layers the hashed cells' lookups were the search's own hot spot. A cell lists its
// elements in increasing order.
class BoxGrid {
 public:
  BoxGrid(const std::vector<Box>& boxes, const std::vector<int>& elements, double cell) : cell_(cell) {
    constexpr double kHuge = std::numeric_limits<double>::max();
    lo_ = Vec3d{{kHuge, kHuge, kHuge}};
    Vec3d hi{{-kHuge, -kHuge, -kHuge}};
    bool finite = std::isfinite(cell) && cell > 0.0;
    for (const int e : elements) {
      for (int k = 0; k < 3; ++k) {
        finite = finite && std::isfinite(boxes[e].lo[k]) && std::isfinite(boxes[e].hi[k]);
        lo_[k] = std::min(lo_[k], boxes[e].lo[k]);
        hi[k] = std::max(hi[k], boxes[e].hi[k]);
      }
    }
    // (Not finite: a diverged state, its boxes' cells hashed as before and no index out of the grid.)
    double cells = 1.0;
    for (int k = 0; k < 3 && finite; ++k) {
      dims_[k] = static_cast<long long>(std::floor((hi[k] - lo_[k]) / cell)) + 1;
      cells *= double(dims_[k]);
    }
    dense_ = finite && cells <= 8.0 * double(elements.size()) + 64.0;
    if (!finite) lo_ = Vec3d{};
    if (dense_) {
      cellStart_.assign(static_cast<std::size_t>(cells) + 1, 0);
      for (const int e : elements) forEachCell(boxes[e], [&](long long c) { ++cellStart_[c + 1]; });
      for (std::size_t c = 1; c < cellStart_.size(); ++c) cellStart_[c] += cellStart_[c - 1];
      cellElements_.resize(cellStart_.back());
      std::vector<int> next(cellStart_.begin(), cellStart_.end() - 1);
      for (const int e : elements) forEachCell(boxes[e], [&](long long c) { cellElements_[next[c]++] = e; });
    } else {
      for (const int e : elements) forEachCell(boxes[e], [&](long long c) { hashed_[c].push_back(e); });
    }
  }
  // Calls fn(cell) for each cell of a box.
  template <class Fn> void forEachCell(const Box& b, const Fn& fn) const {
    const auto [i0, i1] = range(b, 0);
    const auto [j0, j1] = range(b, 1);
    const auto [k0, k1] = range(b, 2);
    for (long long i = i0; i <= i1; ++i)
      for (long long j = j0; j <= j1; ++j)
        for (long long k = k0; k <= k1; ++k) fn(cellKey(i, j, k));
  }
  // The elements of a cell, as [first, second).
  std::pair<const int*, const int*> elements(long long c) const {
    if (dense_) return {cellElements_.data() + cellStart_[c], cellElements_.data() + cellStart_[c + 1]};
    const auto it = hashed_.find(c);
    if (it == hashed_.end()) return {nullptr, nullptr};
    return {it->second.data(), it->second.data() + it->second.size()};
  }

 private:
  std::pair<long long, long long> range(const Box& b, int k) const {
    return {(long long)std::floor((b.lo[k] - lo_[k]) / cell_), (long long)std::floor((b.hi[k] - lo_[k]) / cell_)};
  }
  long long cellKey(long long i, long long j, long long k) const {
    return dense_ ? (i * dims_[1] + j) * dims_[2] + k : (i * 73856093LL) ^ (j * 19349663LL) ^ (k * 83492791LL);
  }
  double cell_;
  Vec3d lo_;
  long long dims_[3] = {1, 1, 1};
  bool dense_ = false;
  std::vector<int> cellStart_, cellElements_;  // dense: cell c's elements at [cellStart[c], cellStart[c + 1])
  std::unordered_map<long long, std::vector<int>> hashed_;
};

// The narrow phase's choice for a key (see detect).
struct Offer {
  Candidate candidate;
  double outside;
  long long visit;
};

// Every rank's choices to every rank, merged by `offer` (the rule that made them).
void exchangeChoices(const Teuchos::Comm<int>& comm, std::map<PointKey, Offer>& chosen, const CandidateOffer& offer) {
  const int ranks = comm.getSize();
  const MPI_Comm raw = core::rawMpiComm(comm);
  struct Record {
    PointKey key;
    int elementA, elementB;
    double outside;
    long long visit;
    ClosestPoints cp;
    int endCut;
  };
  static_assert(std::is_trivially_copyable_v<Record>, "records travel as bytes");
  std::vector<Record> mine;
  mine.reserve(chosen.size());
  for (const auto& [key, o] : chosen)
    mine.push_back(Record{key, o.candidate.elementA, o.candidate.elementB, o.outside, o.visit, o.candidate.cp,
                          o.candidate.endCut});
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
  MPI_Allgatherv(mine.data(), static_cast<int>(bytes), MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE,
                 raw);
  chosen.clear();
  for (const Record& r : all) offer(r.key, Candidate{r.elementA, r.elementB, r.cp, r.endCut}, r.outside, r.visit);
}

}  // namespace

namespace {

// The elements of beams in contact pairs: the only ones boxed, gridded and searched.
std::vector<int> elementsInPairs(const ContactGeometry& geometry) {
  const auto& elems = geometry.beams().elements();
  std::vector<char> inPairs(geometry.beams().beams().size(), 0);
  for (const auto& p : geometry.pairs()) inPairs[p.beamA] = inPairs[p.beamB] = 1;
  std::vector<int> boxed;
  for (std::size_t e = 0; e < elems.size(); ++e)
    if (inPairs[elems[e].beam]) boxed.push_back(static_cast<int>(e));
  return boxed;
}

// Bounding boxes of the elements `boxed` (of beams in contact pairs), swept from the last converged
// state to `s`: a pair that one increment carries through each other is still a candidate, with no
// search margin tuned to the increment. `cell`: the largest extent of a box.
std::vector<Box> sweptBoxes(const ContactGeometry& geometry, const core::State& s, const std::vector<int>& boxed,
                            double& cell) {
  const auto& elems = geometry.beams().elements();
  const core::State& reference = geometry.reference();
  std::vector<Box> boxes(elems.size());
  cell = 0.0;
  for (const int e : boxed) {
    const BeamElement& el = elems[e];
    const auto& sec = geometry.beams().beams()[el.beam].section;
    const double reach =
        (sec.shape == CrossSection::Shape::Rectangle ? 0.5 * std::hypot(sec.width, sec.height) : sec.radius) +
        geometry.options().searchMargin;
    Box b;
    for (int k = 0; k < 3; ++k) {
      b.lo[k] = std::min({s.position[el.node1][k], s.position[el.node2][k], reference.position[el.node1][k],
                          reference.position[el.node2][k]}) -
                reach;
      b.hi[k] = std::max({s.position[el.node1][k], s.position[el.node2][k], reference.position[el.node1][k],
                          reference.position[el.node2][k]}) +
                reach;
      cell = std::max(cell, b.hi[k] - b.lo[k]);
    }
    boxes[e] = b;
  }
  return boxes;
}

// Per beam, the first and last of its elements among `boxed`; `runs`: every beam's elements are
// numbered one after another (then a cell's elements of one beam are one run of the cell).
struct BeamRuns {
  std::vector<int> first, last;
  bool runs = true;
};
BeamRuns beamRuns(const std::vector<BeamElement>& elems, const std::vector<int>& boxed, std::size_t numBeams) {
  BeamRuns r;
  r.first.assign(numBeams, std::numeric_limits<int>::max());
  r.last.assign(numBeams, -1);
  std::vector<int> count(numBeams, 0);
  for (const int e : boxed) {
    const int b = elems[e].beam;
    r.first[b] = std::min(r.first[b], e);
    r.last[b] = std::max(r.last[b], e);
    ++count[b];
  }
  for (std::size_t b = 0; b < numBeams; ++b)
    r.runs = r.runs && (count[b] == 0 || r.last[b] - r.first[b] + 1 == count[b]);
  return r;
}

}  // namespace

void ContactSearch::forEachElementPair(const core::State& s, const std::function<void(int, int, int)>& visit) const {
  const auto& elems = geometry_.beams().elements();
  const std::vector<int> boxedElements = elementsInPairs(geometry_);
  double cell = 0.0;
  const std::vector<Box> boxes = sweptBoxes(geometry_, s, boxedElements, cell);
  if (boxedElements.empty()) return;
  const BoxGrid grid(boxes, boxedElements, cell);
  // Element pairs (pair, element of its beam A, element of its beam B) whose boxes overlap, found
  // from each element's cells (not by looping over every pair and element: with All Pairs of n
  // beams that is n^2 / 2 pairs), then visited pair by pair in element order.
  // A cell lists its elements in increasing order, and a beam's elements are numbered one after
  // another, so the elements of ea's own beam (never in a pair with it) are one run of each cell,
  // skipped by bisection: where elements are short against the sections, a cell holds thousands of
  // one beam's elements, and testing them all made the search quadratic (`check` of Example 1 with
  // 10^4 elements on beam 1: 5.7 s, 88 % of it in these tests; 2 x 10^4: 4 times that).
  const BeamRuns beam = beamRuns(elems, boxedElements, geometry_.beams().beams().size());
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
        const int pair = geometry_.pairOf(elems[ea].beam, elems[eb].beam);
        if (pair < 0) continue;
        seenBy[eb] = ea;
        // Elements that share a node (beams joined there) or whose nodes are pinned together do
        // not contact each other.
        const BeamElement &A0 = elems[ea], &B0 = elems[eb];
        bool joined = false;
        for (int na : {A0.node1, A0.node2})
          for (int nb : {B0.node1, B0.node2}) joined = joined || na == nb || geometry_.joined(na, nb);
        if (!joined) found.emplace_back(pair, ea, eb);
      }
    };
    grid.forEachCell(A, [&](long long c) {
      const auto [begin, end] = grid.elements(c);
      if (!beam.runs) return visitRun(begin, end);
      const int* from = std::lower_bound(begin, end, beam.first[own]);
      const int* to = std::upper_bound(from, end, beam.last[own]);
      visitRun(begin, from);
      visitRun(to, end);
    });
  }
  std::stable_sort(found.begin(), found.end(),
                   [](const auto& a, const auto& b) { return std::get<0>(a) < std::get<0>(b); });
  for (const auto& [pi, ea, eb] : found) visit(pi, ea, eb);
}

std::vector<std::tuple<int, int, int>> ContactSearch::candidates(const core::State& s) const {
  std::vector<std::tuple<int, int, int>> found;
  forEachElementPair(s, [&](int pi, int ea, int eb) { found.emplace_back(pi, ea, eb); });
  std::sort(found.begin(), found.end());
  return found;
}

std::map<PointKey, Candidate> ContactSearch::detect(const core::State& s, const NarrowPhase& narrow) const {
  std::vector<std::tuple<int, int, int>> visits;
  forEachElementPair(s, [&](int pi, int ea, int eb) { visits.emplace_back(pi, ea, eb); });
  // A key's candidate is the one offered with the lowest (outside, visit): for a point contact the
  // candidate most central in its elements, the first visited of equals; for a line Gauss point the
  // last visited (offered with outside 0 and -visit). The choice does not depend on which rank
  // evaluated which visit, so the ranks' shares merge into the whole search's result.
  std::map<PointKey, Offer> chosen;
  const CandidateOffer offer = [&chosen](const PointKey& key, const Candidate& c, double outside, long long visit) {
    const auto it = chosen.find(key);
    if (it == chosen.end()) chosen.emplace(key, Offer{c, outside, visit});
    else if (outside < it->second.outside || (!(it->second.outside < outside) && visit < it->second.visit))
      it->second = Offer{c, outside, visit};
  };
  const int ranks = comm_.is_null() ? 1 : comm_->getSize(), me = comm_.is_null() ? 0 : comm_->getRank();
  const std::size_t first = visits.size() * me / ranks, last = visits.size() * (me + 1) / ranks;
  const auto share = [&] {
    for (std::size_t v = first; v < last; ++v) {
      const auto& [pi, ea, eb] = visits[v];
      narrow(pi, ea, eb, static_cast<long long>(v), offer);
    }
  };
  if (ranks == 1) {
    share();
  } else {
    // A failure in one rank's share is thrown on every rank (the first failing rank's error).
    core::collectively(*comm_, share);
    exchangeChoices(*comm_, chosen, offer);
  }
  std::map<PointKey, Candidate> found;
  for (auto& [key, o] : chosen) found.emplace_hint(found.end(), key, std::move(o.candidate));
  return found;
}

namespace {
// Below this sine of their angle (5.7 degrees) crossing rectangles are checked for faces that overlap
// where no point sees them.
constexpr double kSmallFaceAngleSine = 0.1;
// Rectangles' sections overlapping by more than this of the thinner inscribed radius where no point
// holds them overlap unseen. (1e-3 let stiff beams through: pinned 2 x 1 beams with E = 1e9 crossing
// at 1 degree, 3.9e-3 deflection at mid-span, ended "complete" 37 % low with their faces 2e-4 inside
// each other at the quarter points; the sections' centres lie on line contact's axes and the sections
// turn between the nodes, so an overlap this small is not the test's own geometry.)
constexpr double kSectionOverlap = 1e-5;
// A crossing in point contact whose chords lie deeper inside each other than this of the thinner
// inscribed radius where no point of the pair holds them is refused (checkNoUnseenContact).
constexpr double kUnheldCrossing = 0.01;
}  // namespace

double ContactSearch::sectionOverlap(const core::State& state, int ea, int eb) const {
  // How deep the rectangular sections of two nearly parallel elements overlap, the deepest of a few
  // stations (below): at a station the two sections lie in about one plane (across A's axis), and two
  // rectangles there overlap by the least of their overlaps along the four edge normals (separating
  // axes: for two convex polygons the edge normals are all the directions that can separate them);
  // negative where one of them separates them. (The axes' distance against the inscribed radii sum
  // missed flat sections side by side whose axes lie apart across their width: pinned 2 x 1 beams
  // crossing at 1 and 2 degrees ended "complete" 37 % low with the faces overlapping between the
  // points.)
  const auto& elems = geometry_.beams().elements();
  const auto& beams = geometry_.beams().beams();
  const BeamElement &A = elems[ea], &B = elems[eb];
  const Vec3d &a1 = state.position[A.node1], &a2 = state.position[A.node2];
  const Vec3d &b1 = state.position[B.node1], &b2 = state.position[B.node2];
  const Vec3d tA = (1.0 / norm(a2 - a1)) * (a2 - a1), tB = b2 - b1;
  // A section's axes (k = 1, 2) at u along its element, the nodes' blended (a twisting element's
  // section turns between them), across A's axis.
  const auto across = [&](const BeamElement& e, double u, int k) {
    const Vec3d v = (1.0 - u) * (state.rotation[e.node1] * column(e.data.T0, k)) +
                    u * (state.rotation[e.node2] * column(e.data.T0, k));
    const Vec3d w = v - dot(v, tA) * tA;
    const double n = norm(w);
    return n > 0.0 ? (1.0 / n) * w : w;
  };
  const auto reach = [&](const BeamElement& e, const Vec3d(&x)[2], const Vec3d& u) {
    return sectionReach(beams[e.beam].section, tA, x[0], x[1], u);
  };
  // A point of an element's axis at u: line contact's cubic axis, hermitePoint (a bent element's chord
  // lies off it by up to 4 / 27 of its tangents' turn times its length, more than the depth this test
  // looks for).
  const auto axis = [&](const BeamElement& e, double u) {
    const auto tangent = [&](int node) { return e.data.L0 * (state.rotation[node] * column(e.data.T0, 0)); };
    return hermitePoint(state.position[e.node1], tangent(e.node1), state.position[e.node2], tangent(e.node2), u);
  };
  // Stations: A's nodes and middle projected on B's chord, and B's on A's, where they fall on the
  // other element (a closest point of two elements side by side that do not overlap along their
  // axes compares sections an element apart), the sections' centres on the two axes there.
  const Vec3d uA = a2 - a1;
  double deepest = -std::numeric_limits<double>::infinity();
  for (int side = 0; side < 2; ++side)
    for (const double r : {0.0, 0.5, 1.0}) {
      const Vec3d p = side == 0 ? a1 + r * uA : b1 + r * tB;
      const Vec3d &o = side == 0 ? b1 : a1, &u = side == 0 ? tB : uA;
      const double t = dot(p - o, u) / dot(u, u);
      if (t < 0.0 || t > 1.0) continue;
      const double onA = side == 0 ? r : t, onB = side == 0 ? t : r;
      const Vec3d axes[2][2] = {{across(A, onA, 1), across(A, onA, 2)}, {across(B, onB, 1), across(B, onB, 2)}};
      Vec3d d = axis(B, onB) - axis(A, onA);
      d = d - dot(d, tA) * tA;
      double depth = std::numeric_limits<double>::infinity();
      for (const auto& pair : axes)
        for (const Vec3d& n : pair)
          if (norm(n) > 0.0) depth = std::min(depth, reach(A, axes[0], n) + reach(B, axes[1], n) - std::abs(dot(d, n)));
      deepest = std::max(deepest, depth);
    }
  return deepest;
}

void ContactSearch::checkNoUnseenContact(const core::State& state, bool atStart, const std::string& strategy,
                                         const std::function<bool(int, int, int)>& seen) const {
  // Contacts the point model cannot see: two beams whose axes come closer than the sum of their
  // sections' inscribed radii (so they surely overlap) where no contact point can exist:
  //  - at a free beam end (the closest points of the two lines lie beyond it, so no element pair
  //    has them inside both elements): an end pressed into the side of another beam;
  //  - nearly parallel (sine of the angle below "Parallel Line Tolerance"): point contact is
  //    undefined there;
  //  - rectangular sections in line contact, where no active line point of the pair on or next to
  //    the two elements sees the overlap (deeper than kUnresolvedLine of the thinner section's
  //    inscribed radius, so that a chord's sagitta between touching beams does not count): line
  //    contact sees only the faces it takes as facing each other, and their overlap's bounding lines.
  // A state with such an overlap is not a solution: the increment fails (a run cannot complete with
  // it), and at the start the deck is refused.
  const auto& elems = geometry_.beams().elements();
  const auto& beams = geometry_.beams().beams();
  forEachElementPair(state, [&](int pi, int ea, int eb) {
    const auto& pair = geometry_.pairs()[pi];
    const bool lines = geometry_.inLineContact(pi, ea, eb);
    const double reach = geometry_.inscribed(pair.beamA) + geometry_.inscribed(pair.beamB);
    const BeamElement &A = elems[ea], &B = elems[eb];
    const Vec3d &a1 = state.position[A.node1], &a2 = state.position[A.node2];
    const Vec3d &b1 = state.position[B.node1], &b2 = state.position[B.node2];
    const SegmentClosest c = segmentClosest(a1, a2, b1, b2);
    // (Rectangles may overlap with their axes further apart than the inscribed radii sum, up to the
    // half diagonals' sum: there only the tests of their sections' overlap, sectionOverlap, look.)
    const bool inner = c.distance < reach * (1.0 - 1e-9);
    const bool rectangles = geometry_.rectangles(pi);
    if (!inner &&
        !(rectangles && c.distance < geometry_.circumscribed(pair.beamA) + geometry_.circumscribed(pair.beamB)))
      return;
    const bool endA = (c.s == 0.0 && geometry_.freeEnd(A.node1)) || (c.s == 1.0 && geometry_.freeEnd(A.node2));
    const bool endB = (c.t == 0.0 && geometry_.freeEnd(B.node1)) || (c.t == 1.0 && geometry_.freeEnd(B.node2));
    // The refusal: "beams A and B overlap near (x, y, z), axes d apart" and `why`; at the start an
    // input error, in a run the increment's failure.
    const auto refuse = [&](const std::string& why) {
      const Vec3d at = a1 + c.s * (a2 - a1);
      std::ostringstream s;
      s << "beams \"" << beams[pair.beamA].name << "\" and \"" << beams[pair.beamB].name << "\" overlap near (" << at[0]
        << ", " << at[1] << ", " << at[2] << "), axes " << c.distance << " apart" << why;
      if (atStart) throw core::InputError(s.str() + "; move the beams apart");
      throw std::runtime_error(s.str());
    };
    // (Two free ends nearest each other are end-to-end contact's, below, even in line contact.)
    if ((inner || rectangles) && lines && !(endA && endB)) {
      // An element's material ends at the planes through its nodes: where the other axis's closest
      // point lies beyond such a plane, the axes' distance is no overlap of these two elements (the
      // neighbour past that node has its own pair; past a free end there is nothing, or end-to-end
      // contact). Two beams in line had their elements' axial distances taken as overlaps.
      // (Beyond by more than half their distance: elements side by side whose nodes do not line up
      // have their closest points at one element's end with the other a hair beyond its plane, and
      // overlap all the same.)
      const Vec3d pA = a1 + c.s * (a2 - a1), pB = b1 + c.t * (b2 - b1);
      const double beyond = 0.5 * c.distance;
      if ((c.s == 0.0 || c.s == 1.0) && dot(pB - pA, (1.0 / norm(a2 - a1)) * (c.s == 0.0 ? a1 - a2 : a2 - a1)) > beyond)
        return;
      if ((c.t == 0.0 || c.t == 1.0) && dot(pA - pB, (1.0 / norm(b2 - b1)) * (c.t == 0.0 ? b1 - b2 : b2 - b1)) > beyond)
        return;
      // Line contact of circular sections sees parallel beams whose axes lie apart, along the line
      // between them. Axes that (nearly) coincide have no such line: no point sees them, and at the
      // start a deck with such beams (one rod inside the other) ran "complete". At the start, also an
      // overlap by more than half the thinner section that no point sees (not a chord's sagitta:
      // a helical wire's chords come closer to a core than its curve by a few hundredths of it).
      if (!rectangles) {
        const bool coincide = c.distance <= 1e-6 * reach;
        const bool deep = c.distance < reach - 0.5 * geometry_.thinner(pi);
        // (Two coaxial ends pressed together overlap along the axis where their end-to-end point
        // holds them: seen.)
        const bool unseen = coincide
                                ? !seen(pi, ea, eb)
                                : atStart && deep && !geometry_.options().allowInitialPenetration && !seen(pi, ea, eb);
        if (!unseen) return;
        std::ostringstream why;
        why << " (their radii sum to " << reach << "), in line contact where no line point sees the overlap"
            << (coincide ? " (the axes coincide: no direction separates them)" : "");
        refuse(why.str());
      }
      // (Rectangles: their sections' overlap, sectionOverlap; the axes' distance against the
      // inscribed radii missed a 10 x 1 plate pushed 1.5 into a 1 x 5 beam in one increment, which
      // ended "complete" with no force.)
      const double depth = sectionOverlap(state, ea, eb);
      if (!(depth > kSectionOverlap * geometry_.thinner(pi)) || seen(pi, ea, eb)) return;
      std::ostringstream why;
      why << " (their sections overlap by " << depth
          << "), in line contact of rectangular sections where no line point sees the overlap (line contact "
          << "sees an edge of one beam on the face of the other facing it)";
      refuse(why.str());
    }
    const double sine = norm(cross(a2 - a1, b2 - b1)) / (norm(a2 - a1) * norm(b2 - b1));
    const bool parallel = !lines && !(endA && endB) && sine < geometry_.options().minimumSinAngle;
    // A crossing that no point holds. Two beams have one point contact per pair of their contact lines,
    // at the crossing whose closest points lie most central in their elements (PointContact::findPoints):
    // a beam that crosses the other twice (an arc, a coil, a bent beam over a straight one) is held at
    // one crossing, and at the other the beams overlapped with no force, "complete" (an arc pressed by
    // a bar across both its legs: 0.26 deep at one). On the chords, also a crossing at a node where a
    // beam bends away from the other (the closest points lie beyond the node on both elements: no
    // point; a coil under a bar, 0.45 deep). Refused where the chords lie deeper than
    // kUnheldCrossing (1 %) of the thinner inscribed radius inside each other, at a crossing: where the
    // two polylines' distance has a local minimum, not on elements beside a crossing that a point holds
    // a few elements away (fine meshes: a penalty's point 2.6 % deep at a crossing at right angles of
    // elements a quarter of the radius long had the chords two elements away 1.989 apart of 2, and the
    // run stopped). On the chords: each line's closest point on its element, or at a node where both
    // elements' closest points are that node (a bend away from the other). On the Hermite axes the
    // curves' own closest points (a coarse arc's chords lie inside the curve by its sagitta).
    const double unheld = reach - kUnheldCrossing * geometry_.thinner(pi);
    const auto atCrossing = [&] {
      LinePairInput in = geometry_.axisInput(ea, eb, state);
      geometry_.pointContactAxes(in, ea, eb);
      const ClosestPoints q = closestPoints(in);
      if (q.sinAngle < geometry_.options().minimumSinAngle) return false;
      if (geometry_.options().hermitePointAxes)
        return geometry_.withinElement(ea, q.xi) && geometry_.withinElement(eb, q.eta) && q.distance < unheld;
      // (The chords: c's clamped parameter at a node shared with the neighbour whose own closest point
      // to the other chord is that node too.)
      const auto bentAway = [&](int e, double at, const Vec3d& o1, const Vec3d& o2) {
        if (at != 0.0 && at != 1.0) return false;
        const BeamElement& E = elems[e];
        const int n = at == 0.0 ? e - 1 : e + 1;
        if (n < 0 || n >= static_cast<int>(elems.size()) || elems[n].beam != E.beam) return false;
        const SegmentClosest d = segmentClosest(state.position[elems[n].node1], state.position[elems[n].node2], o1, o2);
        return at == 0.0 ? d.s == 1.0 : d.s == 0.0;
      };
      const bool onA = geometry_.withinElement(ea, q.xi) || bentAway(ea, c.s, b1, b2);
      const bool onB = geometry_.withinElement(eb, q.eta) || bentAway(eb, c.t, a1, a2);
      return onA && onB;
    };
    if (!lines && !parallel && !endA && !endB && c.distance < unheld &&
        !(atStart && geometry_.options().allowInitialPenetration) && !seen(pi, ea, eb) && atCrossing()) {
      std::ostringstream s;
      s << " (their inscribed radii sum to " << reach
        << "), crossing where no contact point holds them: two beams have one point contact per pair of contact "
           "lines, at one crossing, so a beam that crosses the other more than once (an arc, a coil, a bent beam) "
           "is held at one crossing only; give each crossing its own pair by splitting one beam into beams joined "
           "end to end (Joints)";
      if (!geometry_.options().hermitePointAxes)
        s << ", and where the crossing lies at a node at which a beam bends away from the other, its chords have "
             "no closest points on either element: Contact/Point Contact Axes = Hermite sees it";
      refuse(s.str());
    }
    // A free end against the other beam's side is end contact's (its end points), two ends against
    // each other end-to-end contact's where their faces are turned towards each other; the rest is
    // refused where the end faces (discs or rectangles at the end nodes, their support functions
    // unsmoothed) are not separated along the line between the ends nor along either face's normal,
    // and no point of the pair there holds them.
    const bool endToEnd = endA && endB && [&] {
      // Separated along a direction d where the centres lie further apart than the two faces reach
      // along it; tried: the line between the centres and each face's normal (a face reaches 0
      // along its own normal, so two parallel faces apart are separated).
      const int nA = c.s == 0.0 ? A.node1 : A.node2, nB = c.t == 0.0 ? B.node1 : B.node2;
      const Vec3d d = state.position[nB] - state.position[nA];
      const double length = norm(d);
      if (length == 0.0) return true;
      const auto reach = [&](const BeamElement& e, int node, const Vec3d& u) {
        const Mat3d& R = state.rotation[node];
        return sectionReach(beams[e.beam].section, R * column(e.data.T0, 0), R * column(e.data.T0, 1),
                            R * column(e.data.T0, 2), u);
      };
      const Vec3d axes[3] = {(1.0 / length) * d, state.rotation[nA] * column(A.data.T0, 0),
                             state.rotation[nB] * column(B.data.T0, 0)};
      for (const Vec3d& u : axes)
        if (std::abs(dot(d, u)) >= (reach(A, nA, u) + reach(B, nB, u)) * (1.0 - 1e-9)) return false;
      return true;
    }();
    // Rectangles whose axes cross at a small angle (above Parallel Line Tolerance) are in point
    // contact, whose edge points do not see their faces: where the sections overlap (sectionOverlap)
    // and no point of the pair there holds them, the overlap is unseen. (Two face-to-face cantilevers
    // loaded in one increment turned by 0.6 degrees and ended "complete" with one 0.72 inside the
    // other and no contact force.)
    const double facesOverlap = !lines && !endA && !endB && !parallel && sine < kSmallFaceAngleSine && rectangles
                                    ? sectionOverlap(state, ea, eb)
                                    : -std::numeric_limits<double>::infinity();
    const bool unseenFaces = facesOverlap > kSectionOverlap * geometry_.thinner(pi);
    if (!inner && !unseenFaces) return;
    if (!parallel && !endToEnd && !unseenFaces) return;
    if (!parallel && seen(pi, ea, eb)) return;  // (two ends held by their end-to-end point, faces by a point)
    std::ostringstream s;
    s << ", ";
    if (unseenFaces) {
      s << "rectangular sections crossing at a small angle (sine " << sine << ", " << std::asin(sine) * 180.0 / M_PI
        << " degrees) whose faces overlap by " << facesOverlap
        << " where no contact point sees them: point contact sees their edges where they cross, and line contact "
           "(faces against edges) takes rectangles only below Contact/Parallel Line Tolerance ("
        << geometry_.options().minimumSinAngle
        << "); where faces lie on each other along the beams, a Parallel Line Tolerance above this sine puts them "
           "in line contact (a shorter increment helps where the faces only met in one step)";
    } else if (parallel) {
      s << "lying nearly parallel (sine of their angle " << sine
        << " below Contact/Parallel Line Tolerance): point contact cannot model this contact, and line contact "
           "is available only between two circular or two rectangular sections";
      if (!geometry_.lineContact())
        s << " with a strategy that enforces lines and Contact/Line Contact Angle > 0 (" << strategy
          << " here does not)";
    } else {
      s << "at the free ends of both beams, where no end-to-end point holds them (end-to-end contact takes two end "
           "faces turned towards each other, where one end touches the other's face within its rim)";
    }
    refuse(s.str());
  });
}

void ContactSearch::checkNoPassThrough(const core::State& state, const std::function<bool(int, int, int)>& held) const {
  // Beams passed through each other when the axes of two of their elements crossed between the last
  // converged state and this one (the signed distance of the axes, oriented by continuity of
  // t_B x t_A, changed sign while the closest points lay on both elements in both states) and no
  // active contact point of the pair near those elements holds them. A point that carries its normal
  // from before is legal however deep it penetrates (a soft penalty); a crossing that no point
  // saw is not a solution: the increment fails (and is cut), never a silent result.
  // The states compared are taken along the nodes' straight paths between the two, so closely that
  // no node moves more than a quarter of the pair's shorter element from one to the next: where the
  // crossing moved along a beam within the increment, the two end states alone had their closest
  // points on different elements, and no element pair saw it. (Example 1 in one increment with 60
  // Newton iterations allowed: beam 2 carried 40 along beam 1 and 20 down ended "complete" below
  // beam 1, through it, with no contact force.)
  constexpr double kStepOfElement = 0.25;
  constexpr int kMostSteps = 256;
  const double minimumSin = geometry_.options().minimumSinAngle;
  forEachElementPair(state, [&](int pi, int ea, int eb) {
    const LinePairInput now = geometry_.axisInput(ea, eb, state),
                        before = geometry_.axisInput(ea, eb, geometry_.reference());
    const Vec3d* from[4] = {&before.xA1, &before.xA2, &before.xB1, &before.xB2};
    const Vec3d* to[4] = {&now.xA1, &now.xA2, &now.xB1, &now.xB2};
    double motion = 0.0;
    for (int k = 0; k < 4; ++k) motion = std::max(motion, norm(*to[k] - *from[k]));
    const double shorter = std::min(norm(before.xA2 - before.xA1), norm(before.xB2 - before.xB1));
    const int steps = shorter > 0.0 ? static_cast<int>(std::clamp(std::ceil(motion / (kStepOfElement * shorter)), 1.0,
                                                                  static_cast<double>(kMostSteps)))
                                    : 1;
    const auto at = [&](int k) {
      if (k == steps) return now;
      LinePairInput in = now;
      const double f = static_cast<double>(k) / steps;
      Vec3d* x[4] = {&in.xA1, &in.xA2, &in.xB1, &in.xB2};
      for (int n = 0; n < 4; ++n) *x[n] = *from[n] + f * (*to[n] - *from[n]);
      return in;
    };
    ClosestPoints ref = closestPoints(before);
    // (the orientation of t_B x t_A carried along the path)
    Vec3d cRef = lineCross(ref);
    for (int k = 1; k <= steps; ++k) {
      const ClosestPoints cur = closestPoints(at(k));
      const bool judged = cur.sinAngle >= minimumSin && ref.sinAngle >= minimumSin;
      const Vec3d cCur = judged ? lineCross(cur) : cRef;
      const double flip = dot(cRef, cCur) >= 0.0 ? 1.0 : -1.0;
      if (judged && geometry_.withinElement(ea, cur.xi) && geometry_.withinElement(eb, cur.eta) &&
          geometry_.nearElement(ea, ref.xi) && geometry_.nearElement(eb, ref.eta)) {
        const double sideRef = dot(ref.cB - ref.cA, cRef);
        const double sideCur = dot(cur.cB - cur.cA, cCur) * flip;
        if (!(sideRef * sideCur > 0.0 || (sideRef == 0.0 && sideCur == 0.0)) && !held(pi, ea, eb)) {
          const auto& pair = geometry_.pairs()[pi];
          std::ostringstream s;
          s << "beams \"" << geometry_.beams().beams()[pair.beamA].name << "\" and \""
            << geometry_.beams().beams()[pair.beamB].name << "\" passed through each other near (" << cur.cA[0] << ", "
            << cur.cA[1] << ", " << cur.cA[2] << ") with no contact point holding them (smaller increments help)";
          throw std::runtime_error(s.str());
        }
      }
      ref = cur;
      cRef = flip * cCur;
    }
  });
}

}  // namespace bc::constraints
