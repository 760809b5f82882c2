#include "Deck.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <numeric>
#include <set>
#include <sstream>
#include <unordered_map>

#include <Teuchos_Array.hpp>
#include <Teuchos_XMLParameterListHelpers.hpp>

#include "BeamGeometry.hpp"
#include "ModelChecks.hpp"
#include "XmlDeck.hpp"

#include "constraints/ContactManager.hpp"
#include "elements/PinnedJoints.hpp"
#include "core/Checkpoint.hpp"
#include "core/PointGrid.hpp"
#include "constraints/EnforcerRegistry.hpp"

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

const ParameterSpec& sectionSpec() {
  static const ParameterSpec s = [] {
    ParameterSpec p;
    p.addChoice("Shape", "Rectangle", {"Rectangle", "Circle"}, "cross-section shape");
    p.addOptional("Width", 0.1,
                  "Rectangle (required there; not for a Circle): side b along the section's local y axis [length]",
                  core::positive(), "> 0");
    p.addOptional("Height", 0.1,
                  "Rectangle (required there; not for a Circle): side h along the section's local z axis [length]",
                  core::positive(), "> 0");
    p.addOptional("Radius", 0.05, "Circle (required there; not for a Rectangle): radius [length]", core::positive(),
                  "> 0");
    p.addOptional("Torsion Constant", 1.406e-5,
                  "J [length^4]; default: Saint-Venant's value for the shape (set it where a benchmark states GJ)",
                  core::positive(), "> 0");
    return p;
  }();
  return s;
}

const ParameterSpec& materialSpec() {
  static const ParameterSpec s = [] {
    ParameterSpec p;
    p.addRequired("Young's Modulus", 1.0, "E [force/length^2]", core::positive(), "> 0");
    p.addRequired("Poisson's Ratio", 0.3, "nu; the shear modulus is E / (2 (1 + nu))", core::inRange(-1.0, 0.5),
                  "in (-1, 0.5]");
    return p;
  }();
  return s;
}

const ParameterSpec& jointSpec() {
  static const ParameterSpec s = [] {
    ParameterSpec p;
    p.addRequired("Beam A", std::string("beam"), "the beam whose end is joined");
    p.addRequired("Node A", std::string("end"), "its end: \"start\" or \"end\"");
    p.addRequired("Beam B", std::string("beam"), "the beam it is joined to");
    p.addRequired("Node B", std::string("start"),
                  "the node of beam B at the same place: \"start\", \"end\", \"middle\" or an index 0..Elements");
    p.addChoice("Type", "Rigid", {"Rigid", "Pinned"},
                "\"Rigid\": one shared node (what coincident ends get without a Joint); \"Pinned\": translations "
                "tied, rotations free (no moment through the joint)");
    return p;
  }();
  return s;
}

const ParameterSpec& beamSpec() {
  static const ParameterSpec s = [] {
    ParameterSpec p;
    p.addOptional("Start", zero3(),
                  "straight beam: coordinates of the first node (a beam is Start and End, or Points, or an Arc or a "
                  "Helix) [length]",
                  core::vector3());
    p.addOptional("End", values({1, 0, 0}), "straight beam: coordinates of the last node [length]", core::vector3());
    p.addOptional("Points", values({1, 0, 0, 2, 0, 0, 2, 0, 1}),
                  "polyline: x1, y1, z1, x2, y2, z2, ... (at least two points), Elements per segment [length]");
    p.addSublist("Arc", arcSpec().reference(), "circular arc (instead of Start and End), Elements in all");
    p.addSublist("Helix", helixSpec().reference(), "helix (instead of Start and End), Elements in all");
    p.addRequired("Elements", 10, "number of elements along the beam (a polyline: per segment)",
                  core::wholeBetween(1, 10000000), "1 to 1e7");
    p.addOptional("Section Orientation", values({0, 0, 1}),
                  "direction of the section's local y axis (the Width side), projected on each element's normal "
                  "plane; default: normal to the axis (a polyline: its first segment) and to global Z (for an axis "
                  "along Z: global Y), for an arc "
                  "its plane's normal, for a helix its axis",
                  core::vector3());
    p.addSublist("Section", sectionSpec().reference(), "cross-section");
    p.addSublist("Material", materialSpec().reference(), "linear elastic material");
    return p;
  }();
  return s;
}

void addLocation(ParameterSpec& p) {
  p.addOptional("Beam", std::string("beam name"), "name of the beam (give Beam and Node, or Point)");
  p.addOptional("Node", std::string("end"),
                "node of that beam: \"start\", \"end\", \"middle\" or a node index 0..Elements");
  p.addOptional("Point", zero3(), "coordinates of a node [length] (instead of Beam and Node)", core::vector3());
}

const ParameterSpec& supportSpec() {
  static const ParameterSpec s = [] {
    ParameterSpec p;
    addLocation(p);
    p.add("Fixed", std::string("all"),
          "constrained components: \"all\" or a list of ux uy uz rx ry rz (others stay free)");
    p.add("Displacement", zero3(), "prescribed displacement at T = 1 of the fixed ux uy uz [length]", core::vector3());
    p.add("Rotation", zero3(),
          "prescribed rotation at T = 1 of the fixed rx ry rz, as spins about the global axes [rad]", core::vector3());
    p.addOptional("Load Curve", values({0, 0, 0.5, 1, 1, 1}),
                  "load history: T1, f1, T2, f2, ... (T from 0 to 1, increasing): the value at T is the value given "
                  "here times f, linear between the points; default f = T");
    return p;
  }();
  return s;
}

const ParameterSpec& loadSpec() {
  static const ParameterSpec s = [] {
    ParameterSpec p;
    addLocation(p);
    p.add("Force", zero3(), "point force at T = 1 (fixed direction) [force]", core::vector3());
    p.add("Moment", zero3(), "point moment at T = 1 about fixed global axes [force*length]", core::vector3());
    p.addOptional("Load Curve", values({0, 0, 0.5, 1, 1, 1}),
                  "load history: T1, f1, T2, f2, ... (T from 0 to 1, increasing): the value at T is the value given "
                  "here times f, linear between the points; default f = T");
    return p;
  }();
  return s;
}

const ParameterSpec& trackedSpec() {
  static const ParameterSpec s = [] {
    ParameterSpec p;
    addLocation(p);
    for (const char* u : {"ux", "uy", "uz"})
      p.addOptional(std::string("Reference ") + u, 1.0,
                    std::string("a published value of the point's ") + u +
                        " at T = 1 (e.g. a paper's): a complete run prints it beside its own, with the difference "
                        "(run - reference) / reference in % [length]");
    p.addOptional("Reference Source", std::string("paper (Table 1)"),
                  "where the Reference values come from; printed before them (default: \"reference\")");
    return p;
  }();
  return s;
}

const ParameterSpec& outputSpec() {
  static const ParameterSpec s = [] {
    ParameterSpec p;
    p.addOptional("Directory", std::string("results/my_run"),
                  "results directory (default results/<deck file name without .xml>); --output overrides it");
    p.add("Write VTK", true,
          "write VTK files: the beams in vtk/step_*.vtu with results.pvd, the contact points in "
          "vtk/contact_*.vtu with contact.pvd");
    p.add("VTK Every", 1,
          "write the VTK files of every this many converged steps (step numbers divisible by it); 0: only those "
          "of VTK At; T = 0 and the last converged step are always written",
          core::atLeast(0), ">= 0");
    p.addOptional("VTK At", values({0.5, 1}),
                  "load factors T, increasing, in (0, 1]: the first converged step at or beyond each is written too "
                  "(besides those of VTK Every)");
    p.add("VTK Compression", true,
          "compress the VTK files' data with zlib (lossless; false: raw binary, about twice the size)");
    p.add("Checkpoint Every", 0,
          "write checkpoint.txt (the complete state, for --restart) after every this many converged steps; 0: "
          "only when a signal stops the run",
          core::atLeast(0), ">= 0");
    p.addSublist("Tracked Points", ParameterList(),
                 "named sublists, each a point (Beam + Node, or Point) whose motion is written per step");
    return p;
  }();
  return s;
}

const ParameterSpec& contactPairSpec() {
  static const ParameterSpec s = [] {
    ParameterSpec p;
    p.addRequired("Beam A", std::string("beam name"), "first beam of the pair");
    p.addRequired("Beam B", std::string("beam name"), "second beam of the pair");
    p.addRequired("Friction Coefficient", 0.3, "Coulomb friction coefficient mu (0: frictionless)", core::nonNegative(),
                  ">= 0");
    return p;
  }();
  return s;
}

const ParameterSpec& contactSpec() {
  static const ParameterSpec s = [] {
    ParameterSpec p;
    p.add("All Pairs", false, "every pair of beams may come into contact (then give Friction Coefficient here)");
    p.addOptional("Friction Coefficient", 0.3, "with All Pairs: Coulomb friction coefficient of every pair",
                  core::nonNegative(), ">= 0");
    p.addOptional("Search Margin", 0.05,
                  "distance added to the elements' bounding boxes in the contact search [length]; default: half "
                  "the largest section dimension",
                  core::nonNegative(), ">= 0");
    p.add("Parallel Line Tolerance", 1e-3,
          "contact lines whose angle has a sine below this are skipped (point contact is undefined there); "
          "rectangular sections are in line contact (face to face) below it and blend up to twice its angle",
          core::inRange(0.0, 1.0), "in (0, 1]");
    p.add("Line Contact Angle", 5.0,
          "two circular beams' elements whose axes are closer to parallel than this are in line contact (a "
          "traction along the line, with friction along the axes); between this and Point Contact Angle line and "
          "point contact are blended smoothly; 0: no line contact (rectangular sections: line contact only below "
          "Parallel Line Tolerance) [degrees]",
          core::closedRange(0.0, 45.0), "0 to 45");
    p.add("Point Contact Angle", 15.0,
          "above this angle two circular beams' elements are in point contact only [degrees]",
          core::closedRange(0.0, 60.0), "0 to 60, above Line Contact Angle");
    p.add("Line Gauss Points", 6, "Gauss points of line contact per element of beam A", core::wholeBetween(1, 30),
          "1 to 32");
    p.addChoice("Point Contact Axes", "Chord", {"Chord", "Hermite"},
                "the lines point contact finds its closest points, gap and normal on: \"Chord\": the straight "
                "chords between the nodes (the seed paper's; the normal jumps at nodes); \"Hermite\": each "
                "element's cubic Hermite curve through its nodes with one tangent per node, turning with it (the "
                "bisector of its elements' initial directions: smooth across nodes, also of a polyline such as "
                "an arc or a weave's yarn; a corner beyond 45 degrees keeps each element's own; converges "
                "monotonically with the mesh where a contact lies between nodes)");
    p.add("Allow Initial Penetration", false, "accept beams that overlap at T = 0 instead of stopping");
    p.addChoice("Friction Law", "Isotropic Coulomb", {"Isotropic Coulomb", "Per Line"},
                "\"Isotropic Coulomb\": the tangential force vector obeys |F_T| <= mu F_N; \"Per Line\": each of "
                "the two friction forces along the contact lines obeys |F_Ti| <= mu F_N on its own (the seed "
                "paper's law; the resultant may reach 1.41 mu F_N)");
    p.addSublist("Pairs", ParameterList(), "named contact pairs: Beam A, Beam B, Friction Coefficient");
    p.addSublist("Enforcement", ParameterList(), "the enforcement strategy: Type and its sublist");
    return p;
  }();
  return s;
}

const ParameterSpec& topSpec() {
  static const ParameterSpec s = [] {
    ParameterSpec p;
    p.addSublist("Beams", ParameterList(), "one sublist per beam; the sublist name is the beam name");
    p.addSublist("Supports", ParameterList(), "named supports and prescribed motions");
    p.addSublist("Loads", ParameterList(), "named point forces and moments (scaled by T)");
    p.addSublist("Load Stepping", core::loadSteppingSpec().reference(), "load factor increments");
    p.addSublist("Nonlinear Solver", core::newtonSpec().reference(), "Newton-Raphson settings");
    p.addSublist("Linear Solver", core::linearSolverSpec().reference(), "linear solver settings");
    p.addSublist("Output", outputSpec().reference(), "results directory and tracked points");
    p.addSublist("Contact", contactSpec().reference(), "beam-to-beam contact (optional)");
    p.addSublist("Joints", ParameterList(),
                 "named joints between beam ends and nodes of other beams, Rigid or "
                 "Pinned (coincident ends are joined rigidly without one)");
    p.addOptional("Plugins", Array<std::string>(),
                  "shared libraries the deck needs, e.g. a strategy of your own "
                  "(paths relative to the deck's folder); each must also be given with --plugin, which loads it; "
                  "see docs/contact.md");
    p.addOptional("Plugin SHA-256", Array<std::string>(),
                  "SHA-256 of each of Plugins' libraries, in order "
                  "(effective_parameters.xml records them); when given, a library whose digest differs is refused");
    return p;
  }();
  return s;
}

// Item names appear in CSV headers and rows: they must be plain text without commas or quotes.
void checkName(const std::string& name, const std::string& path) {
  std::string why;
  if (name.empty() || name.find_first_not_of(' ') == std::string::npos) why = "is empty";
  else if (name.front() == ' ' || name.back() == ' ') why = "starts or ends with a space";
  else if (name.size() > 100) why = "is longer than 100 characters";
  else
    for (unsigned char c : name)
      if (c == ',' || c == '"' || c < 32 || c == 127) {
        why = c == ',' ? "contains a comma" : c == '"' ? "contains a quote" : "contains a control character";
        break;
      }
  if (!why.empty())
    throw InputError("the name \"" + name + "\" in \"" + path + "\" " + why +
                     "; names appear in the CSV results, use letters, digits, spaces, - _ . ( ) /");
}

// Validates every sublist of `parent` with `spec` (each sublist is one named item).
void forEachItem(ParameterList& parent, const std::string& path, const ParameterSpec& spec,
                 const std::function<void(ParameterList&, const std::string&, const std::string&)>& fn) {
  for (auto it = parent.begin(); it != parent.end(); ++it) {
    const std::string name = parent.name(it);
    if (!parent.isSublist(name))
      throw InputError("\"" + path + "/" + name + "\" must be a sublist (one per item, named by the item)");
    checkName(name, path);
    ParameterList& item = parent.sublist(name);
    spec.apply(item, path + "/" + name);
    fn(item, name, path + "/" + name);
  }
}

// The node of a beam with `ne` elements named by `node` ("start", "end", "middle" or an index).
int nodeIndexOnBeam(const std::string& node, int ne, const std::string& path, const std::string& beam) {
  if (node == "start") return 0;
  if (node == "end") return ne;
  if (node == "middle") {
    if (ne % 2)
      throw InputError("parameter \"" + path + "\": \"middle\" needs an even element count, beam \"" + beam +
                       "\" has " + std::to_string(ne));
    return ne / 2;
  }
  std::size_t used = 0;
  int index = 0;
  try {
    index = std::stoi(node, &used);
  } catch (...) {
    used = 0;
  }
  if (used != node.size() || node.empty() || index < 0 || index > ne)
    throw InputError("parameter \"" + path + "\": \"" + node +
                     "\" is not \"start\", \"end\", \"middle\" or an index 0.." + std::to_string(ne));
  return index;
}

// The index of the beam named `name`; an input error at `where` listing the beams if there is none.
int beamNamed(const std::map<std::string, int>& beamIndex, const std::string& name, const std::string& where) {
  const auto b = beamIndex.find(name);
  if (b == beamIndex.end()) {
    std::vector<std::string> names;
    for (const auto& [n, i] : beamIndex) names.push_back(n);
    throw InputError("parameter \"" + where + "\": unknown beam \"" + name + "\"; beams are " + core::joinNames(names));
  }
  return b->second;
}

class Locator {
 public:
  Locator(const Problem& p, const core::State& s) : p_(p), s_(s) {}

  // Nodes addressed by a location sublist. `several` allows all coincident nodes of a Point.
  std::vector<int> nodes(const ParameterList& item, const std::string& path, bool several) const {
    const bool hasBeam = item.isParameter("Beam"), hasNode = item.isParameter("Node"),
               hasPoint = item.isParameter("Point");
    if (hasPoint && (hasBeam || hasNode))
      throw InputError("\"" + path + "\": give either \"Point\" or \"Beam\" with \"Node\", not both");
    if (hasPoint) return nodesAt(toVec(item.get<Array<double>>("Point")), path, several);
    if (!hasBeam || !hasNode)
      throw InputError("\"" + path + "\": missing location; give \"Beam\" and \"Node\", or \"Point\"");
    const std::string beam = item.get<std::string>("Beam");
    const auto& nodes = p_.beams->beams()[beamNamed(p_.beamIndex, beam, path + "/Beam")].nodes;
    const int ne = static_cast<int>(nodes.size()) - 1;
    return {nodes[nodeIndexOnBeam(item.get<std::string>("Node"), ne, path + "/Node", beam)]};
  }

 private:
  std::vector<int> nodesAt(const Vec3d& x, const std::string& path, bool several) const {
    double scale = 0.0;
    for (const auto& X : s_.reference) scale = std::max(scale, norm(X));
    const double tol = 1e-8 * std::max(scale, 1.0);
    std::vector<int> found;
    double nearest = 1e300;
    for (int n = 0; n < s_.numNodes(); ++n) {
      const double d = norm(s_.reference[n] - x);
      nearest = std::min(nearest, d);
      if (d <= tol) found.push_back(n);
    }
    if (found.empty())
      throw InputError("parameter \"" + path + "/Point\": no node there (nearest node at distance " +
                       std::to_string(nearest) + ")");
    if (found.size() > 1 && !several)
      throw InputError("parameter \"" + path + "/Point\": several beams have a node there; use Beam and Node");
    return found;
  }
  const Problem& p_;
  const core::State& s_;
};

// The six components of a node's motion, in the order of Support::fixed and Support::value.
constexpr const char* kComponents[6] = {"ux", "uy", "uz", "rx", "ry", "rz"};

std::array<bool, 6> parseFixed(const std::string& text, const std::string& path) {
  std::array<bool, 6> fixed{};
  if (text == "all") {
    fixed.fill(true);
    return fixed;
  }
  std::istringstream in(text);
  std::string word;
  bool any = false;
  while (in >> word) {
    int k = 0;
    while (k < 6 && word != kComponents[k]) ++k;
    if (k == 6)
      throw InputError("parameter \"" + path + "/Fixed\": \"" + word + "\" is not a component; use \"all\" alone, or " +
                       "components among ux uy uz rx ry rz");
    fixed[k] = any = true;
  }
  if (!any) throw InputError("parameter \"" + path + "/Fixed\" is empty; use \"all\" or ux uy uz rx ry rz");
  return fixed;
}

// The contact pairs of a validated Contact sublist `c`: All Pairs and the listed Pairs, each pair of
// beams once.
std::vector<constraints::ContactPairSpec> contactPairs(const Problem& p, ParameterList& c, const std::string& path) {
  std::vector<constraints::ContactPairSpec> pairs;
  const int nb0 = static_cast<int>(p.beams->beams().size());
  if (c.get<bool>("All Pairs")) {
    if (!c.isParameter("Friction Coefficient"))
      throw InputError("missing required parameter \"" + path + "/Friction Coefficient\" (needed with All Pairs)");
    const int nb = static_cast<int>(p.beams->beams().size());
    // n beams make n (n - 1) / 2 pairs, each held in the list and the search's index.
    checkModelSize(p.beams->elements().size(), 0, 0.0, 0.5 * double(nb) * double(nb - 1));
    pairs.reserve(std::size_t(nb) * std::size_t(nb - 1) / 2);
    for (int a = 0; a < nb; ++a)
      for (int b = a + 1; b < nb; ++b)
        pairs.push_back(
            {a, b, c.get<double>("Friction Coefficient"), p.beams->beams()[a].name + "-" + p.beams->beams()[b].name});
  } else if (c.isParameter("Friction Coefficient")) {
    throw InputError("parameter \"" + path + "/Friction Coefficient\" applies only with All Pairs; give it per pair");
  }
  forEachItem(c.sublist("Pairs"), path + "/Pairs", contactPairSpec(),
              [&](ParameterList& q, const std::string& name, const std::string& qpath) {
                const int a = beamNamed(p.beamIndex, q.get<std::string>("Beam A"), qpath + "/Beam A");
                const int b = beamNamed(p.beamIndex, q.get<std::string>("Beam B"), qpath + "/Beam B");
                if (a == b) throw InputError("contact pair \"" + qpath + "\" names the same beam twice");
                pairs.push_back({a, b, q.get<double>("Friction Coefficient"), name});
              });
  if (pairs.empty()) throw InputError("\"" + path + "\" declares no contact pair: give Pairs or set All Pairs to true");
  if (c.get<bool>("All Pairs") && pairs.size() > std::size_t(nb0) * std::size_t(nb0 - 1) / 2) {
    // Every pair is declared already (found without a map of all pairs: 10^4 beams make 5 x 10^7).
    const auto& q = pairs[std::size_t(nb0) * std::size_t(nb0 - 1) / 2];
    const auto [lo, hi] = std::minmax(q.beamA, q.beamB);
    throw InputError("contact pairs \"" + p.beams->beams()[lo].name + "-" + p.beams->beams()[hi].name + "\" and \"" +
                     q.name + "\" both join beams \"" + p.beams->beams()[q.beamA].name + "\" and \"" +
                     p.beams->beams()[q.beamB].name +
                     "\" (their contact would count twice); declare each pair once (All Pairs already declares every "
                     "pair)");
  } else if (!c.get<bool>("All Pairs")) {
    std::map<std::pair<int, int>, std::string> seen;
    for (const auto& q : pairs) {
      const auto key = std::minmax(q.beamA, q.beamB);
      const auto [it, fresh] = seen.emplace(key, q.name);
      if (!fresh)
        throw InputError("contact pairs \"" + it->second + "\" and \"" + q.name + "\" both join beams \"" +
                         p.beams->beams()[q.beamA].name + "\" and \"" + p.beams->beams()[q.beamB].name +
                         "\" (their contact would count twice); declare each pair once" +
                         (c.get<bool>("All Pairs") ? " (All Pairs already declares every pair)" : ""));
    }
  }
  return pairs;
}

// The options of a validated Contact sublist `c`.
constraints::ContactOptions contactOptions(const Problem& p, const ParameterList& c, const std::string& path) {
  constraints::ContactOptions options;
  double largest = 0.0;
  for (const auto& b : p.beams->beams())
    largest = std::max({largest, b.section.width, b.section.height, 2 * b.section.radius});
  options.searchMargin = c.isParameter("Search Margin") ? c.get<double>("Search Margin") : 0.5 * largest;
  options.minimumSinAngle = c.get<double>("Parallel Line Tolerance");
  options.hermitePointAxes = c.get<std::string>("Point Contact Axes") == "Hermite";
  options.allowInitialPenetration = c.get<bool>("Allow Initial Penetration");
  options.lineAngle = c.get<double>("Line Contact Angle") * std::acos(-1.0) / 180.0;
  options.pointAngle = c.get<double>("Point Contact Angle") * std::acos(-1.0) / 180.0;
  if (options.lineAngle > 0.0 && !(options.pointAngle > options.lineAngle))
    throw InputError("parameter \"" + path + "/Point Contact Angle\" (" +
                     std::to_string(c.get<double>("Point Contact Angle")) + ") must exceed \"" + path +
                     "/Line Contact Angle\" (" + std::to_string(c.get<double>("Line Contact Angle")) + ")");
  options.lineGaussPoints = c.get<int>("Line Gauss Points");
  options.frictionLaw = c.get<std::string>("Friction Law") == "Per Line" ? constraints::FrictionLaw::PerLine
                                                                         : constraints::FrictionLaw::IsotropicCoulomb;
  for (const auto& c : p.model.contributions)
    if (const auto* pins = dynamic_cast<const elements::PinnedJoints*>(c.get()))
      for (const auto& j : pins->joints()) options.joinedNodes.push_back({j.nodeA, j.nodeB});
  for (const core::Support& s : p.model.supports)
    for (int n : s.nodes)
      for (int c = 0; c < 6; ++c)
        if (s.fixed[c]) options.heldNodes[n][c] = true;
  return options;
}

void buildContact(Problem& p, ParameterList& c, const std::string& path) {
  contactSpec().apply(c, path);
  std::vector<constraints::ContactPairSpec> pairs = contactPairs(p, c, path);
  auto enforcer = constraints::enforcerFromDeck(c.sublist("Enforcement"), path + "/Enforcement");
  const constraints::ContactOptions options = contactOptions(p, c, path);
  auto manager = std::make_shared<constraints::ContactManager>(p.beams, std::move(pairs), std::move(enforcer), options);
  manager->initialize(p.model.initial);
  p.contact = manager;
  p.model.contributions.push_back(manager);
}

core::LoadCurve loadCurve(const ParameterList& item, const std::string& path) {
  core::LoadCurve c;
  if (!item.isParameter("Load Curve")) return c;
  const auto& a = item.get<Array<double>>("Load Curve");
  const std::string where = "parameter \"" + path + "/Load Curve\"";
  if (a.size() < 4 || a.size() % 2 != 0)
    throw InputError(where + " must hold pairs T, f (at least two: T = 0 and T = 1), got " + std::to_string(a.size()) +
                     " numbers");
  for (std::size_t i = 0; i < std::size_t(a.size()); i += 2) {
    if (!std::isfinite(a[i]) || !std::isfinite(a[i + 1])) throw InputError(where + " must be finite");
    if (!c.points.empty() && !(a[i] > c.points.back().first))
      throw InputError(where + ": T must increase from pair to pair, got " + std::to_string(c.points.back().first) +
                       " then " + std::to_string(a[i]));
    c.points.emplace_back(a[i], a[i + 1]);
  }
  if (c.points.front().first != 0.0 || c.points.back().first != 1.0)
    throw InputError(where + " must start at T = 0 and end at T = 1");
  return c;
}

// Nodes closer than this are at the same place (joints): 1e-9 of the model's bounding-box diagonal.
double coincidenceTolerance(const std::vector<Vec3d>& reference) {
  Vec3d lo = reference[0], hi = reference[0];
  for (const Vec3d& x : reference)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], x[k]);
      hi[k] = std::max(hi[k], x[k]);
    }
  return 1e-9 * std::max(norm(hi - lo), 1e-300);
}

// Joints: a beam end that coincides (within 1e-9 of the model's extent) with a node of another beam,
// its end or an interior node, shares that node, so the beams are rigidly joined there: displacements
// and rotations are continuous. Nodes of two beams that coincide away from both beams' ends are not
// joined (crossing beams touch through contact, if at all). Renumbers the nodes (first appearance
// order) and returns how many nodes were shared.
int joinCoincidentNodes(std::vector<elements::Beam>& beams, std::vector<Vec3d>& reference,
                        const std::set<std::pair<int, int>>& forced, const std::set<std::pair<int, int>>& kept,
                        std::vector<int>& newId) {
  const std::size_t n = reference.size();
  std::vector<int> owner(n, -1);
  std::vector<char> isEnd(n, 0);
  for (std::size_t b = 0; b < beams.size(); ++b) {
    for (int node : beams[b].nodes) owner[node] = static_cast<int>(b);
    isEnd[beams[b].nodes.front()] = isEnd[beams[b].nodes.back()] = 1;
  }
  Vec3d lo = reference[0];
  for (const Vec3d& x : reference)
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], x[k]);
  const double tol = coincidenceTolerance(reference);
  // Nodes hashed into cells of size tol: a node within tol of another lies in a neighbouring cell.
  auto cell = [&](const Vec3d& x, int k) { return static_cast<long long>(std::floor((x[k] - lo[k]) / tol)); };
  auto key = [](long long i, long long j, long long k) {
    return (i * 73856093LL) ^ (j * 19349663LL) ^ (k * 83492791LL);
  };
  std::unordered_map<long long, std::vector<int>> grid;
  std::vector<int> rep(n);
  std::iota(rep.begin(), rep.end(), 0);
  int shared = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3d& x = reference[i];
    const long long ci = cell(x, 0), cj = cell(x, 1), ck = cell(x, 2);
    for (long long a = ci - 1; a <= ci + 1 && rep[i] == int(i); ++a)
      for (long long b = cj - 1; b <= cj + 1 && rep[i] == int(i); ++b)
        for (long long c = ck - 1; c <= ck + 1 && rep[i] == int(i); ++c) {
          const auto it = grid.find(key(a, b, c));
          if (it == grid.end()) continue;
          for (int j : it->second) {
            const auto pair = std::make_pair(std::min<int>(i, j), std::max<int>(i, j));
            if (kept.count(pair)) continue;
            if (owner[j] != owner[i] && (isEnd[i] || isEnd[j] || forced.count(pair)) && norm(reference[j] - x) <= tol) {
              rep[i] = rep[j];
              ++shared;
              break;
            }
          }
        }
    grid[key(ci, cj, ck)].push_back(static_cast<int>(i));
  }
  std::vector<int>& id = newId;
  id.assign(n, -1);
  std::vector<Vec3d> merged;
  for (std::size_t i = 0; i < n; ++i)
    if (rep[i] == int(i)) {
      id[i] = static_cast<int>(merged.size());
      merged.push_back(reference[i]);
    }
  for (std::size_t i = 0; i < n; ++i) id[i] = id[rep[i]];
  for (auto& beam : beams)
    for (int& node : beam.nodes) node = id[node];
  reference = std::move(merged);
  return shared;
}

// A beam's section and material (sublists Section and Material of item `b`).
elements::Beam beamSectionAndMaterial(ParameterList& b, const std::string& name, const std::string& path) {
  sectionSpec().apply(b.sublist("Section"), path + "/Section");
  if (!b.isSublist("Material")) throw InputError("missing required sublist \"" + path + "/Material\"");
  materialSpec().apply(b.sublist("Material"), path + "/Material");
  const ParameterList& sec = b.sublist("Section");
  elements::Beam beam;
  beam.name = name;
  if (sec.get<std::string>("Shape") == "Rectangle") {
    for (const char* k : {"Width", "Height"})
      if (!sec.isParameter(k))
        throw InputError("missing required parameter \"" + path + "/Section/" + k + "\" for a Rectangle");
    if (sec.isParameter("Radius"))
      throw InputError("parameter \"" + path + "/Section/Radius\" does not apply to a Rectangle");
    beam.section = elements::CrossSection::rectangle(sec.get<double>("Width"), sec.get<double>("Height"));
  } else {
    if (!sec.isParameter("Radius"))
      throw InputError("missing required parameter \"" + path + "/Section/Radius\" for a Circle");
    if (sec.isParameter("Width") || sec.isParameter("Height"))
      throw InputError("parameters Width/Height in \"" + path + "/Section\" do not apply to a Circle");
    beam.section = elements::CrossSection::circle(sec.get<double>("Radius"));
  }
  beam.material.youngsModulus = b.sublist("Material").get<double>("Young's Modulus");
  beam.material.poissonsRatio = b.sublist("Material").get<double>("Poisson's Ratio");
  if (sec.isParameter("Torsion Constant")) beam.section.givenTorsionConstant = sec.get<double>("Torsion Constant");
  return beam;
}

// A beam's elements have a length and a section orientation across them.
// (`given`: the deck sets Section Orientation; else the default the beam's shape chose, which a message
// must not blame on a parameter the deck does not have.)
void checkElements(const elements::Beam& beam, const std::vector<Vec3d>& points, const std::string& path, bool given) {
  for (std::size_t k = 0; k + 1 < points.size(); ++k) {
    const Vec3d axis = points[k + 1] - points[k];
    const double L = norm(axis);
    if (!(L > 0.0)) throw InputError("beam \"" + path + "\" has an element of zero length (coincident points)");
    // An element that turns back along the one before lies inside it: the beam overlaps itself (a
    // polyline retracing a segment, an arc of 360 degrees in 2 elements).
    if (k > 0) {
      const Vec3d before = points[k] - points[k - 1];
      const double c = dot(before, axis) / (norm(before) * L);
      if (c < -0.999)
        throw InputError("beam \"" + path + "\": elements " + std::to_string(k - 1) + " and " + std::to_string(k) +
                         " turn back along each other (by " +
                         std::to_string(static_cast<int>(std::lround(std::acos(std::max(-1.0, c)) * 180.0 / M_PI))) +
                         " degrees): the beam would overlap itself; give its points (or more elements of a curve) so "
                         "that no element turns back");
    }
    if (norm(cross(beam.sectionY, (1.0 / L) * axis)) <= 1e-8 * norm(beam.sectionY)) {
      if (given)
        throw InputError("parameter \"" + path + "/Section Orientation\" is zero or parallel to element " +
                         std::to_string(k) + " of the beam (give a direction across the beam)");
      std::ostringstream m;
      m << "beam \"" << path << "\": the default section orientation (" << beam.sectionY[0] << ", " << beam.sectionY[1]
        << ", " << beam.sectionY[2] << "), chosen from the beam's first element, lies along element " << k
        << " (elements of one beam turning through that direction, or too few elements per turn of a curve): give "
           "\"Section Orientation\", a direction across every element (for a beam in the XY plane: {0, 0, 1})";
      throw InputError(m.str());
    }
  }
}

// A beam is slender and its stiffness representable.
void checkBeamScale(const elements::Beam& beam, const std::vector<Vec3d>& points, const std::string& path) {
  // A section wider than its beam is no beam (the model is a slender beam: sections much smaller than
  // the length). Measured: Width 1e6 on Example 1's 100 long cantilever made the tangent's condition
  // bound 4e17, and the run stopped with a failed linear solve blaming a free motion.
  double length = 0.0;
  for (std::size_t k = 0; k + 1 < points.size(); ++k) length += norm(points[k + 1] - points[k]);
  {
    const bool circle = beam.section.shape == elements::CrossSection::Shape::Circle;
    const double extent = circle ? 2.0 * beam.section.radius : std::max(beam.section.width, beam.section.height);
    const char* what = circle ? "Radius" : beam.section.width >= beam.section.height ? "Width" : "Height";
    if (extent > length) {
      std::ostringstream m;
      m << "parameter \"" << path << "/Section/" << what << "\": " << (circle ? "a diameter of " : "") << extent
        << " exceeds the beam's length " << length
        << "; a section larger than its beam is not a beam (the model is a slender beam, its section much "
           "smaller than its length)";
      throw InputError(m.str());
    }
  }
  // The forces of a beam scale with E A: outside 1e-100 .. 1e100 they underflow or overflow when the
  // solver squares them for its norms (measured: E = 1e-300 on Example 1 gave forces of 1e-298, whose
  // norm was 0, and every step passed as converged without a solve).
  const double EA = beam.material.youngsModulus * beam.section.area();
  if (!(EA >= 1e-100 && EA <= 1e100)) {
    std::ostringstream m;
    m << "parameter \"" << path << "/Material/Young's Modulus\": " << beam.material.youngsModulus
      << " makes the beam's axial stiffness E A = " << EA
      << ", outside 1e-100 to 1e100: forces on that scale underflow or overflow in double precision; choose "
         "units in which E A is nearer 1";
    throw InputError(m.str());
  }
}

// The beams as read, before joints: their nodes numbered beam after beam.
struct BeamsRead {
  std::vector<elements::Beam> beams;
  std::vector<Vec3d> reference;
};

BeamsRead readBeams(Problem& p, ParameterList& deck, const std::string& top) {
  BeamsRead read;
  ParameterList& beamList = deck.sublist("Beams");
  if (beamList.numParams() == 0) throw InputError("\"" + top + "/Beams\" holds no beam");
  forEachItem(beamList, top + "/Beams", beamSpec(),
              [&](ParameterList& b, const std::string& name, const std::string& path) {
                elements::Beam beam = beamSectionAndMaterial(b, name, path);
                const int ne = b.get<int>("Elements");
                const std::vector<Vec3d> points = beamPoints(b, path, ne, beam.sectionY);
                checkElements(beam, points, path, b.isParameter("Section Orientation"));
                checkBeamScale(beam, points, path);
                checkModelSize(read.reference.size() + points.size());
                const int first = static_cast<int>(read.reference.size());
                for (std::size_t k = 0; k < points.size(); ++k) {
                  read.reference.push_back(points[k]);
                  beam.nodes.push_back(first + static_cast<int>(k));
                }
                p.beamIndex[name] = static_cast<int>(read.beams.size());
                read.beams.push_back(beam);
              });
  return read;
}

// Explicit joints: (beam, node) pairs that must coincide; Rigid ones are merged even between interior
// nodes, Pinned ones are kept apart and tied by the PinnedJoints contribution.
struct JointsRead {
  std::set<std::pair<int, int>> forced, kept;
  std::vector<elements::PinnedJoint> pins;
};

// The two nodes (before joining) a joint item `j` names.
std::array<int, 2> jointNodes(const Problem& p, const BeamsRead& read, const ParameterList& j,
                              const std::string& path) {
  std::array<int, 2> ends{0, 0};
  for (int s = 0; s < 2; ++s) {
    const std::string key = s == 0 ? "A" : "B";
    const std::string beam = j.get<std::string>("Beam " + key);
    const auto& nodes = read.beams[beamNamed(p.beamIndex, beam, path + "/Beam " + key)].nodes;
    const std::string node = j.get<std::string>("Node " + key);
    if (s == 0 && node != "start" && node != "end")
      throw InputError("parameter \"" + path +
                       "/Node A\": a joint starts at a beam end, \"start\" or "
                       "\"end\", not \"" +
                       node + "\"");
    ends[s] = nodes[nodeIndexOnBeam(node, static_cast<int>(nodes.size()) - 1, path + "/Node " + key, beam)];
  }
  return ends;
}

JointsRead readJoints(const Problem& p, const BeamsRead& read, ParameterList& deck, const std::string& top) {
  JointsRead joints;
  if (!deck.isSublist("Joints")) return joints;
  const double tolerance = coincidenceTolerance(read.reference);
  forEachItem(deck.sublist("Joints"), top + "/Joints", jointSpec(),
              [&](ParameterList& j, const std::string& name, const std::string& path) {
                const std::array<int, 2> ends = jointNodes(p, read, j, path);
                if (j.get<std::string>("Beam A") == j.get<std::string>("Beam B"))
                  throw InputError("\"" + path + "\" joins beam \"" + j.get<std::string>("Beam A") + "\" to itself");
                const double d = norm(read.reference[ends[0]] - read.reference[ends[1]]);
                if (d > tolerance)
                  throw InputError("\"" + path + "\" joins nodes " + std::to_string(d) +
                                   " apart; a joint's two nodes must be at the same place");
                const auto pair = std::make_pair(std::min(ends[0], ends[1]), std::max(ends[0], ends[1]));
                if (j.get<std::string>("Type") == "Pinned") {
                  joints.kept.insert(pair);
                  joints.pins.push_back({name, ends[0], ends[1]});
                } else {
                  joints.forced.insert(pair);
                }
              });
  return joints;
}

// Joins the beams' coincident nodes and ties the pinned joints; the model's beams and initial state.
void joinBeams(Problem& p, BeamsRead& read, JointsRead& joints) {
  std::vector<int> newId;
  p.joints = joinCoincidentNodes(read.beams, read.reference, joints.forced, joints.kept, newId);
  for (auto& pin : joints.pins) {
    pin.nodeA = newId[pin.nodeA];
    pin.nodeB = newId[pin.nodeB];
    if (pin.nodeA == pin.nodeB)
      throw InputError("pinned joint \"" + pin.name +
                       "\": its nodes are also rigidly joined (through a third beam "
                       "or another joint)");
    p.pins.emplace_back(pin.nodeA, pin.nodeB);
  }
  core::State& state = p.model.initial;
  state.resize(static_cast<int>(read.reference.size()));
  state.reference = read.reference;
  state.position = read.reference;
  for (const auto& beam : read.beams) p.beams->addBeam(beam, read.reference);
  p.model.contributions.push_back(p.beams);
  p.joints += static_cast<int>(joints.pins.size());
  if (!joints.pins.empty()) p.model.contributions.push_back(std::make_shared<elements::PinnedJoints>(joints.pins));
}

void readSupports(Problem& p, ParameterList& deck, const std::string& top, const Locator& locate) {
  forEachItem(deck.sublist("Supports"), top + "/Supports", supportSpec(),
              [&](ParameterList& s, const std::string& name, const std::string& path) {
                core::Support sup;
                sup.name = name;
                sup.nodes = locate.nodes(s, path, true);
                sup.fixed = parseFixed(s.get<std::string>("Fixed"), path);
                const auto d = s.get<Array<double>>("Displacement"), r = s.get<Array<double>>("Rotation");
                for (int k = 0; k < 6; ++k) {
                  sup.value[k] = k < 3 ? d[k] : r[k - 3];
                  if (sup.value[k] != 0.0 && !sup.fixed[k])
                    throw InputError("parameter \"" + path + (k < 3 ? "/Displacement" : "/Rotation") +
                                     "\": a nonzero value is given for " + kComponents[k] + ", which is not in Fixed");
                }
                sup.curve = loadCurve(s, path);
                p.model.supports.push_back(sup);
              });
  // A component two supports prescribe differently: only the later would hold (a copied support
  // whose sign was not changed). The same motion twice (both hold a clamped end) is fine, and so is a
  // later support moving a component an earlier one holds at zero (press, then slide: the pressing
  // support fixes ux, the drag moves it); the later holding a component an earlier one moves is not.
  std::map<long long, int> first;  // node * 6 + component -> the first support prescribing it
  const auto& supports = p.model.supports;
  for (int i = 0; i < static_cast<int>(supports.size()); ++i)
    for (const int node : supports[i].nodes)
      for (int k = 0; k < 6; ++k) {
        if (!supports[i].fixed[k]) continue;
        const auto [it, fresh] = first.emplace(6LL * node + k, i);
        if (fresh) continue;
        const core::Support& a = supports[it->second];
        const core::Support& b = supports[i];
        const bool same = a.value[k] == b.value[k] && (a.value[k] == 0.0 || a.curve.points == b.curve.points);
        if (same || a.value[k] == 0.0) {
          it->second = i;  // (the later's motion is applied; a third is compared with it)
          continue;
        }
        const auto& x = p.model.initial.reference[node];
        std::ostringstream m;
        m << "supports \"" << a.name << "\" and \"" << b.name << "\" both prescribe " << kComponents[k]
          << " of the node at (" << x[0] << ", " << x[1] << ", " << x[2] << "), differently (" << a.value[k] << " and "
          << b.value[k] << " at T = 1" << (a.value[k] == b.value[k] ? ", with different Load Curves" : "")
          << "): only one motion can hold there (a later support may move what an earlier one holds at zero, "
             "not the reverse); remove "
          << kComponents[k] << " from one support's Fixed";
        throw InputError(m.str());
      }
}

void readLoads(Problem& p, ParameterList& deck, const std::string& top, const Locator& locate) {
  // (Both default to zero: a load that gives neither, e.g. with "Forces" misspelt as a sublist's
  // name, would apply nothing.)
  const ParameterList& loads = deck.sublist("Loads");
  for (auto it = loads.begin(); it != loads.end(); ++it)
    if (const std::string& name = loads.name(it); loads.isSublist(name) && !loads.sublist(name).isParameter("Force") &&
                                                  !loads.sublist(name).isParameter("Moment"))
      throw InputError("load \"" + top + "/Loads/" + name +
                       "\" gives neither \"Force\" nor \"Moment\": it would apply nothing; give one of them");
  forEachItem(deck.sublist("Loads"), top + "/Loads", loadSpec(),
              [&](ParameterList& l, const std::string& name, const std::string& path) {
                core::NodalLoad load;
                load.name = name;
                load.node = locate.nodes(l, path, false).front();
                const auto f = l.get<Array<double>>("Force"), m = l.get<Array<double>>("Moment");
                for (int k = 0; k < 3; ++k) {
                  load.value[k] = f[k];
                  load.value[3 + k] = m[k];
                }
                load.curve = loadCurve(l, path);
                p.model.loads.push_back(load);
              });
}

// Load Stepping, Nonlinear Solver and Linear Solver.
void readSolvers(Problem& p, ParameterList& deck, const std::string& top) {
  ParameterList& stepping = deck.sublist("Load Stepping");
  // Load Factors replace Number of Increments: a deck (or a study varying one of them) that gives
  // both would run one and silently ignore the other.
  const bool factors = stepping.isParameter("Load Factors");
  if (factors && stepping.isParameter("Number of Increments"))
    throw InputError("\"" + top +
                     "/Load Stepping\" gives both \"Load Factors\" and \"Number of Increments\": "
                     "Load Factors replace the increments; give one of them");
  core::loadSteppingSpec().apply(stepping, top + "/Load Stepping");
  if (factors) stepping.remove("Number of Increments", false);  // its default, unused
  ParameterList& newton = deck.sublist("Nonlinear Solver");
  core::newtonSpec().apply(newton, top + "/Nonlinear Solver");
  p.solver = core::readSolverSettings(stepping, newton);
  ParameterList& linear = deck.sublist("Linear Solver");
  core::applyLinearSolverParameters(linear, top + "/Linear Solver");
  p.linearSolver = linear;
}

void readOutput(Problem& p, ParameterList& deck, const std::string& top, const std::string& deckName,
                const Locator& locate) {
  ParameterList& out = deck.sublist("Output");
  outputSpec().apply(out, top + "/Output");
  p.writeVtk = out.get<bool>("Write VTK");
  p.outputDirectory = out.isParameter("Directory") ? out.get<std::string>("Directory") : "results/" + deckName;
  if (p.outputDirectory.find_first_not_of(" \t") == std::string::npos)
    throw InputError("parameter \"" + top +
                     "/Output/Directory\" is empty; name a directory (or leave the "
                     "parameter out for results/" +
                     deckName + ")");
  p.checkpointEvery = out.get<int>("Checkpoint Every");
  p.vtkEvery = out.get<int>("VTK Every");
  p.vtkCompression = out.get<bool>("VTK Compression");
  if (out.isParameter("VTK At")) {
    const auto& at = out.get<Array<double>>("VTK At");
    const std::string where = "parameter \"" + top + "/Output/VTK At\"";
    for (double T : at) {
      if (!(T > 0.0 && T <= 1.0))
        throw InputError(where + ": load factors must lie in (0, 1], got " + core::shortest(T));
      if (!p.vtkAt.empty() && !(T > p.vtkAt.back()))
        throw InputError(where + ": load factors must increase, got " + core::shortest(p.vtkAt.back()) + " then " +
                         core::shortest(T));
      p.vtkAt.push_back(T);
    }
  }
  forEachItem(out.sublist("Tracked Points"), top + "/Output/Tracked Points", trackedSpec(),
              [&](ParameterList& t, const std::string& name, const std::string& path) {
                p.model.tracked.push_back({name, locate.nodes(t, path, false).front()});
              });
}

// A given penalty parameter so far above the beams' stiffness that theirs is lost in the matrix's
// round-off: the solve fails as singular, a message blaming the supports. (eps_N 1e30 on beams of
// E A / L = 3e5.) The bound, 1e10 times the stiffest element's E A / L, leaves the beams 1e-6 of
// double precision; the paper's examples use 1e-2 to 3e2 times theirs.
void checkPenaltyScale(const Problem& p, const ParameterList& enforcement, const std::string& path) {
  double stiffest = 0.0;
  for (const auto& e : p.beams->elements()) {
    const auto& beam = p.beams->beams()[e.beam];
    stiffest = std::max(stiffest, beam.material.youngsModulus * beam.section.area() / e.data.L0);
  }
  if (!(stiffest > 0.0) || !enforcement.isParameter("Type")) return;
  const std::string type = enforcement.get<std::string>("Type");
  if (!enforcement.isSublist(type)) return;
  const ParameterList& own = enforcement.sublist(type);
  for (const char* name : {"Normal Penalty Parameter", "Tangential Penalty Parameter"}) {
    if (!own.isType<double>(name)) continue;
    const double eps = own.get<double>(name);
    if (!(eps > 1e10 * stiffest)) continue;
    std::ostringstream m;
    m << "parameter \"" << path << "/" << type << "/" << name << "\" = " << eps << " is " << eps / stiffest
      << " times the stiffest element's E A / L (" << stiffest
      << "): the beams' own stiffness would be lost in the matrix's round-off (a singular solve); choose at most 1e10 "
         "times it, or \"Automatic\"";
    throw InputError(m.str());
  }
}

// Penalty's springs on the line's nodes take the lines' friction as springs eps_T on the field's
// weighted slips with the Isotropic Coulomb law; the Per Line law's stick and slip on the nodes are
// Lagrange's rigid ones (a slipping node sticks again only when its slip turns round), which a spring's
// elastic slip never does: its nodes stayed at the cone (50 times the friction of springs at the Gauss
// points, measured). Refused rather than answered wrongly, on the pairs as built (All Pairs too).
void checkLineSpringsFriction(const Problem& p, ParameterList& contact, const std::string& path) {
  const auto& enforcer = p.contact->enforcer();
  if (enforcer.type() != "Penalty" || !enforcer.lineFieldPenalized() ||
      contact.get<std::string>("Friction Law") != "Per Line" || !(contact.get<double>("Line Contact Angle") > 0.0))
    return;
  for (const auto& pair : p.contact->pairs())
    if (pair.friction > 0.0)
      throw InputError("parameter \"" + path + "/Friction Law\" = \"Per Line\" and \"" + path +
                       "/Enforcement/Penalty/Line Springs\" = \"Nodes\" with friction on pair \"" + pair.name +
                       "\": the springs on the line's nodes take the lines' friction with the Isotropic Coulomb law "
                       "only; use Friction Law = Isotropic Coulomb, or Line Springs = Gauss Points");
}

// Contact (when the deck has it), its memory estimate, and the linear solver it needs.
void readContact(Problem& p, ParameterList& deck, const std::string& top) {
  if (deck.isSublist("Contact")) {
    buildContact(p, deck.sublist("Contact"), top + "/Contact");
    checkPenaltyScale(p, deck.sublist("Contact").sublist("Enforcement"), top + "/Contact/Enforcement");
    checkLineSpringsFriction(p, deck.sublist("Contact"), top + "/Contact");
    // (Multipliers, and a plug-in's strategy, at the larger cost per point.)
    const std::string type = deck.sublist("Contact").sublist("Enforcement").get<std::string>("Type");
    const bool builtIn = constraints::findEnforcer(type, top + "/Contact/Enforcement/Type").origin == "built-in";
    checkModelSize(p.beams->elements().size(), p.contact->points().size(),
                   builtIn && !p.contact->addsMultiplierRows() ? kBytesPerPointPenalty : kBytesPerPointLagrange);
  }
  const ParameterList& linear = p.linearSolver;
  if (linear.get<std::string>("Type") == "GMRES" && linear.get<std::string>("Preconditioner") == "MueLu" && p.contact &&
      p.contact->addsMultiplierRows())
    throw InputError("parameter \"" + top +
                     "/Linear Solver/Preconditioner\" = \"MueLu\" preconditions matrices of "
                     "nodal dofs only, and \"" +
                     top + "/Contact/Enforcement/Type\" = \"" +
                     deck.sublist("Contact").sublist("Enforcement").get<std::string>("Type") +
                     "\" adds multiplier rows (Lagrange Multiplier at every point; Augmented Lagrange, and Penalty "
                     "with Line Springs = Nodes, on the lines of line contact): use Penalty (Line Springs = Gauss "
                     "Points) with it, or Augmented Lagrange with " +
                     top + "/Contact/Line Contact Angle = 0, or Linear Solver/Type = Direct");
}

}  // namespace

ParameterList readDeckFile(const std::string& path, std::string* sha256) {
  if (!std::filesystem::exists(path)) throw InputError("deck file \"" + path + "\" does not exist");
  return readParameterXmlFile(path, sha256);
}

Problem buildProblem(ParameterList deck, const std::string& deckName) {
  Problem p;
  const std::string top = "BeamContact";
  if (deck.name() != top && deck.name() != "ANONYMOUS")
    throw InputError("the deck's top-level ParameterList must be named \"" + top + "\", not \"" + deck.name() + "\"");
  topSpec().apply(deck, top);
  for (const char* required : {"Beams"})
    if (!deck.isSublist(required)) throw InputError("missing required sublist \"" + top + "/" + required + "\"");
  for (const char* sub : {"Supports", "Loads", "Load Stepping", "Nonlinear Solver", "Linear Solver", "Output"})
    deck.sublist(sub);

  p.beams = std::make_shared<elements::BeamSet>();
  BeamsRead beams = readBeams(p, deck, top);
  JointsRead joints = readJoints(p, beams, deck, top);
  joinBeams(p, beams, joints);
  const Locator locate(p, p.model.initial);
  readSupports(p, deck, top, locate);
  readLoads(p, deck, top, locate);
  readSolvers(p, deck, top);
  readOutput(p, deck, top, deckName, locate);
  readContact(p, deck, top);

  if (p.model.supports.empty())
    throw InputError("\"" + top + "/Supports\" is empty: the structure would be free to move as a rigid body");
  checkDuplicateBeams(p);
  checkRigidBodyMotions(p);
  p.effective = deck;
  return p;
}

std::string deckFingerprint(const Problem& problem) {
  // The Output sublist may change between a run and its restart (where VTK files go, how often),
  // except its tracked points: tracked_points.csv's columns are theirs, and rows of other points
  // under the same header would pass for the same quantities.
  ParameterList deck = problem.effective;
  const bool tracked = deck.sublist("Output").isSublist("Tracked Points");
  const ParameterList points = tracked ? deck.sublist("Output").sublist("Tracked Points") : ParameterList();
  deck.remove("Output", false);
  if (tracked) deck.sublist("Output").sublist("Tracked Points").setParameters(points);
  std::ostringstream xml;
  Teuchos::writeParameterListToXmlOStream(deck, xml);
  char hex[32];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(core::fingerprint(xml.str())));
  return hex;
}

ParameterList referenceParameters() {
  ParameterList ref("BeamContact");
  ref.setParameters(topSpec().reference());
  ParameterList beam = beamSpec().reference();
  ref.sublist("Beams").sublist("<beam name>", false, "one sublist per beam").setParameters(beam);
  ref.sublist("Supports").sublist("<support name>").setParameters(supportSpec().reference());
  ref.sublist("Loads").sublist("<load name>").setParameters(loadSpec().reference());
  ref.sublist("Output").sublist("Tracked Points").sublist("<point name>").setParameters(trackedSpec().reference());
  ref.sublist("Contact").sublist("Pairs").sublist("<pair name>").setParameters(contactPairSpec().reference());
  ref.sublist("Contact").sublist("Enforcement").setParameters(constraints::enforcementReference());
  ref.sublist("Joints").sublist("<joint name>").setParameters(jointSpec().reference());
  return ref;
}

}  // namespace bc::input
