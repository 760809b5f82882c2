#include "PointContact.hpp"

#include <algorithm>

namespace bc::constraints {

LinePairInput PointContact::input(int eA, int lA, int eB, int lB, const core::State& s) const {
  LinePairInput in = geometry_.lineInput(eA, lA, eB, lB, s);
  if (!geometry_.options().hermitePointAxes) in.dA = in.dB = Vec3d{};
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
      // A known point stays on its element pair while its closest points lie within the
      // elements or up to kStay of an element length beyond a shared node; it is handed to a
      // neighbour only beyond that, so a point at a node cannot flip between elements from one
      // iteration to the next. Otherwise the candidate most central in its elements wins.
      constexpr double kStay = 0.05;
      double out = std::max(std::abs(cp.xi - 0.5), std::abs(cp.eta - 0.5));
      if (it != known.end() && it->second.elementA == ea && it->second.elementB == eb && out <= 0.5 + kStay) out = -1.0;
      offer(key, Candidate{ea, eb, cp}, out, visit);
    }
}

ClosestPoints PointContact::geometry(const ContactPointRecord& p, const core::State& s) const {
  const LinePairInput in = input(p.elementA, p.key.lineA, p.elementB, p.key.lineB, s);
  ClosestPoints cp = closestPoints(in);
  orient(cp, p.sigma, in.radiusSum);
  return cp;
}

ContactKinematics PointContact::kinematics(const ContactPointRecord& p, const core::State& s, Variations order) const {
  const LinePairInput in = input(p.elementA, p.key.lineA, p.elementB, p.key.lineB, s);
  const double xiPrev = p.xiPrev - geometry_.beams().elements()[p.elementA].index;
  const double etaPrev = p.etaPrev - geometry_.beams().elements()[p.elementB].index;
  return contactKinematics(in, p.sigma, xiPrev, etaPrev, order);
}

}  // namespace bc::constraints
