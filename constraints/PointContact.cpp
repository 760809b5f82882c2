#include "PointContact.hpp"

#include <algorithm>
#include <cmath>

namespace bc::constraints {

LinePairInput PointContact::input(int eA, int lA, int eB, int lB, const core::State& s) const {
  LinePairInput in = geometry_.lineInput(eA, lA, eB, lB, s);
  geometry_.pointContactAxes(in, eA, eB);
  return in;
}

double PointContact::referenceSigma(int eA, int lA, int eB, int lB, const ClosestPoints& cp) const {
  // The orientation of a newly found point: in the last converged state (no interpenetration there)
  // the normal points from beam A to beam B; carried to the current lines by continuity of their
  // cross product. Without it a beam carried through the other within one increment would be
  // found on the far side and pushed on through. Where the lines did not overlap in the last
  // converged state (closest points beyond the elements), the current side is taken.
  const ClosestPoints ref = closestPoints(input(eA, lA, eB, lB, geometry_.reference()));
  if (ref.sinAngle < geometry_.options().minimumSinAngle || !geometry_.nearElement(eA, ref.xi) ||
      !geometry_.nearElement(eB, ref.eta))
    return cp.sigma;
  return dot(lineCross(ref), lineCross(cp)) >= 0.0 ? ref.sigma : -ref.sigma;
}

void PointContact::findPoints(int pi, int ea, int eb, long long visit, const core::State& s, const PointMap& known,
                              const CandidateOffer& offer) const {
  const auto& pair = geometry_.pairs()[pi];
  for (int la = 0; la < geometry_.lineCount(pair.beamA); ++la)
    for (int lb = 0; lb < geometry_.lineCount(pair.beamB); ++lb) {
      const LinePairInput in = input(ea, la, eb, lb, s);
      ClosestPoints cp = closestPoints(in);
      if (cp.sinAngle < geometry_.options().minimumSinAngle) continue;
      if (!geometry_.withinElement(ea, cp.xi) || !geometry_.withinElement(eb, cp.eta)) continue;
      const PointKey key = PointKey::contact(pi, la, lb);
      // The normal's orientation: carried by a known point, else from the last converged state.
      const auto it = known.find(key);
      orient(cp, it != known.end() ? it->second.sigma : referenceSigma(ea, la, eb, lb, cp), in.radiusSum);
      // Only lines on the sides facing each other.
      if (dot(cp.pA - cp.cA, cp.normal) < -1e-12 || dot(cp.pB - cp.cB, cp.normal) > 1e-12) continue;
      if (in.radiusSum == 0.0 && (dot(cp.pA - cp.cA, cp.normal) <= 0 || dot(cp.pB - cp.cB, cp.normal) >= 0)) continue;
      if (in.radiusSum == 0.0 && acrossFaces(ea, eb, cp, in, geometry_.thinner(pi))) continue;
      // A new edge pair of rectangles within both sections' circumscribed radii of a free beam end is
      // not taken deeper than half the thinner section's inscribed radius: an end standing on a face
      // has its edges inside that face, where the closest points of its edges and the face's bounding
      // edges give spurious points 1 to 1.5 deep (the end point holds that end). Away from free ends
      // a deep new point is a real overlap (at the start: refused; within an increment: held).
      const double reach = geometry_.circumscribed(pair.beamA) + geometry_.circumscribed(pair.beamB);
      if (in.radiusSum == 0.0 && it == known.end() && cp.gap < -0.5 * geometry_.thinner(pi) &&
          (nearFreeEnd(ea, cp.pA, reach, s) || nearFreeEnd(eb, cp.pB, reach, s)))
        continue;
      // A known point stays on its element pair while its closest points lie within the
      // elements or up to kStay of an element length beyond a shared node; it is handed to a
      // neighbour only beyond that, so a point at a node cannot flip between elements from one
      // iteration to the next. Otherwise the candidate most central in its elements wins.
      constexpr double kStay = 0.05;
      double out = std::max(std::abs(cp.xi - 0.5), std::abs(cp.eta - 0.5));
      if (it != known.end() && it->second.elementA == ea && it->second.elementB == eb && out <= 0.5 + kStay) out = -1.0;
      offer(key, Candidate{ea, eb, cp}, out, visit);
    }
  findEnds(pi, ea, eb, false, visit, s, known, offer);
  findEnds(pi, eb, ea, true, visit, s, known, offer);
}

bool PointContact::acrossFaces(int ea, int eb, const ClosestPoints& cp, const LinePairInput& in, double thinner) const {
  // Two edges' closest points measure the sections' overlap along the edges' common normal. Where
  // that normal lies along one of A's section axes, the sections' overlap along A's other axis tells
  // whether they touch along the normal at all: lying apart (or just touching) along that other axis
  // while overlapping deeper along the normal, the sections are not in contact there. So it is for
  // nearly parallel rectangles bent against each other (two stacked cantilevers, their faces
  // together): the common normal of an edge of A and an edge of B is then horizontal, across the
  // faces' normal, and an edge of A against the far edge of B, 2 apart across a 2-wide section, was
  // found 2 deep (with the blend's weight 0.27) and cycled the active set. The edges of beams crossing
  // at a small angle overlap along the other axis (their point lies on both sections' edges), so
  // they keep their points.
  const auto& elements = geometry_.beams().elements();
  const auto& a = elements[ea];
  const auto& b = elements[eb];
  const auto& secA = geometry_.beams().beams()[a.beam].section;
  const auto& secB = geometry_.beams().beams()[b.beam].section;
  const Mat3d& RA = cp.xi < 0.5 ? in.RA1 : in.RA2;
  const Mat3d& RB = cp.eta < 0.5 ? in.RB1 : in.RB2;
  const Vec3d a2 = RA * column(a.data.T0, 1), a3 = RA * column(a.data.T0, 2);
  const Vec3d b2 = RB * column(b.data.T0, 1), b3 = RB * column(b.data.T0, 2);
  const bool alongWidth = std::abs(dot(cp.normal, a2)) > std::abs(dot(cp.normal, a3));
  const Vec3d other = alongWidth ? a3 : a2;
  // (Only while B's axis lies across that other axis: where B runs along it, as at a crossing at
  // right angles, B's length spans it, not its section.)
  if (std::abs(dot(RB * column(b.data.T0, 0), other)) > 0.1) return false;
  const double halfA = 0.5 * (alongWidth ? secA.height : secA.width);
  const double halfB = 0.5 * (std::abs(dot(b2, other)) * secB.width + std::abs(dot(b3, other)) * secB.height);
  const double apart = std::abs(dot(cp.cB - cp.cA, other)) - halfA - halfB;
  return apart > -0.1 * thinner && apart > cp.gap + 0.1 * thinner;
}

LinePairInput PointContact::endInput(int eE, int end, int eS, int face, const core::State& s, int corner) const {
  LinePairInput in = input(eE, 0, eS, 0, s);
  in.endCorner = corner;
  const auto& E = geometry_.beams().elements()[eE];
  const auto& S = geometry_.beams().elements()[eS];
  const auto& secE = geometry_.beams().beams()[E.beam].section;
  const auto& secS = geometry_.beams().beams()[S.beam].section;
  in.oA = in.oB = Vec3d{};
  in.radiusSum = 0.0;
  in.endNode = end;
  in.outward = end == 0 ? -1.0 : 1.0;
  for (int a = 0; a < 3; ++a) in.endAxes[a] = column(E.data.T0, a);
  if (secE.shape == elements::CrossSection::Shape::Rectangle) {
    in.endRectangle = true;
    in.endHalf[0] = 0.5 * secE.width;
    in.endHalf[1] = 0.5 * secE.height;
  } else {
    in.endRadius = secE.radius;
  }
  if (secS.shape == elements::CrossSection::Shape::Rectangle) {
    // B's face `face`: outward normal +e2, +e3, -e2, -e3 (as line contact's faces)
    const Vec3d axis = column(S.data.T0, 1 + face % 2);
    const double sign = face < 2 ? 1.0 : -1.0;
    in.oB = (sign * 0.5 * (face % 2 == 0 ? secS.width : secS.height)) * axis;
    in.nB = sign * axis;
    in.halfWidthB = 0.5 * (face % 2 == 0 ? secS.height : secS.width);
    in.face = true;
  } else {
    in.radiusB = secS.radius;
    in.acrossB = column(S.data.T0, 1);
  }
  return in;
}

bool PointContact::nearFreeEnd(int e, const Vec3d& x, double reach, const core::State& s) const {
  // Within `reach` of a free end node of element e (an end touching the other beam has its edges'
  // closest points there).
  const auto& E = geometry_.beams().elements()[e];
  for (const int node : {E.node1, E.node2})
    if (geometry_.freeEnd(node) && norm(x - s.position[node]) <= reach) return true;
  return false;
}

void PointContact::findEnds(int pi, int eE, int eS, bool ofB, long long visit, const core::State& s,
                            const PointMap& known, const CandidateOffer& offer) const {
  const auto& E = geometry_.beams().elements()[eE];
  const auto& S = geometry_.beams().elements()[eS];
  const bool rectangles = geometry_.rectangles(pi);
  for (int end = 0; end < 2; ++end) {
    const int node = end == 0 ? E.node1 : E.node2;
    if (!geometry_.freeEnd(node)) continue;
    // A known point keeps its face of B (rectangles); a new one takes the face turned most towards
    // the end's centre.
    int face = 0;
    const ContactPointRecord* have = nullptr;
    bool haveCorners = false;  // (a known corner point of this end: the end stays on its corners)
    for (int f = 0; f < (rectangles ? 4 : 1); ++f) {
      const auto it = known.find(PointKey::endPoint(pi, ofB, end, f));
      if (it != known.end()) {
        have = &it->second;
        face = f;
      }
      for (int c = 0; rectangles && c < 4; ++c)
        if (known.count(PointKey::cornerPoint(pi, ofB, end, f, c))) {
          haveCorners = true;
          face = f;
        }
    }
    // (at the last converged state, so an end that went through B within the increment is found on
    // the face it came through, deeply inside)
    const core::State& r = geometry_.reference();
    if (rectangles && !have && !haveCorners) face = outsideFace(eS, r.position[node], r);
    const LinePairInput in = endInput(eE, end, eS, face, s);
    // The side of a new circular point: where the end's centre lay from B's axis at the last
    // converged state, so an end that passed B's axis within the increment is deeply inside.
    double side = have ? have->sigma : 1.0;
    ClosestPoints cp = endProjection(in, side);
    if (!have && !rectangles) {
      const ClosestPoints ref = endProjection(endInput(eE, end, eS, face, geometry_.reference()), 1.0);
      if (dot(ref.pB - ref.pA, cp.pB - cp.pA) < 0.0) cp = endProjection(in, side = -1.0);
    }
    if (!geometry_.withinElement(eS, cp.eta)) continue;
    if (rectangles) {
      // The face's plane reaches beyond the face: an end beside the face (its centre farther across
      // than the face's half width and the end's circumscribed radius) does not touch it, and a new
      // point for an end beyond B's far face (a gap below minus B's thickness and that radius) is no
      // contact either (an end that went through is the pass-through check's).
      const double endReach = geometry_.circumscribed(E.beam), thickness = 2.0 * faceDepth(eS, face);
      if (std::abs(cp.etaRate) > in.halfWidthB + endReach) continue;
      if (!have && !haveCorners && cp.gap < -(thickness + endReach)) continue;
    }
    // Only an end face turned towards B. Circles: the axis (chord, or Hermite tangent) continued
    // beyond the end passes B on the far side of the end, i.e. the closest points of the axes lie
    // beyond it (otherwise the beam's side near its end faces B: point contact's place).
    // Rectangles: the end's axis points into B's face (against its outward normal).
    const Vec3d axis = geometry_.options().hermitePointAxes ? s.rotation[node] * column(E.data.T0, 0)
                                                            : s.position[E.node2] - s.position[E.node1];
    const Vec3d towards = rectangles ? cp.normal : side * (cp.pB - cp.pA);
    const bool turnedTowards = in.outward * dot(towards, axis) > 0.0;
    // An end past a free end of B's element whose face is turned towards it is end-to-end contact's
    // (its face, not B's side: end on end, the end's axis lies along B's faces).
    if (beyondFreeEnd(eE, node, eS, s)) continue;
    if (rectangles && !have) {
      // A rectangular end whose axis does not point into B's face (it lies along the face), or whose
      // corners towards B do not all lie over the face (it hangs over the face's side), touches B
      // with those of its corners that lie over a face: a point for each ("End corners"). A known
      // corner point keeps the end on its corners (a known end point keeps it on its face).
      // (across the face as the end's offset cp.etaRate is measured: B's axis x the face's normal)
      const auto acrossOf = [&](const ClosestPoints& q) {
        const Vec3d a = cross(s.position[S.node2] - s.position[S.node1], -1.0 * q.normal);
        return (1.0 / norm(a)) * a;
      };
      // (each corner's offset from the end's centre, cp.pA)
      bool hangs = false;
      for (int c = 0; c < 4; ++c) {
        const Vec3d offset = cornerAt(eE, node, c, s) - cp.pA;
        if (dot(offset, cp.normal) > 0.0 && std::abs(cp.etaRate + dot(offset, acrossOf(cp))) > in.halfWidthB)
          hangs = true;
      }
      if (haveCorners || hangs || !turnedTowards) {
        for (int c = 0; c < 4; ++c) {
          // Its face: a known corner point's, else the face whose plane it lay furthest outside at
          // the last converged state (a corner beside B's top face lies inside the plane of B's side).
          int fc = -1;
          for (int f = 0; f < 4; ++f)
            if (known.count(PointKey::cornerPoint(pi, ofB, end, f, c))) fc = f;
          if (fc < 0) fc = outsideFace(eS, cornerAt(eE, node, c, r), r);
          const LinePairInput ic = endInput(eE, end, eS, fc, s, c);
          const ClosestPoints q = endProjection(ic, 1.0);
          const Vec3d offset = q.pA - cp.pA;
          const PointKey key = PointKey::cornerPoint(pi, ofB, end, fc, c);
          const auto it = known.find(key);
          // Only a corner towards that face, over it, on B's element, and (new) not beyond B's far side.
          if (!(dot(offset, q.normal) > 0.0)) continue;
          if (std::abs(q.etaRate + dot(offset, acrossOf(q))) > ic.halfWidthB) continue;
          if (!geometry_.withinElement(eS, q.eta)) continue;
          if (it == known.end() && q.gap < -2.0 * faceDepth(eS, fc)) continue;
          double out = std::abs(q.eta - 0.5);
          if (it != known.end() && it->second.elementA == eE && it->second.elementB == eS && out <= 0.55) out = -1.0;
          offer(key, Candidate{eE, eS, q}, out, visit);
        }
        continue;
      }
    }
    if (!turnedTowards) continue;
    const PointKey key = PointKey::endPoint(pi, ofB, end, face);
    double out = std::abs(cp.eta - 0.5);
    if (have && have->elementA == eE && have->elementB == eS && out <= 0.55 && !handedOver_.count(key)) out = -1.0;
    offer(key, Candidate{eE, eS, cp}, out, visit);
  }
}

double PointContact::faceDepth(int eS, int face) const {
  const auto& sec = geometry_.beams().beams()[geometry_.beams().elements()[eS].beam].section;
  return 0.5 * (face % 2 == 0 ? sec.width : sec.height);
}

int PointContact::outsideFace(int eS, const Vec3d& x, const core::State& s) const {
  const auto& S = geometry_.beams().elements()[eS];
  const Vec3d from = x - 0.5 * (s.position[S.node1] + s.position[S.node2]);
  int face = 0;
  double most = -1e300;
  for (int f = 0; f < 4; ++f) {  // the largest distance from a face's plane
    const Vec3d n = (f < 2 ? 1.0 : -1.0) * (s.rotation[S.node1] * column(S.data.T0, 1 + f % 2));
    const double out = dot(n, from) - faceDepth(eS, f);
    if (out > most) {
      most = out;
      face = f;
    }
  }
  return face;
}

Vec3d PointContact::cornerAt(int eE, int node, int corner, const core::State& s) const {
  // (as LinePairInput::endCorner: bit 0 minus e2, bit 1 minus e3, the end's triad turned with its node)
  const auto& E = geometry_.beams().elements()[eE];
  const auto& sec = geometry_.beams().beams()[E.beam].section;
  const Vec3d local = ((corner & 1 ? -0.5 : 0.5) * sec.width) * column(E.data.T0, 1) +
                      ((corner & 2 ? -0.5 : 0.5) * sec.height) * column(E.data.T0, 2);
  return s.position[node] + s.rotation[node] * local;
}

Vec3d PointContact::outwardAxis(int e, int node, const core::State& s) const {
  const auto& E = geometry_.beams().elements()[e];
  return (node == E.node1 ? -1.0 : 1.0) * (s.rotation[node] * column(E.data.T0, 0));
}

bool PointContact::beyondFreeEnd(int eE, int node, int eS, const core::State& s) const {
  const auto& E = geometry_.beams().elements()[eE];
  const auto& S = geometry_.beams().elements()[eS];
  const Vec3d outE = outwardAxis(eE, node, s);
  for (const int nS : {S.node1, S.node2}) {
    if (!geometry_.freeEnd(nS)) continue;
    const Vec3d outS = outwardAxis(eS, nS, s);
    if (dot(outE, outS) < 0.0 && dot(s.position[node] - s.position[nS], outS) > -geometry_.circumscribed(E.beam))
      return true;
  }
  return false;
}

LinePairInput PointContact::endToEndInput(int eE, int end, int eO, int otherEnd, const core::State& s) const {
  LinePairInput in = endInput(eE, end, eO, 0, s);
  const auto& O = geometry_.beams().elements()[eO];
  const auto& secO = geometry_.beams().beams()[O.beam].section;
  in.face = false;
  in.oB = in.nB = in.acrossB = Vec3d{};
  in.halfWidthB = in.radiusB = 0.0;
  in.otherEnd = otherEnd;
  for (int a = 0; a < 3; ++a) in.otherAxes[a] = (a == 0 && otherEnd == 0 ? -1.0 : 1.0) * column(O.data.T0, a);
  if (secO.shape == elements::CrossSection::Shape::Rectangle) {
    in.otherRectangle = true;
    in.otherHalf[0] = 0.5 * secO.width;
    in.otherHalf[1] = 0.5 * secO.height;
  } else {
    in.otherRadius = secO.radius;
  }
  return in;
}

void PointContact::findEndToEnd(int pi, int ea, int eb, long long visit, const core::State& s, const PointMap& known,
                                const CandidateOffer& offer) const {
  const auto& elems = geometry_.beams().elements();
  const auto& A = elems[ea];
  const auto& B = elems[eb];
  const double rA = geometry_.circumscribed(A.beam), rB = geometry_.circumscribed(B.beam);
  for (int endA = 0; endA < 2; ++endA)
    for (int endB = 0; endB < 2; ++endB) {
      const int nA = endA == 0 ? A.node1 : A.node2, nB = endB == 0 ? B.node1 : B.node2;
      if (!geometry_.freeEnd(nA) || !geometry_.freeEnd(nB)) continue;
      // The larger end face is the plane (the pair's B's on a tie), the other end presses on it; a
      // known point keeps its roles.
      bool ofB = rB < rA;
      const PointKey asA = PointKey::endToEndPoint(pi, false, endA, endB),
                     asB = PointKey::endToEndPoint(pi, true, endB, endA);
      const bool haveA = known.count(asA) > 0, haveB = known.count(asB) > 0;
      if (haveA || haveB) ofB = haveB;
      const int eE = ofB ? eb : ea, eO = ofB ? ea : eb, end = ofB ? endB : endA, other = ofB ? endA : endB;
      const LinePairInput in = endToEndInput(eE, end, eO, other, s);
      const ClosestPoints cp = endToEndProjection(in);
      // Only two end faces turned towards each other: their outward normals opposed, the pressing
      // end's centre in front of the plane (a new point no deeper than its circumscribed radius) and
      // its support point (where it touches) on the other face. (An end hanging over the other
      // face's rim touches that rim with its face: not modelled, refused where the faces overlap.)
      if (!(dot(outwardAxis(ea, nA, s), outwardAxis(eb, nB, s)) < 0.0)) continue;
      const double reach = geometry_.circumscribed(elems[eE].beam);
      if (!(haveA || haveB) && cp.gap < -reach) continue;
      const Vec3d q = cp.pA - cp.cB;
      const Vec3d e2 = s.rotation[ofB ? nA : nB] * in.otherAxes[1], e3 = s.rotation[ofB ? nA : nB] * in.otherAxes[2];
      const double q2 = dot(q, e2), q3 = dot(q, e3);
      const bool within = in.otherRectangle ? std::abs(q2) <= in.otherHalf[0] && std::abs(q3) <= in.otherHalf[1]
                                            : std::hypot(q2, q3) <= in.otherRadius;
      if (!within) continue;
      offer(ofB ? asB : asA, Candidate{eE, eO, cp}, -1.0, visit);
    }
}

ClosestPoints PointContact::geometry(const ContactPointRecord& p, const core::State& s) const {
  if (p.key.endToEnd())
    return endToEndProjection(endToEndInput(p.elementA, p.key.endIndex(), p.elementB, p.key.otherEnd(), s));
  if (p.end())
    return endProjection(endInput(p.elementA, p.key.endIndex(), p.elementB, p.key.endFace(), s, p.key.cornerIndex()),
                         p.sigma);
  const LinePairInput in = input(p.elementA, p.key.lineA, p.elementB, p.key.lineB, s);
  ClosestPoints cp = closestPoints(in);
  orient(cp, p.sigma, in.radiusSum);
  return cp;
}

double PointContact::rivalAngle(const ContactPointRecord& p, const ClosestPoints& cp, const core::State& s,
                                double tolerance, double* initialKink) const {
  if (initialKink) *initialKink = 0.0;
  if (p.end() || p.line() || p.node()) return 0.0;
  const auto& elements = geometry_.beams().elements();
  // The angle at which two elements of a beam meet on the smoothed Hermite axes in the initial shape:
  // zero where the node's tangent is shared (a polyline's gentle bend: an arc, a helix, a weave's
  // undulation), the elements' angle at a corner (ContactGeometry::kCornerAngle), which Hermite axes
  // keep; the chords have every initial angle and what the bending adds.
  const auto kink = [&](int e, int n) { return geometry_.smoothedKink(e, n < e ? 0 : 1); };
  // The element beside e across its node nearer to the parameter t (-1: none, a beam's end).
  const auto beside = [&](int e, double t) {
    const int n = t < 0.5 ? e - 1 : e + 1;
    return n >= 0 && n < static_cast<int>(elements.size()) && elements[n].beam == elements[e].beam ? n : -1;
  };
  const int na = beside(p.elementA, cp.xi), nb = beside(p.elementB, cp.eta);
  double angle = 0.0;
  for (const auto& [ea, eb] : {std::pair{na, p.elementB}, std::pair{p.elementA, nb}, std::pair{na, nb}}) {
    if (ea < 0 || eb < 0) continue;
    const LinePairInput in = input(ea, p.key.lineA, eb, p.key.lineB, s);
    ClosestPoints q = closestPoints(in);
    if (q.sinAngle < geometry_.options().minimumSinAngle || !geometry_.withinElement(ea, q.xi) ||
        !geometry_.withinElement(eb, q.eta))
      continue;
    orient(q, p.sigma, in.radiusSum);
    if (q.gap > cp.gap + tolerance) continue;
    angle = std::max(angle, std::acos(std::clamp(dot(q.normal, cp.normal), -1.0, 1.0)));
    if (initialKink)
      *initialKink = std::max(
          {*initialKink, ea != p.elementA ? kink(p.elementA, ea) : 0.0, eb != p.elementB ? kink(p.elementB, eb) : 0.0});
  }
  return angle;
}

ContactKinematics PointContact::kinematics(const ContactPointRecord& p, const core::State& s, Variations order) const {
  if (p.key.endToEnd())
    return endToEndKinematics(endToEndInput(p.elementA, p.key.endIndex(), p.elementB, p.key.otherEnd(), s), p.etaRate,
                              p.across2, order);
  if (p.end())
    return endKinematics(endInput(p.elementA, p.key.endIndex(), p.elementB, p.key.endFace(), s, p.key.cornerIndex()),
                         p.sigma, p.etaPrev - geometry_.beams().elements()[p.elementB].index, p.etaRate, order);
  const LinePairInput in = input(p.elementA, p.key.lineA, p.elementB, p.key.lineB, s);
  const double xiPrev = p.xiPrev - geometry_.beams().elements()[p.elementA].index;
  const double etaPrev = p.etaPrev - geometry_.beams().elements()[p.elementB].index;
  return contactKinematics(in, p.sigma, xiPrev, etaPrev, order);
}

}  // namespace bc::constraints
