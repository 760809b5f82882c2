#include "Generate.hpp"

#include <filesystem>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>

#include <Teuchos_Array.hpp>
#include <Teuchos_ParameterList.hpp>
#include <Teuchos_XMLParameterListHelpers.hpp>

#include "core/Checkpoint.hpp"
#include "core/Faults.hpp"
#include "core/Parameters.hpp"
#include "core/PointGrid.hpp"
#include "core/SmallMath.hpp"
#include "input/XmlDeck.hpp"
#include "CommandLine.hpp"

namespace bc::drivers {

using core::InputError;
using input::xmlEscaped;
using Teuchos::Array;
using Teuchos::ParameterList;

namespace {

// Options with their defaults and meaning; every given option must be one of them.
struct Options {
  std::map<std::string, std::pair<double, std::string>> values;
  double operator[](const std::string& k) const { return values.at(k).first; }
  int whole(const std::string& k, int lo, int hi) const {
    const double v = values.at(k).first;
    if (v != std::floor(v) || v < lo || v > hi)
      throw InputError("generate: --" + k + " takes a whole number from " + std::to_string(lo) + " to " +
                       std::to_string(hi));
    return static_cast<int>(v);
  }
};

Array<double> vec(double x, double y, double z) { return Array<double>(std::vector<double>{x, y, z}); }

// A circular section of radius r, E and nu = 0.3.
void circleOf(ParameterList& beam, double r, double E) {
  beam.sublist("Section").set("Shape", std::string("Circle"));
  beam.sublist("Section").set("Radius", r);
  beam.sublist("Material").set("Young's Modulus", E);
  beam.sublist("Material").set("Poisson's Ratio", 0.3);
}

ParameterList& beam(ParameterList& beams, const std::string& name, const Array<double>& a, const Array<double>& b,
                    int elements, double radius, double E) {
  ParameterList& l = beams.sublist(name);
  l.set("Start", a);
  l.set("End", b);
  l.set("Elements", elements);
  circleOf(l, radius, E);
  return l;
}

void support(ParameterList& supports, const std::string& name, const std::string& beamName, const std::string& node,
             const std::string& fixed, const Array<double>& displacement) {
  ParameterList& s = supports.sublist(name);
  s.set("Beam", beamName);
  s.set("Node", node);
  s.set("Fixed", fixed);
  s.set("Displacement", displacement);
}

// All pairs in contact with the options' friction, Penalty (and Augmented Lagrange's parameters, so
// switching Type is one edit), and the load increments.
void contactAndStepping(ParameterList& deck, const Options& o) {
  ParameterList& contact = deck.sublist("Contact");
  contact.set("All Pairs", true);
  contact.set("Friction Coefficient", o["friction"]);
  ParameterList& e = contact.sublist("Enforcement");
  e.set("Type", std::string("Penalty"));
  for (const char* strategy : {"Penalty", "Augmented Lagrange"}) {
    e.sublist(strategy).set("Normal Penalty Parameter", o["penalty"]);
    e.sublist(strategy).set("Tangential Penalty Parameter", o["penalty"] / 10);
  }
  deck.sublist("Load Stepping").set("Number of Increments", o.whole("increments", 1, 1000000));
}

// Two layers of crossing circular beams: n along X at z = 0 (pinned ends, twist held), m along Y above
// them with a gap, their pinned ends pressed down by --press, and each of their crossing nodes loaded
// by --load. Crossings are at the mid-points of the
// spacing grid. --elements 0 (the default) gives a beam max(9, crossings + 1) elements: at least one
// free node per crossing (a beam with more crossings than free nodes over-constrains its contact
// points on the element chords: the Lagrange multipliers' matrix is then singular). From 9 crossings
// on they fall on nodes; with fewer (9 elements), between nodes unless the count divides.
ParameterList grid(const Options& o) {
  const int n = o.whole("n", 1, 1000), m = o.whole("m", 1, 1000), ne = o.whole("elements", 0, 100000);
  const int neX = ne > 0 ? ne : std::max(9, m + 1), neY = ne > 0 ? ne : std::max(9, n + 1);
  const double s = o["spacing"], r = o["radius"], gap = o["gap"];
  if (!(s > 2 * r) || !(r > 0) || !(gap >= 0)) throw InputError("generate grid: need spacing > 2 radius > 0, gap >= 0");
  ParameterList deck("BeamContact");
  ParameterList& beams = deck.sublist("Beams");
  ParameterList& supports = deck.sublist("Supports");
  const double lx = s * (m + 1), ly = s * (n + 1), z = 2 * r + gap;
  for (int j = 0; j < n; ++j) {
    const std::string name = "x" + std::to_string(j + 1);
    beam(beams, name, vec(0, s * (j + 1), 0), vec(lx, s * (j + 1), 0), neX, r, o["youngs-modulus"]);
    support(supports, name + " start", name, "start", "ux uy uz rx", vec(0, 0, 0));
    support(supports, name + " end", name, "end", "uy uz rx", vec(0, 0, 0));
  }
  const double load = o["load"];
  if (load != 0.0 && neY % (n + 1) != 0)
    throw InputError(
        "generate grid: --load acts at the top layer's crossings, which need to be nodes: give --elements "
        "a multiple of n + 1 = " +
        std::to_string(n + 1));
  for (int i = 0; i < m; ++i) {
    const std::string name = "y" + std::to_string(i + 1);
    beam(beams, name, vec(s * (i + 1), 0, z), vec(s * (i + 1), ly, z), neY, r, o["youngs-modulus"]);
    support(supports, name + " start", name, "start", "ux uy uz ry", vec(0, 0, -o["press"]));
    support(supports, name + " end", name, "end", "ux uz ry", vec(0, 0, -o["press"]));
    if (load == 0.0) continue;
    for (int j = 0; j < n; ++j) {
      ParameterList& l = deck.sublist("Loads").sublist(name + " crossing " + std::to_string(j + 1));
      l.set("Beam", name);
      l.set("Node", std::to_string((j + 1) * (neY / (n + 1))));
      l.set("Force", vec(0, 0, -load));
    }
  }
  contactAndStepping(deck, o);
  return deck;
}

// A plain-weave mat: n warp yarns along X and m weft yarns along Y, circular, each a polyline through
// z = +-amplitude cos(pi t / spacing) (warp and weft in opposite phase, neighbours alternating), so at
// every crossing the two yarns pass on opposite sides with 2 amplitude - 2 radius between their
// surfaces (amplitude = radius + gap / 2). Every yarn end is pinned (twist held); the warp yarns' ends
// are pulled apart along X by --pull at T = 1, straightening them against the wefts.
ParameterList weave(const Options& o) {
  const int n = o.whole("n", 1, 1000), m = o.whole("m", 1, 1000), per = o.whole("elements", 2, 1000);
  const double s = o["spacing"], r = o["radius"], gap = o["gap"], E = o["youngs-modulus"];
  if (!(s > 4 * r) || !(r > 0) || !(gap >= 0))
    throw InputError("generate weave: need spacing > 4 radius > 0, gap >= 0");
  const double a = r + 0.5 * gap, pi = std::acos(-1.0);
  ParameterList deck("BeamContact");
  ParameterList& beams = deck.sublist("Beams");
  ParameterList& supports = deck.sublist("Supports");
  // Yarn k of a family runs over t in [0, (count + 1) s], sampled `per` points per spacing.
  auto yarn = [&](const std::string& name, int count, bool warp, int k) {
    const double L = (count + 1) * s, across = (k + 1) * s, phase = warp ? (k % 2 ? pi : 0.0) : (k % 2 ? 0.0 : pi);
    std::vector<double> pts;
    const int samples = (count + 1) * per;
    for (int q = 0; q <= samples; ++q) {
      const double t = L * q / samples, z = a * std::cos(pi * t / s + phase);
      if (warp) pts.insert(pts.end(), {t, across, z});
      else pts.insert(pts.end(), {across, t, z});
    }
    ParameterList& l = beams.sublist(name);
    l.set("Points", Array<double>(pts));
    l.set("Elements", 1);
    circleOf(l, r, E);
  };
  for (int j = 0; j < n; ++j) {
    const std::string name = "warp " + std::to_string(j + 1);
    yarn(name, m, true, j);
    support(supports, name + " start", name, "start", "ux uy uz rx", vec(-0.5 * o["pull"], 0, 0));
    support(supports, name + " end", name, "end", "ux uy uz rx", vec(0.5 * o["pull"], 0, 0));
  }
  for (int i = 0; i < m; ++i) {
    const std::string name = "weft " + std::to_string(i + 1);
    yarn(name, n, false, i);
    support(supports, name + " start", name, "start", "ux uy uz ry", vec(0, 0, 0));
    support(supports, name + " end", name, "end", "ux uy uz ry", vec(0, 0, 0));
  }
  contactAndStepping(deck, o);
  // The yarns are smooth curves sampled by straight elements: point contact on the smoothed Hermite
  // axes (one tangent per node) sees them smooth. On the chords every crossing lies at a node where
  // the elements meet at an angle on the side facing the other yarn, a V-groove that one point per
  // crossing cannot hold without friction: the frictionless 10 x 10 weave stopped with Penalty and
  // Augmented Lagrange (docs/contact.md, "Point contact axes").
  deck.sublist("Contact").set("Point Contact Axes", std::string("Hermite"));
  return deck;
}

using V = math::Vec3d;

// The box a fibre network's centres are drawn in and the rules a drawn fibre keeps (above).
struct FibreBox {
  int count;
  double L, H, len, tilt, minAngle;  // box side and height, fibre length, angles [rad]
  double r, gap, reach;  // radius, least gap, the distance within which fibres may touch
};

double segmentDistance(const V& a, const V& b, const V& c, const V& d) {
  return math::segmentClosest(a, b, c, d).distance;
}

// Whether the drawn fibre a-b (direction d) may be kept beside the kept fibre p-q.
bool keepsClear(const FibreBox& box, const V& a, const V& b, const V& d, const V& p, const V& q) {
  const double dist = segmentDistance(a, b, p, q);
  if (dist < 2 * box.r + box.gap) return false;
  const V e{{q[0] - p[0], q[1] - p[1], q[2] - p[2]}};
  const double cosine = std::abs(d[0] * e[0] + d[1] * e[1] + d[2] * e[2]) / box.len;
  if (dist < box.reach && cosine > std::cos(box.minAngle)) return false;
  // No fibre end within reach of another fibre: contact at a beam end is not modelled.
  if (dist < box.reach && std::min({segmentDistance(a, a, p, q), segmentDistance(b, b, p, q),
                                    segmentDistance(p, p, a, b), segmentDistance(q, q, a, b)}) < box.reach)
    return false;
  return true;
}

// Draws per fibre before a network whose fibres do not all fit is given up.
constexpr long kDrawsPerFibre = 1000;

// The fibres (start, end) drawn from the sequence of `seed` and kept, in the order kept: all
// box.count of them, or fewer when kDrawsPerFibre draws per fibre did not place them all.
std::vector<std::pair<V, V>> placeFibres(const FibreBox& box, std::uint64_t seed) {
  const double pi = std::acos(-1.0), L = box.L, H = box.H, len = box.len;
  std::mt19937_64 random(seed);
  auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * static_cast<double>(random() >> 11) * 0x1.0p-53; };
  std::vector<std::pair<V, V>> kept;
  // The kept fibres by the cell of their centre (cells of side length + reach, so every fibre that can
  // come within reach of a drawn one has its centre in the drawn one's cell or a neighbour): each draw
  // is tested against the fibres nearby, not against every fibre kept (the same fibres fail a draw,
  // so the deck is the same).
  core::PointGrid centres(len + box.reach);
  const long attempts = kDrawsPerFibre * box.count;
  for (long tries = 0; static_cast<int>(kept.size()) < box.count; ++tries) {
    if (tries == attempts) break;
    const V c{{uniform(0, L), uniform(0, L), uniform(0, H)}};
    const double phi = uniform(0, pi), theta = uniform(-box.tilt, box.tilt);
    const V d{{std::cos(theta) * std::cos(phi), std::cos(theta) * std::sin(phi), std::sin(theta)}};
    const V a{{c[0] - 0.5 * len * d[0], c[1] - 0.5 * len * d[1], c[2] - 0.5 * len * d[2]}};
    const V b{{c[0] + 0.5 * len * d[0], c[1] + 0.5 * len * d[1], c[2] + 0.5 * len * d[2]}};
    bool fits = true;
    for (const int f : centres.near(c)) {
      if (!keepsClear(box, a, b, d, kept[f].first, kept[f].second)) {
        fits = false;
        break;
      }
    }
    if (fits) {
      centres.insert(c, static_cast<int>(kept.size()));
      kept.push_back({a, b});
    }
  }
  return kept;
}

// The refusal of a network whose fibres did not all fit: the message names the smallest --box (two
// significant digits, from the density of the fibres placed, then 10 % larger at a time, up to 12
// tries) in which the same seed and options place them all, as tried here.
[[noreturn]] void refuseNetwork(const FibreBox& box, std::uint64_t seed, std::size_t placed) {
  std::ostringstream s;
  s << "generate network: placed only " << placed << " of " << box.count << " fibres in " << kDrawsPerFibre * box.count
    << " draws; give fewer --fibres, a smaller --radius, --gap or --min-angle, or a larger --box or --height";
  const auto roundUp = [](double x) {  // up to two significant digits
    const double unit = std::pow(10.0, std::floor(std::log10(x)) - 1);
    return std::ceil(x / unit - 1e-9) * unit;
  };
  double side = roundUp(box.L * std::sqrt(double(box.count) / double(std::max<std::size_t>(placed, 1))));
  for (int k = 0; k < 12; ++k, side = roundUp(1.1 * side)) {
    FibreBox larger = box;
    larger.L = side;
    if (static_cast<int>(placeFibres(larger, seed).size()) == box.count) {
      s << " (--box " << side << " places them all with this seed and these options)";
      throw InputError(s.str());
    }
  }
  s << " (no --box up to " << side << " placed them all: the height, the angles or the gap bind)";
  throw InputError(s.str());
}

// A random fibre network: straight circular fibres of one length with centres uniform in the box
// [0, box]^2 x [0, height], in-plane angles uniform, out-of-plane angles uniform within +-tilt. A drawn
// fibre is kept only if its surface stays --gap clear of every fibre kept before, and, where the two
// could touch during the compression (axes closer than 2 radius + gap + compress height), if they
// cross at --min-angle or more (point contact is undefined between nearly parallel fibres: line
// contact, issue 11) and no end of either lies that close to the other (contact at a beam end is not
// modelled). Each fibre's start is clamped and its end pinned, and the fibre is moved down
// by the compression at its centre, u_z = -compress z_centre at T = 1 (the mat is squeezed; moving
// its ends by the affine field instead would shorten every tilted fibre by about compress sin^2 of
// its tilt, beyond the Euler strain of a slender fibre, and buckle it). The fibres touch where the
// compression brings their crossings together. Reproducible: the sequence
// comes from std::mt19937_64, whose output the C++ standard fixes, seeded with --seed.
ParameterList network(const Options& o) {
  const int count = o.whole("fibres", 1, 100000), ne = o.whole("elements", 1, 100000);
  const double L = o["box"], H = o["height"], len = o["length"], r = o["radius"], gap = o["gap"];
  const double pi = std::acos(-1.0), tilt = o["tilt"] * pi / 180, minAngle = o["min-angle"] * pi / 180;
  const double compress = o["compress"];
  if (!(L > 0) || !(H >= 0) || !(len > 0) || !(r > 0) || !(gap >= 0))
    throw InputError("generate network: need box > 0, height >= 0, length > 0, radius > 0, gap >= 0");
  if (!(tilt >= 0 && tilt <= pi / 2) || !(minAngle >= 0 && minAngle < pi / 2))
    throw InputError("generate network: need 0 <= tilt <= 90 and 0 <= min-angle < 90 (degrees)");
  if (!(compress >= 0 && compress < 1)) throw InputError("generate network: need 0 <= compress < 1");
  const FibreBox box{count, L, H, len, tilt, minAngle, r, gap, 2 * r + gap + compress * H};
  const auto seed = static_cast<std::uint64_t>(o.whole("seed", 0, 2000000000));
  const auto kept = placeFibres(box, seed);
  if (static_cast<int>(kept.size()) < count) refuseNetwork(box, seed, kept.size());
  ParameterList deck("BeamContact");
  ParameterList& beams = deck.sublist("Beams");
  ParameterList& supports = deck.sublist("Supports");
  for (int k = 0; k < count; ++k) {
    const std::string name = "f" + std::to_string(k + 1);
    const auto& [a, b] = kept[k];
    beam(beams, name, vec(a[0], a[1], a[2]), vec(b[0], b[1], b[2]), ne, r, o["youngs-modulus"]);
    const double down = -compress * 0.5 * (a[2] + b[2]);
    support(supports, name + " start", name, "start", "all", vec(0, 0, down));
    support(supports, name + " end", name, "end", "ux uy uz", vec(0, 0, down));
  }
  contactAndStepping(deck, o);
  return deck;
}

// The helix radius of a strand: the smallest R at which the wires' polylines (the elements the contact
// sees: chords, inside the helix) keep gap between neighbouring surfaces and, with a core, between each
// wire and the core. Neighbouring helices are closest along a line tilted by the lay angle, so
// r / sin(pi / wires) is not enough; found by bisection on the chords' closest distances.
// The screw motion that carries node q of every wire to node q + 1 carries chord i of a wire to
// chord i + 1, so the distance of chord i of wire 1 and chord j of wire 2 depends on j - i only:
// one chord against all of the other wire's gives every distance (2 n chord pairs per evaluation,
// not n^2: --elements 10000 took 467 s, now 0.1 s), and every chord is as far from the core.
double helixRadius(int wires, int core, int elements, double r, double rc, double lay, double turns, double gap) {
  const double pi = std::acos(-1.0);
  auto polyline = [&](double R, int k) {
    std::vector<math::Vec3d> p;
    for (int q = 0; q <= elements; ++q) {
      const double t = 2 * pi * (turns * q / elements + double(k) / wires);
      p.push_back(math::Vec3d{{R * std::cos(t), R * std::sin(t), lay * turns * q / elements}});
    }
    return p;
  };
  auto clearance = [&](double R) {
    const auto a = polyline(R, 0), b = polyline(R, 1);
    double c = 1e300;
    for (std::size_t d = 0; d + 1 < a.size(); ++d) {
      c = std::min(c, math::segmentClosest(a[0], a[1], b[d], b[d + 1]).distance - 2 * r);
      c = std::min(c, math::segmentClosest(a[d], a[d + 1], b[0], b[1]).distance - 2 * r);
    }
    if (core)
      c = std::min(
          c,
          math::segmentClosest(a[0], a[1], math::Vec3d{{0, 0, 0}}, math::Vec3d{{0, 0, lay * turns}}).distance - r - rc);
    return c;
  };
  double lo = 0.5 * r, hi = 10 * (r + rc + gap + r / std::sin(pi / wires));
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (clearance(mid) < gap ? lo : hi) = mid;
  }
  return hi;
}

// The contact angles of a strand of `wires` helices of radius R and lay length `lay` (with a core or
// not). Neighbouring helices keep the same distance all along (a screw motion maps each onto the next),
// so they touch along a line, although their tangents at the closest points differ by
// beta = 2 asin(sin(alpha) sin(pi / wires)) (alpha the lay angle; a helix and the core: alpha).
// The all-angle blend must see these pairs as line contact: Line Contact Angle above the larger
// angle by half of it plus a degree, Point Contact Angle 5 degrees above that. (In point contact,
// which the default angles gave at 18 degrees, Lagrange multipliers and Augmented Lagrange stopped
// at T = 0.37 and 0.26, and Penalty's forces jumped between steps.)
void strandContactAngles(ParameterList& deck, double R, double lay, int wires, int core) {
  const double pi = std::acos(-1.0);
  const double alpha = std::atan(2 * pi * R / lay);
  const double beta = 2 * std::asin(std::sin(alpha) * std::sin(pi / wires));
  const double widest = std::max(beta, core ? alpha : 0.0) * 180.0 / pi;
  const double lineAngle = std::min(1.5 * widest + 1.0, 40.0);  // (the deck allows up to 45)
  deck.sublist("Contact").set("Line Contact Angle", lineAngle);
  deck.sublist("Contact").set("Point Contact Angle", lineAngle + 5.0);
}

// A strand: --wires helical wires of radius r around the Z axis (lay length, turns), around a straight
// core wire (--core 1, radius core-radius) or none (--core 0). The helix radius puts each wire
// --gap clear of its neighbours and of the core (helixRadius). Every wire is clamped at both ends; the
// ends at the top are pulled along the axis by --stretch at T = 1, so the helices tighten onto the
// core or onto each other. Neighbouring helices, and a helix on the core, touch along a line: the
// deck puts them in line contact (the contact angles, strandContactAngles; Penalty with
// --regularization as its Regularization Gap).
ParameterList strand(const Options& o) {
  const int wires = o.whole("wires", 2, 36), core = o.whole("core", 0, 1), per = o.whole("elements", 4, 10000);
  const double r = o["radius"], rc = o["core-radius"] > 0 ? o["core-radius"] : 1.05 * r, lay = o["lay-length"];
  const double turns = o["turns"], gap = o["gap"];
  if (!(r > 0) || !(lay > 0) || !(turns > 0) || !(gap >= 0))
    throw InputError("generate strand: need radius > 0, lay-length > 0, turns > 0, gap >= 0");
  const int elements = std::max(1, static_cast<int>(std::lround(per * turns)));
  const double R = helixRadius(wires, core, elements, r, rc, lay, turns, gap);
  ParameterList deck("BeamContact");
  ParameterList& beams = deck.sublist("Beams");
  ParameterList& supports = deck.sublist("Supports");
  const double length = lay * turns;
  auto clamp = [&](const std::string& name) {
    support(supports, name + " start", name, "start", "all", vec(0, 0, 0));
    support(supports, name + " end", name, "end", "all", vec(0, 0, o["stretch"]));
  };
  if (core) {
    beam(beams, "core", vec(0, 0, 0), vec(0, 0, length), elements, rc, o["youngs-modulus"]);
    clamp("core");
  }
  for (int k = 0; k < wires; ++k) {
    const std::string name = "wire " + std::to_string(k + 1);
    ParameterList& l = beams.sublist(name);
    ParameterList& h = l.sublist("Helix");
    h.set("Axis Point", vec(0, 0, 0));
    h.set("Axis Direction", vec(0, 0, 1));
    h.set("Radius", R);
    h.set("Pitch", lay);
    h.set("Turns", turns);
    h.set("Reference Direction", vec(1, 0, 0));
    h.set("Start Angle", 360.0 * k / wires);
    l.set("Elements", elements);
    circleOf(l, r, o["youngs-modulus"]);
    clamp(name);
  }
  contactAndStepping(deck, o);
  deck.sublist("Contact").sublist("Enforcement").sublist("Penalty").set("Regularization Gap", o["regularization"]);
  strandContactAngles(deck, R, lay, wires, core);
  return deck;
}

// Options every generator has, then those of `kind`, with their defaults and meaning. Throws on an
// unknown kind.
Options optionsOf(const std::string& kind) {
  Options o;
  o.values = {{"radius", {1.0, "radius of every beam [length]"}},
              {"youngs-modulus", {1e5, "E [force/length^2]"}},
              {"friction", {0.2, "Coulomb coefficient of every pair"}},
              {"penalty", {1e4, "eps_N of Penalty and Augmented Lagrange (eps_T = eps_N / 10) [force/length]"}},
              {"increments", {10, "load increments"}}};
  if (kind == "grid" || kind == "weave")
    o.values.insert({"spacing", {10.0, "distance between neighbouring beams of a family [length]"}});
  if (kind == "grid") {
    o.values.insert({{"n", {3, "beams along X (bottom layer)"}},
                     {"m", {3, "beams along Y (top layer)"}},
                     {"gap", {0.1, "gap between the layers at the start [length]"}},
                     {"press", {0.5, "downward motion of the top layer's ends at T = 1 [length]"}},
                     {"load",
                      {0.0,
                       "downward force on the top layer at each crossing at T = 1 (the crossings must be "
                       "nodes) [force]"}},
                     {"elements", {0, "elements per beam; 0: max(9, crossings along the beam + 1)"}}});
  } else if (kind == "weave") {
    o.values.insert({{"n", {3, "warp yarns (along X)"}},
                     {"m", {3, "weft yarns (along Y)"}},
                     {"gap", {0.1, "gap between crossing yarns at the start [length]"}},
                     {"pull", {0.2, "stretch of the warp yarns at T = 1 (each end moves half) [length]"}},
                     {"elements", {8, "elements per spacing along each yarn (the undulation's polyline)"}}});
  } else if (kind == "network") {
    o.values.insert(
        {{"fibres", {20, "fibres"}},
         {"box", {50.0, "side of the square the fibre centres lie in [length]"}},
         {"height", {6.0, "height of the box the fibre centres lie in [length]"}},
         {"length", {40.0, "length of every fibre [length]"}},
         {"tilt", {10.0, "largest angle of a fibre out of the plane [degrees]"}},
         {"gap", {0.2, "least distance between fibre surfaces at the start [length]"}},
         {"min-angle", {10.0, "least crossing angle of fibres that may touch [degrees]"}},
         {"compress", {0.3, "compression of the box height at T = 1 (each fibre moves down by compress z_centre)"}},
         {"seed", {1, "seed of the random sequence (the same seed gives the same deck)"}},
         {"elements", {8, "elements per fibre"}}});
  } else if (kind == "strand") {
    o.values.insert({{"wires", {3, "helical wires around the axis"}},
                     {"core", {0, "1: a straight core wire inside them, 0: none"}},
                     {"core-radius", {0.0, "radius of the core wire; 0: 1.05 radius [length]"}},
                     {"lay-length", {40.0, "rise of a wire per turn (pitch) [length]"}},
                     {"turns", {1.0, "turns of the wires (the strand is lay-length x turns long)"}},
                     {"gap", {0.01, "radial clearance of the wires at the start [length]"}},
                     {"stretch", {0.05, "axial motion of the strand's top ends at T = 1 [length]"}},
                     {"regularization", {1e-3, "Penalty's Regularization Gap (line contact) [length]"}},
                     {"elements", {24, "elements per turn of every wire"}}});
  } else {
    throw InputError("generate: unknown kind \"" + kind + "\"; kinds are \"grid\", \"weave\", \"network\", \"strand\"");
  }
  return o;
}

// A default as the --help shows it: the shortest text that reads back as the same number.
std::string shortNumber(double v) {
  char text[32];
  if (v == std::floor(v) && std::abs(v) < 1e7) {
    std::snprintf(text, sizeof text, "%.0f", v);
    return text;
  }
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, v);
    if (std::stod(text) == v) break;
  }
  return text;
}

// The options of `kind` as a command-line table (CommandLine.hpp): its parsing and its --help.
cli::Command commandOf(const std::string& kind, const Options& o) {
  cli::Command c;
  c.name = "generate " + kind;
  c.summary = kind == "grid"      ? "Two layers of crossing circular beams pressed together."
              : kind == "weave"   ? "A plain-weave mat of undulating yarns whose warps are pulled."
              : kind == "network" ? "Random straight fibres in a box, compressed."
                                  : "Helical wires around an axis (and a core), pulled.";
  c.summary +=
      "\nWrites the deck to FILE, or prints it. Units are those of the options (consistent length and "
      "force); docs/input.md describes each generator.";
  for (const auto& [name, value] : o.values)
    c.options.push_back({name, 0, "X", shortNumber(value.first), value.second});
  c.options.push_back({"output", 'o', "FILE", "print the deck on standard output",
                       "the deck file to write (a new file, or with --overwrite any regular file)"});
  c.options.push_back({"overwrite", 0, "", "", "replace FILE if it exists (a deck you edited is lost)"});
  return c;
}

// Reads the options of `args` (after the kind) into `o` and `overwrite`; returns --output (empty:
// none), or nullopt when --help was printed.
std::optional<std::string> readOptions(const std::vector<std::string>& args, const std::string& kind, Options& o,
                                       bool& overwrite) {
  const cli::Command command = commandOf(kind, o);
  const cli::Parsed parsed = cli::parse(command, std::vector<std::string>(args.begin() + 2, args.end()));
  if (parsed.help) {
    std::fputs(cli::help(command).c_str(), stdout);
    return std::nullopt;
  }
  overwrite = parsed.has("overwrite");
  for (const auto& [key, values] : parsed.values) {
    if (key == "output" || key == "overwrite") continue;
    const std::string& text = values.back();
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(text, &used);
    } catch (...) {
      used = 0;
    }
    if (used != text.size() || !std::isfinite(v))
      throw cli::UsageError(command.name, "--" + key + " takes a number, got \"" + text + "\"");
    o.values.at(key).first = v;
  }
  return parsed.get("output");
}

// A parameter list as plain XML, a person can edit: each parameter's name, type and value (numbers in
// their shortest exact form), nested lists indented; nothing else (Teuchos' own writer adds ids, doc
// strings and flags, and 17 digits).
void writePlainXml(const ParameterList& list, const std::string& name, std::ostream& out, int depth) {
  const std::string pad(2 * depth, ' ');
  out << pad << "<ParameterList name=\"" << xmlEscaped(name) << "\">\n";
  for (auto it = list.begin(); it != list.end(); ++it) {
    const Teuchos::ParameterEntry& e = list.entry(it);
    if (e.isList()) {
      writePlainXml(Teuchos::getValue<ParameterList>(e), list.name(it), out, depth + 1);
      continue;
    }
    out << pad << "  <Parameter name=\"" << xmlEscaped(list.name(it)) << "\" type=\"" << input::deckType(e)
        << "\" value=\"" << xmlEscaped(input::deckValue(e)) << "\"/>\n";
  }
  out << pad << "</ParameterList>\n";
}

// The deck as XML, headed by the options it was generated with.
std::string deckXml(const std::string& kind, const Options& o, const ParameterList& deck) {
  std::ostringstream xml;
  xml << "<!-- Generated by: beamcontact generate " << kind;
  for (const auto& [k, v] : o.values) xml << " " << k << "=" << v.first;
  xml << "\n     Units are those of the options (consistent length and force). -->\n";
  writePlainXml(deck, "BeamContact", xml, 0);
  return xml.str();
}

// Writes a deck to `output` (an existing file only with `overwrite`), or prints it when empty.
void writeDeck(const std::string& xml, const std::string& output, bool overwrite) {
  if (output.empty()) {
    std::fputs(xml.c_str(), stdout);
  } else {
    // A deck replaces a regular file only: a device, a pipe, a folder or a link at the path is left
    // alone (a rename over /dev/null would replace the device itself).
    std::error_code ec;
    const auto status = std::filesystem::symlink_status(output, ec);
    if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status))
      throw core::InputError("generate: --output \"" + output + "\" is " +
                             (std::filesystem::is_symlink(status)     ? "a symbolic link"
                              : std::filesystem::is_directory(status) ? "a folder"
                                                                      : "not a regular file (a device or a pipe)") +
                             "; give the path of a deck file, or leave out --output to print the deck");
    if (std::filesystem::exists(status) && !overwrite)
      throw core::InputError("generate: --output \"" + output +
                             "\" exists; add --overwrite to replace it, or give another file");
    core::writeFileAtomically(output, xml);
  }
}

}  // namespace

int generateDeck(const std::vector<std::string>& args) {
  const std::string kinds = "grid, weave, network or strand";
  if (args.size() < 2 || args[1] == "--help" || args[1] == "-h") {
    if (args.size() < 2) throw cli::UsageError("generate", "a kind is needed: " + kinds);
    std::printf(
        "usage: beamcontact generate KIND [--OPTION VALUE]... [-o FILE [--overwrite]]\n\n"
        "Writes a many-beam deck from a few parameters (docs/input.md). KIND is one of\n"
        "  grid      two layers of crossing beams pressed together\n"
        "  weave     a plain-weave mat of undulating yarns whose warps are pulled\n"
        "  network   random fibres in a box, compressed\n"
        "  strand    helical wires, pulled\n"
        "beamcontact generate KIND --help lists KIND's options with their defaults and meaning.\n\n%s",
        cli::documentationNote().c_str());
    return 0;
  }
  const std::string kind = args[1];
  if (kind != "grid" && kind != "weave" && kind != "network" && kind != "strand")
    throw cli::UsageError("generate", "unknown kind \"" + kind + "\"; kinds are " + kinds);
  Options o = optionsOf(kind);
  bool overwrite = false;
  const auto output = readOptions(args, kind, o, overwrite);
  if (!output) return 0;
  // The options every kind has, checked here as the deck would check them (else the deck is written
  // and refused by the run).
  if (!(o["youngs-modulus"] > 0)) throw InputError("generate " + kind + ": need youngs-modulus > 0");
  if (!(o["friction"] >= 0)) throw InputError("generate " + kind + ": need friction >= 0");
  if (!(o["penalty"] > 0)) throw InputError("generate " + kind + ": need penalty > 0");
  const ParameterList deck = kind == "grid"     ? grid(o)
                             : kind == "weave"  ? weave(o)
                             : kind == "strand" ? strand(o)
                                                : network(o);
  writeDeck(deckXml(kind, o, deck), *output, overwrite);
  // Where the deck went (printed decks say nothing: stdout is the deck).
  if (!output->empty())
    std::printf("generate %s: wrote %s (%d beams); run it with: beamcontact run %s\n", kind.c_str(), output->c_str(),
                static_cast<int>(deck.sublist("Beams").numParams()), output->c_str());
  return 0;
}

}  // namespace bc::drivers
