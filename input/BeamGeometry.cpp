// The nodes of a beam along its geometry: a straight line (Start and End), a polyline (Points), a
// circular arc (Arc) or a helix (Helix), with its default section orientation.
#include "BeamGeometry.hpp"

#include <cmath>
#include <string>

#include <Teuchos_Array.hpp>

namespace bc::input {

using core::InputError;
using core::ParameterSpec;
using elements::Vec3d;
using Teuchos::Array;
using Teuchos::ParameterList;

namespace {
Array<double> zero3() { return Array<double>(3, 0.0); }
// An array of the values given (examples of the reference).
Array<double> values(std::initializer_list<double> v) { return Array<double>(v.begin(), v.end()); }
}  // namespace

const ParameterSpec& arcSpec() {
  static const ParameterSpec s = [] {
    ParameterSpec p;
    p.addRequired("Centre", zero3(), "centre of the circle [length]", core::vector3());
    p.addRequired("Radius", 1.0, "radius [length]", core::positive(), "> 0");
    p.addRequired("Normal", values({0, 0, 1}), "normal of the arc's plane; angles turn about it (right hand)",
                  core::vector3());
    p.addRequired("Reference Direction", values({1, 0, 0}), "direction of angle 0 (projected on the plane)",
                  core::vector3());
    p.addRequired("Start Angle", 0.0, "angle of the first node [degrees]");
    p.addRequired("End Angle", 90.0, "angle of the last node [degrees]; |End - Start| <= 360");
    return p;
  }();
  return s;
}

const ParameterSpec& helixSpec() {
  static const ParameterSpec s = [] {
    ParameterSpec p;
    p.addRequired("Axis Point", zero3(), "a point of the helix axis, where the first node's height is 0 [length]",
                  core::vector3());
    p.addRequired("Axis Direction", values({0, 0, 1}), "direction of the axis; the helix turns about it (right hand)",
                  core::vector3());
    p.addRequired("Radius", 1.0, "radius [length]", core::positive(), "> 0");
    p.addRequired("Pitch", 1.0, "rise along the axis per turn [length]", core::positive(), "> 0");
    p.addRequired("Turns", 1.0, "number of turns (any positive real)", core::positive(), "> 0");
    p.addRequired("Reference Direction", values({1, 0, 0}), "direction of the first node from the axis (projected)",
                  core::vector3());
    p.add("Start Angle", 0.0, "angle of the first node from the reference direction [degrees]");
    return p;
  }();
  return s;
}

namespace {

// The corners of a straight beam (Start, End) or of a polyline (Points).
std::vector<Vec3d> corners(const ParameterList& b, const std::string& path, bool straight) {
  std::vector<Vec3d> corners;
  if (straight) {
    for (const char* k : {"Start", "End"})
      if (!b.isParameter(k))
        throw InputError("missing required parameter \"" + path + "/" + k + "\" (a straight beam)");
    corners = {toVec(b.get<Array<double>>("Start")), toVec(b.get<Array<double>>("End"))};
    if (!(norm(corners[1] - corners[0]) > 0.0))
      throw InputError("beam \"" + path + "\" has zero length (Start equals End)");
    return corners;
  }
  const auto& a = b.get<Array<double>>("Points");
  if (a.size() < 6 || a.size() % 3 != 0)
    throw InputError("parameter \"" + path + "/Points\" must hold x, y, z of at least two points, got " +
                     std::to_string(a.size()) + " numbers");
  for (std::size_t i = 0; i < std::size_t(a.size()); i += 3) {
    if (!std::isfinite(a[i]) || !std::isfinite(a[i + 1]) || !std::isfinite(a[i + 2]))
      throw InputError("parameter \"" + path + "/Points\" must be finite");
    corners.push_back(Vec3d{{a[i], a[i + 1], a[i + 2]}});
  }
  return corners;
}

// `ne` elements between each two corners; by default the section's y axis normal to the first
// segment and global Z.
std::vector<Vec3d> alongCorners(const std::vector<Vec3d>& corners, int ne, bool given, Vec3d& sectionY) {
  std::vector<Vec3d> pts;
  for (std::size_t c = 0; c + 1 < corners.size(); ++c)
    for (int k = 0; k < ne; ++k) pts.push_back(corners[c] + (double(k) / ne) * (corners[c + 1] - corners[c]));
  pts.push_back(corners.back());
  if (!given) {
    const Vec3d Z{{0, 0, 1}};
    const Vec3d c = cross(Z, corners[1] - corners[0]);
    sectionY = norm(c) > 1e-8 * norm(corners[1] - corners[0]) ? (1.0 / norm(c)) * c : Vec3d{{0, 1, 0}};
  }
  return pts;
}

// An arc or a helix (sublist Arc or Helix of `b`) in `ne` elements; by default the section's y axis
// along the arc's normal or the helix's axis.
std::vector<Vec3d> curvePoints(ParameterList& b, const std::string& path, int ne, bool given, Vec3d& sectionY) {
  const double pi = std::acos(-1.0);
  const bool arc = b.isSublist("Arc");
  ParameterList& g = b.sublist(arc ? "Arc" : "Helix");
  const std::string gpath = path + (arc ? "/Arc" : "/Helix");
  (arc ? arcSpec() : helixSpec()).apply(g, gpath);
  const Vec3d axis = toVec(g.get<Array<double>>(arc ? "Normal" : "Axis Direction"));
  if (!(norm(axis) > 0.0))
    throw InputError("parameter \"" + path + "/" + (arc ? "Arc/Normal" : "Helix/Axis Direction") + "\" is zero");
  const Vec3d n = (1.0 / norm(axis)) * axis;
  const Vec3d r = toVec(g.get<Array<double>>("Reference Direction"));
  const Vec3d rp = r - dot(r, n) * n;
  if (!(norm(rp) > 1e-8 * std::max(norm(r), 1e-300)))
    throw InputError("parameter \"" + gpath + "/Reference Direction\" is zero or along the " +
                     (arc ? "normal" : "axis"));
  const Vec3d e1 = (1.0 / norm(rp)) * rp, e2 = cross(n, e1);
  const double R = g.get<double>("Radius");
  const Vec3d c = toVec(g.get<Array<double>>(arc ? "Centre" : "Axis Point"));
  double t0 = 0.0, t1 = 0.0, rise = 0.0;
  if (arc) {
    t0 = g.get<double>("Start Angle") * pi / 180.0;
    t1 = g.get<double>("End Angle") * pi / 180.0;
    if (!(std::abs(t1 - t0) > 0.0) || std::abs(t1 - t0) > 2 * pi * (1 + 1e-12))
      throw InputError("parameters \"" + gpath +
                       "/Start Angle\" and \"End Angle\" must differ by more than 0 and at most 360 degrees");
  } else {
    t0 = g.get<double>("Start Angle") * pi / 180.0;
    t1 = t0 + 2 * pi * g.get<double>("Turns");
    rise = g.get<double>("Pitch") / (2 * pi);
  }
  std::vector<Vec3d> pts;
  for (int k = 0; k <= ne; ++k) {
    const double t = t0 + (double(k) / ne) * (t1 - t0);
    pts.push_back(c + (R * std::cos(t)) * e1 + (R * std::sin(t)) * e2 + (rise * (t - t0)) * n);
  }
  if (!given) sectionY = n;
  return pts;
}

}  // namespace

std::vector<Vec3d> beamPoints(ParameterList& b, const std::string& path, int ne, Vec3d& sectionY) {
  const bool straight = b.isParameter("Start") || b.isParameter("End");
  const int kinds = int(straight) + int(b.isParameter("Points")) + int(b.isSublist("Arc")) + int(b.isSublist("Helix"));
  if (kinds != 1)
    throw InputError("beam \"" + path + "\" needs exactly one geometry: Start and End, Points, Arc or Helix" +
                     (kinds ? " (it has " + std::to_string(kinds) + ")" : ""));
  const bool given = b.isParameter("Section Orientation");
  if (given) sectionY = toVec(b.get<Array<double>>("Section Orientation"));
  if (straight || b.isParameter("Points")) return alongCorners(corners(b, path, straight), ne, given, sectionY);
  return curvePoints(b, path, ne, given, sectionY);
}

}  // namespace bc::input
