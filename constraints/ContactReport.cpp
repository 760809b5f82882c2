#include "ContactReport.hpp"

#include <cmath>
#include <functional>
#include <iomanip>
#include <limits>
#include <sstream>

namespace bc::constraints {

namespace {
// A line point whose applied force has |F_T| > mu |F_N| + this |F_N| is reported. Every strategy's
// multipliers satisfy the cone and a Gauss point applies them along unit vectors (docs/contact.md, "The
// Coulomb cone on lines"): Penalty's per Gauss point, a multiplier field's on its nodes, whose friction
// rows are their own (LineContact::evaluateNodal), and so at every point between them. A point outside
// is a strategy's fault (a plug-in's nodal field whose rows do not keep its nodes in the cone).
constexpr double kOutsideCone = 1e-9;
constexpr double kOutsidePointCone = 1e-6;
// Pairs named one by one in a warning that many pairs share (ContactReport::warnings).
constexpr std::size_t kListedPairs = 3;
}  // namespace

void ContactReport::noteCone(const ContactPointRecord& p, double friction) {
  // (A frictionless pair applies no friction force: the tangential part of its line points' force is
  // that of the gap's gradient off the reported normal, up to 1.6e-4 of N where rectangles cross at
  // 1 to 3 degrees near held ends (measured), and no cone is left.)
  if (friction == 0.0) return;
  const double N = norm(p.normalForce), T = norm(p.tangentialForce);
  if (!(T > (friction + kOutsideCone) * N)) return;
  // A point contact's friction is settled by Newton's own rows (Isotropic Coulomb's complementarity
  // function) to Newton's tolerance: the 16 x 16 layers with Lagrange multipliers reached 1 + 1.6e-8
  // of mu N at an iterate; beyond a millionth is the force's, not the solve's.
  if (!p.line() && !(T > friction * N * (1.0 + kOutsidePointCone))) return;
  const double ratio = friction > 0.0 && N > 0.0 ? T / (friction * N) : std::numeric_limits<double>::infinity();
  auto& worst = (p.line() ? outsideCone_ : pointsOutsideCone_)[p.key.pair];
  if (ratio > worst.first) worst = {ratio, p.position};
}

void ContactReport::noteDepth(const ContactPointRecord& p, const ClosestPoints& cp) {
  const double depth = -cp.gap, inscribed = geometry_.thinner(p.key.pair);
  if (depth > kDeep * inscribed) {
    auto& worst = deepPoints_[p.key.pair];
    if (depth > worst.first) worst = {depth, geometry_.touching(p, cp)};
  }
}

void ContactReport::noteRival(const ContactPointRecord& p, double angle, double initialKink) {
  if (!(angle > kRivalAngle)) return;
  auto& worst = rivals_[p.key.pair];
  if (angle > worst.first) {
    worst = {angle, p.position};
    rivalKinks_[p.key.pair] = initialKink;
  }
}

std::string ContactReport::tableHeader() const {
  std::string header =
      "pair,line_A,line_B,beam_A_coordinate,beam_B_coordinate,x,y,z,gap,normal_force,tangential_force_1,"
      "tangential_force_2,state_1,state_2,active,normal_x,normal_y,normal_z,normal_force_x,normal_force_y,"
      "normal_force_z,tangential_force_x,tangential_force_y,tangential_force_z,tangential_force,element_A,element_B,"
      "line_traction";
  for (const std::string& column : enforcer_.outputColumns()) header += "," + column;
  return header;
}

std::vector<std::string> ContactReport::tableRows(const PointMap& committed) const {
  std::vector<std::string> rows;
  for (const auto& [key, p] : committed) {
    if (p.node()) continue;
    std::ostringstream s;
    s.precision(12);
    const auto state = [&](int i) { return !p.result.active ? "open" : (p.result.slip[i] ? "slip" : "stick"); };
    const auto code = p.key.code();
    // (A point with swapped roles, on an edge of beam B: its coordinates and elements as the pair's.)
    const bool swapped = geometry_.swapped(p);
    s << geometry_.pairs()[p.key.pair].name << "," << code[1] << "," << code[2] << ","
      << (swapped ? p.etaPrev : p.xiPrev) << "," << (swapped ? p.xiPrev : p.etaPrev) << "," << p.position[0] << ","
      << p.position[1] << "," << p.position[2] << "," << p.gap << "," << -p.result.lambdaN << "," << p.result.lambdaT[0]
      << "," << p.result.lambdaT[1] << "," << state(0) << "," << state(1) << "," << (p.result.active ? 1 : 0);
    for (const Vec3d* v : {&p.normal, &p.normalForce, &p.tangentialForce})
      for (int a = 0; a < 3; ++a) s << "," << (*v)[a];
    s << "," << norm(p.tangentialForce);
    // The segment (the elements, within their beams, the point lies on) and, for a line point, its
    // normal force per unit length of line A (0 for point contacts).
    const auto& elems = geometry_.beams().elements();
    const auto [onA, onB] = geometry_.pairElements(p);
    s << "," << elems[onA].index << "," << elems[onB].index << ","
      << (p.line() && p.length > 0.0 ? -p.result.lambdaN / p.length : 0.0);
    // The strategy's own columns (the built-in ones: the penalty parameters the point used, 0 for none
    // or where it carried no force).
    const std::size_t columns = enforcer_.outputColumns().size();
    for (std::size_t c = 0; c < columns; ++c) s << "," << (c < p.outputs.size() ? p.outputs[c] : 0.0);
    rows.push_back(s.str());
  }
  return rows;
}

void ContactReport::appendVtk(const PointMap& committed, core::VtkMesh& mesh) const {
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
  const auto& elems = geometry_.beams().elements();
  for (const auto& [key, p] : committed) {
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
    const auto [onA, onB] = geometry_.pairElements(p);
    mesh.setPointScalar("segment element A", point, elems[onA].index);
    mesh.setPointScalar("segment element B", point, elems[onB].index);
    mesh.cellTypes.push_back(1);  // VTK_VERTEX
    mesh.cells.push_back({point});
    mesh.cellBeam.push_back(-1);
    mesh.cellElement.push_back(-1);
  }
}

std::vector<std::string> ContactReport::warnings() const {
  std::vector<std::string> w;
  const auto& pairs = geometry_.pairs();
  if (const std::string relaxed = penalty_.warning(); !relaxed.empty()) w.push_back(relaxed);
  // A kind of warning that many pairs share (a weave's every crossing at a bent node) is one line: its
  // worst pair's, with how many pairs and the first few named (kListedPairs).
  const auto perPair = [&](const std::map<int, std::pair<double, Vec3d>>& worst,
                           const std::function<std::string(int pair, double value, const Vec3d& at)>& text) {
    if (worst.size() <= kListedPairs) {
      for (const auto& [pair, v] : worst)
        w.push_back("contact pair \"" + pairs[pair].name + "\": " + text(pair, v.first, v.second));
      return;
    }
    auto top = worst.begin();
    for (auto it = worst.begin(); it != worst.end(); ++it)
      if (it->second.first > top->second.first) top = it;
    std::ostringstream s;
    s << worst.size() << " contact pairs (";
    int listed = 0;
    for (const auto& [pair, v] : worst) {
      if (listed == static_cast<int>(kListedPairs)) break;
      s << (listed++ ? ", " : "") << "\"" << pairs[pair].name << "\"";
    }
    s << ", ...), the worst pair \"" << pairs[top->first].name
      << "\": " << text(top->first, top->second.first, top->second.second);
    w.push_back(s.str());
  };
  perPair(deepPoints_, [&](int pair, double depth, const Vec3d& at) {
    std::ostringstream s;
    s << "the beams penetrated each other by up to " << depth << " (" << 100.0 * depth / geometry_.thinner(pair)
      << " % of the thinner section's inscribed radius) near (" << at[0] << ", " << at[1] << ", " << at[2]
      << "), more than " << 100.0 * kDeep
      << " %: the sections overlap visibly there, so the forces are those of a soft contact law, not of contact; "
         "raise the Normal Penalty Parameter (or lower a Regularization Gap comparable to this depth, or use Augmented "
         "Lagrange or Lagrange Multiplier)";
    return s.str();
  });
  perPair(rivals_, [&](int pair, double angle, const Vec3d& at) {
    const double degrees = angle * 180.0 / M_PI;
    const auto kink = rivalKinks_.find(pair);
    const double initial = kink == rivalKinks_.end() ? 0.0 : kink->second;
    std::ostringstream s;
    s << "a point contact lay at a node where a beam's straight elements meet at an angle, near (" << at[0] << ", "
      << at[1] << ", " << at[2]
      << "): the elements on both sides of the node each hold a closest point about as close, with normals up to "
      << degrees << " degrees apart; the point takes one element's, so its force leans across the beams by up to "
      << 0.5 * degrees << " degrees to that element's side (a symmetric model can answer unsymmetrically); ";
    // (Hermite axes keep a corner of the initial shape: refining does not help there either.)
    if (initial > kRivalAngle)
      s << "the beam's elements met at " << initial * 180.0 / M_PI
        << " degrees there in its initial shape, a corner (beyond " << ContactGeometry::kCornerAngle * 180.0 / M_PI
        << " degrees) that Hermite axes keep too: the contact at a corner is that of two straight beams";
    else s << "set Contact/Point Contact Axes = Hermite (smooth across nodes), or refine the beams";
    return s.str();
  });
  lineWarnings(w);
  for (int pair : lines_.frictionless()) {
    std::ostringstream s;
    s << "contact pair \"" << pairs[pair].name << "\" has friction coefficient " << pairs[pair].friction
      << ", and its beams were in line contact (nearly parallel): ";
    s << "friction acted along the axes only; sliding across them (perpendicular to both axes) is frictionless";
    w.push_back(s.str());
  }
  return w;
}

void ContactReport::lineWarnings(std::vector<std::string>& w) const {
  const auto& pairs = geometry_.pairs();
  const auto& beams = geometry_.beams().beams();
  for (const auto& [pair, worst] : lines_.unseenBetween()) {
    std::ostringstream s;
    s << "contact pair \"" << pairs[pair].name << "\": between the Gauss points of line contact the beams "
      << "overlapped by up to " << worst.first << " more than at any Gauss point, near (" << worst.second[0] << ", "
      << worst.second[1] << ", " << worst.second[2] << ") (more than " << kUnresolvedLine
      << " of the thinner section's inscribed radius): the contact zone there is shorter than the Gauss points' "
         "spacing (axes "
         "crossing at a small angle), so part of the contact was not seen; raise Contact/Line Gauss Points or "
         "refine beam \""
      << beams[pairs[pair].beamA].name << "\"";
    w.push_back(s.str());
  }
  for (const auto& [pair, worst] : lines_.unresolved()) {
    std::ostringstream s;
    s << "contact pair \"" << pairs[pair].name << "\": " << enforcer_.type()
      << " enforces line contact on gaps weighted over the elements of beam \"" << beams[pairs[pair].beamA].name
      << "\", and between its nodes the beams penetrated by up to " << worst.first << " near (" << worst.second[0]
      << ", " << worst.second[1] << ", " << worst.second[2] << "), more than " << kUnresolvedLine
      << " of the thinner section's inscribed radius: the contact zone there is short against the elements (beams "
         "crossing at a "
         "small angle, or a beam end on the other beam), so the contact force is not resolved; refine beam \""
      << beams[pairs[pair].beamA].name
      << "\" or use Penalty with Line Springs = Gauss Points (whose Gauss points each hold their own gap)";
    w.push_back(s.str());
  }
  for (const auto& [pair, held] : lines_.heldEnds()) {
    std::ostringstream s;
    const std::string beamA = beams[pairs[pair].beamA].name;
    s << std::setprecision(3) << "contact pair \"" << pairs[pair].name << "\": supports hold both beams near ("
      << held.at[0] << ", " << held.at[1] << ", " << held.at[2]
      << "), where their slopes turned the contact normal so that the gap they hold there is " << held.gap
      << ", a penetration that no contact force can remove (the force there goes into the supports and is set by "
         "the strategy and the mesh, not by the beams): ";
    if (held.excess > 0.0)
      s << "the contact points on beam \"" << beamA << "\"'s end element there carry " << held.excess
        << " per length beyond the mean traction " << held.mean << " (" << held.excess / held.mean << " times it)";
    if (held.excess > 0.0 && held.traction > 0.0) s << "; ";
    if (held.traction > 0.0)
      s << enforcer_.type() << "'s rigid line contact closes it within an element of beam \"" << beamA
        << "\" with tractions of about E I |g| / h^4 = " << held.traction << " (" << 100.0 * held.traction / held.mean
        << " % of the mean traction " << held.mean
        << "), which grow as h^-4 when the beams are refined, and so do the errors of the contact force and the "
           "reactions";
    s << "; hold only one of the two beams there"
      << (lines_.nodal() && enforcer_.type() != "Penalty" ? ", or use Penalty (which takes the gap with a force eps_N "
                                                            "|g|)"
                                                          : ", or lower the penalty (which takes the gap with a force "
                                                            "eps_N |g|)");
    w.push_back(s.str());
  }
  for (const auto& [pair, worst] : outsideCone_) {
    std::ostringstream s;
    s << "contact pair \"" << pairs[pair].name << "\": a Gauss point of line contact applied a tangential force of "
      << worst.first << " times mu times its normal force near (" << worst.second[0] << ", " << worst.second[1] << ", "
      << worst.second[2]
      << "): outside the Coulomb cone. The built-in strategies keep every line point's force in the cone "
      << "(Penalty at each Gauss point, the multiplier fields of Lagrange and Augmented Lagrange on their nodes, "
      << "between which the force is interpolated); a strategy of your own with a nodal field must keep its "
      << "nodes' multipliers in the cone (docs/contact.md, \"The Coulomb cone on lines\")";
    w.push_back(s.str());
  }
  for (const auto& [pair, worst] : pointsOutsideCone_) {
    std::ostringstream s;
    s << "contact pair \"" << pairs[pair].name << "\": a contact point applied a tangential force of " << worst.first
      << " times mu times its normal force near (" << worst.second[0] << ", " << worst.second[1] << ", "
      << worst.second[2]
      << "): outside the Isotropic Coulomb cone. The built-in strategies keep a point contact's multipliers "
         "on the cone, and its slips make the force they apply the law's (on the chords and on the Hermite "
         "axes, to round-off); a strategy of your own must keep its multipliers in the cone of the law's "
         "metric (docs/contact.md, \"Friction law\")";
    w.push_back(s.str());
  }
}

std::string ContactReport::progressSummary(const PointMap& committed, int lastPasses) const {
  // (Stick and slip are counted on pairs with friction only: a frictionless point's lines neither stick
  // nor slip.)
  int active = 0, stick = 0, slip = 0;
  bool friction = false;
  for (const auto& [key, p] : committed) {
    if (!p.result.active || p.node()) continue;
    ++active;
    if (!(geometry_.pairs()[p.key.pair].friction > 0.0)) continue;
    friction = true;
    for (int i = 0; i < 2; ++i) (p.result.slip[i] ? slip : stick)++;
  }
  std::ostringstream s;
  s << "contact " << active;
  if (friction) s << " (stick " << stick << ", slip " << slip << " lines)";
  if (enforcer_.maximumPasses() > 1) s << ", passes " << lastPasses;
  return s.str();
}

}  // namespace bc::constraints
