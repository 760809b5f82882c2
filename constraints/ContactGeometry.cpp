#include "ContactGeometry.hpp"

#include <algorithm>
#include <map>

#include "core/Faults.hpp"
#include "core/Parameters.hpp"

namespace bc::constraints {

using elements::BeamElement;
using elements::CrossSection;

ContactGeometry::ContactGeometry(std::shared_ptr<const elements::BeamSet> beams, std::vector<ContactPairSpec> pairs,
                                 ContactOptions options, bool lineContact)
    : beams_(std::move(beams)), pairs_(std::move(pairs)), options_(std::move(options)), lineContact_(lineContact) {
  for (std::size_t i = 0; i < pairs_.size(); ++i)
    pairIndex_[beamPairKey(pairs_[i].beamA, pairs_[i].beamB)] = static_cast<int>(i);
  for (const auto& [a, b] : options_.joinedNodes) {
    joined_.insert({a, b});
    joined_.insert({b, a});
  }
  // The elements' ends at each node, (element, its end 0 or 1): a free end has one, and no pin.
  const auto& elems = beams_->elements();
  std::map<int, std::vector<std::pair<int, int>>> ends;
  for (std::size_t e = 0; e < elems.size(); ++e) {
    ends[elems[e].node1].emplace_back(static_cast<int>(e), 0);
    ends[elems[e].node2].emplace_back(static_cast<int>(e), 1);
  }
  for (const auto& [node, at] : ends)
    if (at.size() == 1 &&
        std::none_of(joined_.begin(), joined_.end(), [&, node = node](const auto& j) { return j.first == node; }))
      freeEnd_.insert(node);
  for (const auto& b : beams_->beams()) {
    inscribed_.push_back(b.section.shape == CrossSection::Shape::Rectangle
                             ? 0.5 * std::min(b.section.width, b.section.height)
                             : b.section.radius);
    circumscribed_.push_back(b.section.shape == CrossSection::Shape::Rectangle
                                 ? 0.5 * std::hypot(b.section.width, b.section.height)
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
  // Smoothed axes: a node of exactly two elements (inside a beam, or where two beams are joined end to
  // end at one node) has one tangent, the bisector of the two elements' directions through it.
  nodeTangents_.resize(elems.size());
  kinkLeft_.assign(elems.size(), {0.0, 0.0});
  for (std::size_t e = 0; e < elems.size(); ++e)
    nodeTangents_[e] = {column(elems[e].data.T0, 0), column(elems[e].data.T0, 0)};
  for (const auto& [node, at] : ends) {
    if (at.size() != 2) continue;
    const auto [e, ke] = at[0];
    const auto [f, kf] = at[1];
    // The directions of travel from e through the node into f, along each element.
    const Vec3d de = (ke == 1 ? 1.0 : -1.0) * column(elems[e].data.T0, 0);
    const Vec3d df = (kf == 0 ? 1.0 : -1.0) * column(elems[f].data.T0, 0);
    const double angle = std::acos(std::clamp(dot(de, df), -1.0, 1.0));
    if (angle > kCornerAngle) {
      kinkLeft_[e][ke] = kinkLeft_[f][kf] = angle;
      continue;
    }
    const Vec3d t = (1.0 / norm(de + df)) * (de + df);
    nodeTangents_[e][ke] = (ke == 1 ? 1.0 : -1.0) * t;
    nodeTangents_[f][kf] = (kf == 0 ? 1.0 : -1.0) * t;
  }
  for (const auto& p : pairs_) {
    const bool rA = beams_->beams()[p.beamA].section.shape == CrossSection::Shape::Rectangle;
    const bool rB = beams_->beams()[p.beamB].section.shape == CrossSection::Shape::Rectangle;
    if (rA != rB)
      throw core::InputError("contact pair \"" + p.name +
                             "\": contact between a rectangular and a circular section is not supported");
  }
}

double ContactGeometry::beamCoordinate(int element, double xi) const { return beams_->elements()[element].index + xi; }

bool ContactGeometry::blends(int pair) const {
  // Both circular, or both rectangular (a mixed pair is refused at construction).
  return lineContact_;
}

std::pair<double, double> ContactGeometry::blendAngles(int pair) const {
  // Circular sections: the deck's angles. Rectangular ones: their edges' point contact holds down to
  // small angles (crossings at 0.1 .. 12 degrees complete), while the face contact's edges missed
  // B's edges on A's face at a crossing when only A's edges took part (crossings at 4 .. 12 degrees
  // failed at first contact with the deck's angles; with B's edges taking part, crossings at 1 and 2
  // degrees pressed with friction still stop: Lagrange's rows on both beams' edges become dependent):
  // line contact only where the edges are parallel within Parallel Line Tolerance, and the blend up
  // to twice that angle.
  if (!rectangles(pair)) return {options_.lineAngle, options_.pointAngle};
  const double parallel = std::asin(std::min(1.0, options_.minimumSinAngle));
  return {parallel, 2.0 * parallel};
}

bool ContactGeometry::rectangles(int pair) const {
  return beams_->beams()[pairs_[pair].beamA].section.shape == CrossSection::Shape::Rectangle;
}

double ContactGeometry::axisAngle(int elementA, int elementB, const core::State& s) const {
  const BeamElement &a = beams_->elements()[elementA], &b = beams_->elements()[elementB];
  const Vec3d tA = s.position[a.node2] - s.position[a.node1], tB = s.position[b.node2] - s.position[b.node1];
  return std::acos(std::min(1.0, std::abs(dot(tA, tB)) / (norm(tA) * norm(tB))));
}

bool ContactGeometry::inLineContact(int pair, int elementA, int elementB) const {
  // Line points exist up to a margin beyond the point-contact angle (their weight is 0 there), so a
  // pair whose angle closes within an increment finds them.
  if (!blends(pair)) return false;
  const auto [lo, hi] = blendAngles(pair);
  return axisAngle(elementA, elementB, reference_) < hi + 0.5 * (hi - lo) ||
         (!lineGates_.empty() && lineGates_.count({pair, elementA, elementB}) > 0);
}

bool ContactGeometry::inPointContact(int pair, int elementA, int elementB) const {
  if (!blends(pair)) return true;
  return axisAngle(elementA, elementB, reference_) > 0.5 * blendAngles(pair).first ||
         (!pointGates_.empty() && pointGates_.count({pair, elementA, elementB}) > 0);
}

int ContactGeometry::openGates(const std::vector<std::tuple<int, int, int>>& elementPairs, const core::State& s) {
  int opened = 0;
  for (const auto& [pair, a, b] : elementPairs) {
    if (!blends(pair)) continue;
    const auto [lo, hi] = blendAngles(pair);
    const double angle = axisAngle(a, b, s);
    if (angle < hi + 0.5 * (hi - lo) && !inLineContact(pair, a, b) && lineGates_.insert({pair, a, b}).second) ++opened;
    if (angle > 0.5 * lo && !inPointContact(pair, a, b) && pointGates_.insert({pair, a, b}).second) ++opened;
  }
  return opened;
}

double ContactGeometry::blendWeight(const ContactPointRecord& p, double cosine, const double* cosineR,
                                    Vector24* gradient) const {
  // zeta(alpha) = (1 - cos(pi (alpha - alpha_l) / (alpha_p - alpha_l))) / 2 between the two angles,
  // 0 below alpha_l, 1 above alpha_p: C1 in alpha. A point contact carries zeta, a line point 1 - zeta.
  if (gradient) gradient->fill(0.0);
  // (An end-to-end point is no point contact of two lines: two ends meet with their axes in line.)
  if (!blends(p.key.pair) || p.key.endToEnd()) return 1.0;
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
  // A rectangular end lying along the other beam's face within line contact's angles: a nodal field
  // holds it there (its weighted gaps are enforced whatever the blend's weight, and a free end of B
  // inside A's element has a point of its own: LineContact::offerSegment), and an end point beside it
  // made Lagrange's rows dependent (the end point's gap a combination of the field's rows at the end:
  // the 2 x 1 rectangles lying parallel stopped at T = 0.96 on a singular matrix, the end point's
  // weight 0.005). The end point takes part only beyond the blend.
  if (nodalLineField_ && p.end() && rectangles(p.key.pair)) return zeta < 1.0 ? 0.0 : 1.0;
  const double sign = p.line() ? -1.0 : 1.0;
  if (gradient && dzeta != 0.0 && c < 1.0) {
    // d alpha / d cosine = -sign(cosine) / sqrt(1 - cosine^2)
    const double dAlpha = -(cosine >= 0.0 ? 1.0 : -1.0) / std::sqrt(1.0 - c * c);
    for (int i = 0; i < kPairDofs; ++i) (*gradient)[i] = sign * dzeta * dAlpha * cosineR[i];
  }
  return p.line() ? 1.0 - zeta : zeta;
}

bool ContactGeometry::withinElement(int element, double xi) const {
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

bool ContactGeometry::nearElement(int element, double xi) const {
  // Within one element length of the element and not beyond its beam's ends.
  const BeamElement& e = beams_->elements()[element];
  const int count = static_cast<int>(beams_->beams()[e.beam].nodes.size()) - 1;
  const double b = e.index + xi;
  return xi >= -1.0 && xi <= 2.0 && b >= -1e-9 && b <= count + 1e-9;
}

LinePairInput ContactGeometry::lineInput(int eA, int lA, int eB, int lB, const core::State& s) const {
  const BeamElement& a = beams_->elements()[eA];
  const BeamElement& b = beams_->elements()[eB];
  const Line& la = lines_[a.beam][lA];
  const Line& lb = lines_[b.beam][lB];
  LinePairInput in;
  in.xA1 = s.position[a.node1];
  in.xA2 = s.position[a.node2];
  in.xB1 = s.position[b.node1];
  in.xB2 = s.position[b.node2];
  in.RA1 = s.rotation[a.node1];
  in.RA2 = s.rotation[a.node2];
  in.RB1 = s.rotation[b.node1];
  in.RB2 = s.rotation[b.node2];
  in.oA = la.cy * column(a.data.T0, 1) + la.cz * column(a.data.T0, 2);
  in.oB = lb.cy * column(b.data.T0, 1) + lb.cz * column(b.data.T0, 2);
  in.radiusSum = la.radius + lb.radius;
  in.radiusA = la.radius;
  in.dA = a.data.L0 * column(a.data.T0, 0);
  in.dB = b.data.L0 * column(b.data.T0, 0);
  return in;
}

void ContactGeometry::pointContactAxes(LinePairInput& in, int eA, int eB) const {
  if (!options_.hermitePointAxes) {
    in.dA = in.dB = in.dA2 = in.dB2 = Vec3d{};
    return;
  }
  const BeamElement& a = beams_->elements()[eA];
  const BeamElement& b = beams_->elements()[eB];
  in.dA = a.data.L0 * nodeTangents_[eA][0];
  in.dA2 = a.data.L0 * nodeTangents_[eA][1];
  in.dB = b.data.L0 * nodeTangents_[eB][0];
  in.dB2 = b.data.L0 * nodeTangents_[eB][1];
}

LinePairInput ContactGeometry::axisInput(int eA, int eB, const core::State& s) const {
  LinePairInput in = lineInput(eA, 0, eB, 0, s);
  in.oA = in.oB = Vec3d{};
  in.radiusSum = 0.0;
  in.dA = in.dB = Vec3d{};  // the chords (the pass-through check)
  return in;
}

std::array<core::GlobalDof, kPairDofs> ContactGeometry::pointDofs(const ContactPointRecord& p) const {
  const auto& a = beams_->elements()[p.elementA];
  const auto& b = beams_->elements()[p.elementB];
  const int nodes[4] = {a.node1, a.node2, b.node1, b.node2};
  std::array<core::GlobalDof, kPairDofs> d;
  for (int n = 0; n < 4; ++n)
    for (int k = 0; k < 6; ++k) d[6 * n + k] = core::GlobalDof(core::kDofsPerNode) * nodes[n] + k;
  return d;
}

ContactPoint ContactGeometry::strategyView(const ContactPointRecord& p, const ContactKinematics& k,
                                           const core::State& state) const {
  // Line points have friction along the axes (their g_T2); across the axes (g_T1) only circles' (the
  // surfaces' slip, LinePairInput::turnSlip) with the isotropic law (acrossFriction).
  // End points have no contact line of their own to take friction along: the Per Line law (two
  // independent Coulomb laws along the two lines) does not apply to them; their friction is isotropic.
  ContactPoint view{k, pairs_[p.key.pair].friction, p.end() ? FrictionLaw::IsotropicCoulomb : options_.frictionLaw,
                    pointMultipliers(p, state), blendWeight(p, k.axesCosine, nullptr, nullptr)};
  if (p.line()) view.measured[0] = acrossFriction(p.key.pair) && movesAcross(p, k);
  view.frictionRelaxation = frictionRelaxation_;
  return view;
}

bool ContactGeometry::acrossFriction(int pair) const {
  return !rectangles(pair) && options_.frictionLaw == FrictionLaw::IsotropicCoulomb;
}

bool ContactGeometry::movesAcross(const ContactPointRecord& p, const ContactKinematics& k) const {
  double largest = 0.0;
  for (double v : k.tangent1.R) largest = std::max(largest, std::abs(v));
  if (largest == 0.0) return true;  // (values without variations: a point judged by its gap alone)
  const auto& a = beams_->elements()[p.elementA];
  const auto& b = beams_->elements()[p.elementB];
  const int nodes[4] = {a.node1, a.node2, b.node1, b.node2};
  for (int m = 0; m < 4; ++m) {
    const auto it = options_.heldNodes.find(nodes[m]);
    for (int c = 0; c < 6; ++c)
      if ((it == options_.heldNodes.end() || !it->second[c]) && std::abs(k.tangent1.R[6 * m + c]) > 1e-9 * largest)
        return true;
  }
  return false;
}

}  // namespace bc::constraints
