// The CSV balance test: statics checked from a run's written files alone (reactions.csv,
// contact_points.csv, tracked_points.csv, steps.csv) with the deck's loads and reference nodes, at
// every converged step of the paper's Examples 1-3, input/parallel_rods.xml, press-then-slide (two
// supports on each end node of beam 2) and a line contact whose Augmented Lagrange points carry forces
// at positive gaps (also slid with friction), with every strategy, and the twisting rods (three
// supports on one node) with Penalty.
//
// What must hold (the source of each expected value: statics of the discrete model):
//  1. The whole model: every residual contribution but the loads is internal (the beams' and the
//     contact's residuals do not change under a rigid motion, so their forces sum to zero and their
//     moments about any point too), so the supports' reactions plus the applied loads sum to zero,
//     forces and moments about the origin (a reaction's moment about the origin: x_n x F_n + M_n at
//     its node's current place, read from tracked_points.csv).
//  2. Each free body (beams connected by shared nodes or pinned joints): its supports' reactions, its
//     loads and the contact forces on it sum to zero. contact_points.csv gives each point's force on
//     the pair's beam B; beam A takes minus that (equal and opposite). A body passes only if the
//     table's force vectors are the forces the residual applied, on both beams.
//  3. Each row of contact_points.csv: the normal force column N is the normal part of the force
//     vector, N = F_N . n (an Augmented Lagrange point at a positive gap had N > 0 and a zero vector).
// Tolerances: 1e-8 of the force scale (the largest reaction, load or contact force component of the
// step) plus what Newton leaves unbalanced: the residual at the free dofs, whose components sum to at
// most sqrt(dofs) ||r|| (Cauchy-Schwarz; ||r|| the step's final residual in steps.csv), and for
// moments that times (1 + the largest distance from the origin).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <numeric>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "support/ContactDecks.hpp"

using namespace bc;
using namespace bc::test;

namespace {

using V3 = std::array<double, 3>;

V3 cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// A CSV file of the results directory: its header and rows, a value by column name.
struct Csv {
  std::map<std::string, std::size_t> column;
  std::vector<std::vector<std::string>> rows;
  double at(std::size_t row, const std::string& name) const {
    const auto c = column.find(name);
    if (c == column.end()) throw std::runtime_error("no column \"" + name + "\"");
    return std::stod(rows[row].at(c->second));
  }
  const std::string& text(std::size_t row, const std::string& name) const { return rows[row].at(column.at(name)); }
};

Csv readCsv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  Csv csv;
  std::string line;
  std::getline(in, line);
  std::stringstream hs(line);
  for (std::string h; std::getline(hs, h, ',');) csv.column[h] = csv.column.size();
  while (std::getline(in, line)) {
    std::vector<std::string> row;
    std::stringstream ls(line);
    for (std::string v; std::getline(ls, v, ',');) row.push_back(v);
    EXPECT_EQ(row.size(), csv.column.size()) << path << ": a row of another length: " << line;
    csv.rows.push_back(row);
  }
  return csv;
}

// The largest imbalances found in a run, relative to their tolerances, and in absolute numbers.
struct Worst {
  double force = 0.0, moment = 0.0, body = 0.0, normal = 0.0;  // imbalance / tolerance
  double forceAbs = 0.0, momentAbs = 0.0, bodyAbs = 0.0;  // the largest imbalances
  double scale = 0.0, length = 0.0;  // the run's largest force component and distance from the origin
  int steps = 0, bodies = 0, rows = 0;
};

// Tracked points named "node <n>" at every node that holds a support or a load (by its reference
// coordinates), so that tracked_points.csv gives their current places.
Deck withTrackedNodes(Deck deck, const std::string& name) {
  const input::Problem p = input::buildProblem(deck, name);
  std::set<int> nodes;
  for (const auto& s : p.model.supports) nodes.insert(s.nodes.begin(), s.nodes.end());
  for (const auto& l : p.model.loads) nodes.insert(l.node);
  for (int n : nodes) {
    Deck& t = input::sublistAtPath(deck, "Output/Tracked Points/node " + std::to_string(n));
    const auto& x = p.model.initial.reference[n];
    t.set("Point", Teuchos::Array<double>(std::vector<double>{x[0], x[1], x[2]}));
  }
  input::setAtPath(deck, "Output/Write VTK", false);
  return deck;
}

// Runs `deck` and checks 1-3 above at every step from the written CSV files; returns the worst ratios.
Worst runAndBalance(const Deck& original, const std::string& name) {
  Worst w;
  const Deck deck = withTrackedNodes(original, name);
  auto p = input::buildProblem(deck, name);
  // Each tracked point lies at the node it was put at (no other node at that place comes first).
  for (const auto& t : p.model.tracked)
    if (t.name.rfind("node ", 0) == 0) {
      EXPECT_EQ(t.name, "node " + std::to_string(t.node)) << name;
    }
  const auto r = test::runQuiet(p, Tpetra::getDefaultComm(), name);
  EXPECT_TRUE(r.report.completed) << name << ": " << r.report.failure;
  if (!r.report.completed) return w;
  const std::string dir = test::scratchDirectory(name + "_np1");
  const Csv steps = readCsv(dir + "/steps.csv"), reactions = readCsv(dir + "/reactions.csv"),
            tracked = readCsv(dir + "/tracked_points.csv"), contact = readCsv(dir + "/contact_points.csv");
  EXPECT_EQ(steps.rows.size(), reactions.rows.size()) << name;
  EXPECT_EQ(steps.rows.size(), tracked.rows.size()) << name;

  // Free bodies: beams joined through shared nodes or pinned joints (union-find over the beams).
  const auto& beams = p.beams->beams();
  std::vector<int> parent(beams.size());
  std::iota(parent.begin(), parent.end(), 0);
  const std::function<int(int)> find = [&](int b) { return parent[b] == b ? b : parent[b] = find(parent[b]); };
  std::map<int, int> beamOfNode;
  for (std::size_t b = 0; b < beams.size(); ++b)
    for (int n : beams[b].nodes) {
      const auto [it, fresh] = beamOfNode.emplace(n, static_cast<int>(b));
      if (!fresh) parent[find(static_cast<int>(b))] = find(it->second);
    }
  for (const auto& [a, b] : p.pins) parent[find(beamOfNode.at(a))] = find(beamOfNode.at(b));
  const auto body = [&](int node) { return find(beamOfNode.at(node)); };
  // A support whose nodes lie on two bodies cannot be split between them from the file: those bodies
  // are not checked alone.
  std::set<int> unstated;
  for (const auto& s : p.model.supports)
    for (int n : s.nodes)
      if (body(n) != body(s.nodes.front())) unstated.insert({body(n), body(s.nodes.front())});
  std::map<std::string, std::pair<int, int>> pairBodies;
  for (const auto& pr : p.contact->pairs()) pairBodies[pr.name] = {find(pr.beamA), find(pr.beamB)};

  double extent = 0.0;
  for (const auto& x : p.model.initial.reference)
    extent = std::max({extent, std::abs(x[0]), std::abs(x[1]), std::abs(x[2])});
  const double dofs = 6.0 * p.model.initial.reference.size();
  std::size_t contactRow = 0;
  for (std::size_t s = 0; s < steps.rows.size(); ++s) {
    const double T = reactions.at(s, "T"), residual = steps.at(s, "final_residual");
    EXPECT_EQ(reactions.text(s, "step"), steps.text(s, "step")) << name;
    // The current place of a tracked node.
    const auto place = [&](int n) {
      V3 x;
      for (int a = 0; a < 3; ++a)
        x[a] = p.model.initial.reference[n][a] +
               tracked.at(s, "node " + std::to_string(n) + "_u" + std::string(1, "xyz"[a]));
      return x;
    };
    double L = extent;
    for (const auto& t : p.model.tracked) {
      if (t.name.rfind("node ", 0) != 0) continue;
      const V3 x = place(t.node);
      L = std::max({L, std::abs(x[0]), std::abs(x[1]), std::abs(x[2])});
    }
    double scale = 0.0;
    V3 force{}, moment{};
    std::map<int, V3> onBody;
    const auto add = [&](int node, const V3& F, const V3& M) {
      const V3 x = place(node), xF = cross(x, F);
      for (int a = 0; a < 3; ++a) {
        force[a] += F[a];
        moment[a] += xF[a] + M[a];
        onBody[body(node)][a] += F[a];
        scale = std::max(scale, std::abs(F[a]));
      }
    };
    for (const auto& sup : p.model.supports) {
      // (A support's reaction is its nodes' sum: with several nodes they must be at one place.)
      for (int n : sup.nodes)
        for (int a = 0; a < 3; ++a) EXPECT_NEAR(place(n)[a], place(sup.nodes.front())[a], 1e-12 * L) << sup.name;
      V3 F, M;
      for (int a = 0; a < 3; ++a) {
        F[a] = reactions.at(s, sup.name + "_F" + std::string(1, "xyz"[a]));
        M[a] = reactions.at(s, sup.name + "_M" + std::string(1, "xyz"[a]));
      }
      add(sup.nodes.front(), F, M);
    }
    for (const auto& l : p.model.loads) {
      const double c = l.curve(T);
      add(l.node, V3{c * l.value[0], c * l.value[1], c * l.value[2]},
          V3{c * l.value[3], c * l.value[4], c * l.value[5]});
    }
    // The contact rows of this step: each point's force on the pair's beam B, minus that on beam A.
    for (; contactRow < contact.rows.size() && contact.text(contactRow, "step") == steps.text(s, "step");
         ++contactRow) {
      V3 F, FN, n;
      for (int a = 0; a < 3; ++a) {
        const std::string c(1, "xyz"[a]);
        FN[a] = contact.at(contactRow, "normal_force_" + c);
        F[a] = FN[a] + contact.at(contactRow, "tangential_force_" + c);
        n[a] = contact.at(contactRow, "normal_" + c);
        scale = std::max(scale, std::abs(F[a]));
      }
      const auto [a, b] = pairBodies.at(contact.text(contactRow, "pair"));
      for (int i = 0; i < 3; ++i) {
        onBody[b][i] += F[i];
        onBody[a][i] -= F[i];
      }
      const double N = contact.at(contactRow, "normal_force");
      const double normalPart = FN[0] * n[0] + FN[1] * n[1] + FN[2] * n[2];
      const double tolN = 1e-9 * std::max({std::abs(N), std::abs(F[0]), std::abs(F[1]), std::abs(F[2]), 1e-300});
      w.normal = std::max(w.normal, std::abs(N - normalPart) / tolN);
      EXPECT_NEAR(N, normalPart, tolN) << name << ", step " << steps.text(s, "step") << ", contact row " << contactRow;
      ++w.rows;
    }
    if (scale == 0.0) continue;
    ++w.steps;
    w.scale = std::max(w.scale, scale);
    w.length = std::max(w.length, L);
    const double unbalanced = std::sqrt(dofs) * residual;
    const double tolF = 1e-8 * scale + unbalanced, tolM = 1e-8 * scale * L + (1.0 + L) * unbalanced;
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(force[a], 0.0, tolF) << name << ", step " << steps.text(s, "step") << ", F"
                                       << "xyz"[a];
      EXPECT_NEAR(moment[a], 0.0, tolM) << name << ", step " << steps.text(s, "step") << ", M"
                                        << "xyz"[a];
      w.force = std::max(w.force, std::abs(force[a]) / tolF);
      w.moment = std::max(w.moment, std::abs(moment[a]) / tolM);
      w.forceAbs = std::max(w.forceAbs, std::abs(force[a]));
      w.momentAbs = std::max(w.momentAbs, std::abs(moment[a]));
    }
    for (const auto& [b, F] : onBody) {
      if (unstated.count(b)) continue;
      ++w.bodies;
      for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(F[a], 0.0, tolF) << name << ", step " << steps.text(s, "step") << ", the body of beam \""
                                     << beams[b].name << "\", F"
                                     << "xyz"[a];
        w.body = std::max(w.body, std::abs(F[a]) / tolF);
        w.bodyAbs = std::max(w.bodyAbs, std::abs(F[a]));
      }
    }
  }
  EXPECT_EQ(contactRow, contact.rows.size()) << name << ": contact rows of steps steps.csv does not have";
  std::printf(
      "%-32s %2d steps %3d contact rows: largest |sum F| %.1e, |sum M| %.1e (/ L), bodies %.1e of the run's "
      "force scale %.4g (of their tolerances: %.3f, %.3f, %.3f; N vs F_N.n %.3f)\n",
      name.c_str(), w.steps, w.rows, w.forceAbs / w.scale, w.momentAbs / (w.scale * w.length), w.bodyAbs / w.scale,
      w.scale, w.force, w.moment, w.body, w.normal);
  EXPECT_GT(w.steps, 0) << name;
  return w;
}

const char* const kStrategies[] = {"Penalty", "Lagrange Multiplier", "Augmented Lagrange"};

std::string tag(const std::string& type) {
  std::string t;
  for (char c : type)
    if (c != ' ') t += c;
  return t;
}

}  // namespace

TEST(CsvBalance, PaperExamples) {
  for (const char* deck : {"example1.xml", "example2.xml", "example3.xml"})
    for (const std::string type : kStrategies) {
      const std::string name = std::string(deck).substr(0, 8) + "_" + tag(type);
      const Worst w = runAndBalance(inputDeck(deck, type), name);
      EXPECT_GT(w.bodies, 0) << name;
    }
}

TEST(CsvBalance, ParallelRods) {
  for (const std::string type : kStrategies) runAndBalance(inputDeck("parallel_rods.xml", type), "rods_" + tag(type));
}

// The layered rods with friction (input/layered_rods.xml): the friction forces' moments about each
// rod's axis (the sections' turns in the slip) enter each body's balance.
TEST(CsvBalance, LayeredRods) {
  for (const std::string type : kStrategies) runAndBalance(inputDeck("layered_rods.xml", type), "layered_" + tag(type));
}

// A rod twisted on a held rod (input/twisted_rod.xml): friction across the axes, its forces applied
// where the surfaces touch, balance the torque with the clamp's and the supports' reactions.
TEST(CsvBalance, TwistedRod) {
  for (const std::string type : kStrategies) runAndBalance(inputDeck("twisted_rod.xml", type), "twisted_" + tag(type));
}

TEST(CsvBalance, PressThenSlideSplitsTheSharedNodesReactions) {
  // Beam 2's end nodes are held by two supports each: "beam 2 end" fixes uz, ry (the press) and
  // "beam 2 end drag" fixes ux (the slide). Each reports the components it fixes, so the file's sum is
  // the total (before: each reported the whole node, and the rows summed to twice its reaction).
  for (const std::string type : kStrategies) {
    const std::string name = "press_slide_" + tag(type);
    runAndBalance(pressThenSlide(type, 0.3, true), name);
    const auto last = lastReactions(test::scratchDirectory(name + "_np1"));
    for (const std::string end : {"beam 2 start", "beam 2 end"}) {
      EXPECT_EQ(last.at(end + "_Fx"), 0.0) << type;
      EXPECT_EQ(last.at(end + " drag_Fz"), 0.0) << type;
      EXPECT_EQ(last.at(end + " drag_My"), 0.0) << type;
      EXPECT_GT(std::abs(last.at(end + " drag_Fx")), 0.0) << type;  // the friction the drag overcomes
      EXPECT_GT(std::abs(last.at(end + "_Fz")), 0.0) << type;
    }
  }
  // A component two supports fix: the pressing support also holds ux (motion 0), the drag support comes
  // later in the deck and moves it. The drag's motion is applied (the last support's), and its
  // reaction is reported once, by the drag; the pressing support's Fx is 0.
  Deck d = pressThenSlide("Penalty", 0.3, true);
  for (const std::string end : {"beam 2 start", "beam 2 end"})
    input::replaceAtPath(d, "Supports/" + end + "/Fixed", std::string("ux uz ry"));
  runAndBalance(d, "press_slide_twice");
  const auto last = lastReactions(test::scratchDirectory("press_slide_twice_np1"));
  const auto slid = lastReactions(test::scratchDirectory("press_slide_Penalty_np1"));
  for (const std::string end : {"beam 2 start", "beam 2 end"}) {
    EXPECT_EQ(last.at(end + "_Fx"), 0.0);
    EXPECT_NEAR(last.at(end + " drag_Fx"), slid.at(end + " drag_Fx"), 1e-9 * std::abs(slid.at(end + " drag_Fx")));
  }
}

TEST(CsvBalance, AugmentedLagrangePointsAtPositiveGapsReportTheirForce) {
  // input/parallel_rods.xml with the upper rod loaded at its middle node only (100 down; E = 1e9): the
  // rods touch over the middle part, and Augmented Lagrange with Gap Tolerance 1e-3 ends with Gauss
  // points at the zone's ends whose gap is positive (9.7e-6) while they carry lambda_hat + eps_N g_N < 0.
  // Before, their force vectors were zero (0.77 % of the pair's N missing: the bodies off by 1.5e-2 of
  // the force scale), and points on slivers of a segment, which the strategy does not judge, reported
  // their stale multipliers (1e-5).
  // With friction 0.3 and the upper rod's ends also moved by 0.5 along X (slid along the lower rod: the
  // line points slip along the axes), the same.
  for (const bool slide : {false, true})
    for (const std::string type : kStrategies) {
      Deck d = inputDeck("parallel_rods.xml", type);
      Deck& loads = input::sublistAtPath(d, "Loads", false);
      for (int n = 0; n <= 10; ++n)
        if (n != 5) loads.remove("q " + std::to_string(n));
      input::replaceAtPath(d, "Loads/q 5/Force", vec("0, 0, -100"));
      input::setAtPath(d, "Contact/Enforcement/Augmented Lagrange/Gap Tolerance", 1e-3);
      if (slide) {
        input::replaceAtPath(d, "Contact/Pairs/rods/Friction Coefficient", 0.3);
        input::replaceAtPath(d, "Supports/upper end/Fixed", std::string("ux uy uz rx"));
        for (const std::string end : {"upper start", "upper end"})
          input::setAtPath(d, "Supports/" + end + "/Displacement", vec("0.5, 0, 0"));
      }
      runAndBalance(d, std::string(slide ? "rods_mid_load_slid_" : "rods_mid_load_") + tag(type));
    }
}

TEST(CsvBalance, TwistingRods) {
  // input/twisting_rods.xml with Penalty: each rod's top node is held by three supports (ux and uy on
  // load curves, and uz with the three rotations: the stretch and the half turn about z), the rods in
  // line contact along a helix. The moments about the origin balance with the clamps' turned moments.
  runAndBalance(inputDeck("twisting_rods.xml", "Penalty"), "twisting_Penalty");
}

TEST(CsvBalance, EndContactOffTheBeamsCentreLine) {
  // input/column_on_beam.xml with the column 0.5 off the beam's top line (across it), both sections
  // (rectangles: beam 2 x 2, column 1 x 1), friction 0.3 and the column's top moved by (3, -0.2,
  // -0.08) in 8 increments (the end touches at T = 0.75 and slips along and across the beam): the end
  // point's forces act off both axes.
  // Before, a unit multiplier acted on the end's centre and on B's axis: the moments did not balance
  // by the force times the offset (ContactKinematics.UnitMultipliersForcesBalance).
  for (const bool rect : {false, true})
    for (const std::string type : kStrategies) {
      Deck d = inputDeck("column_on_beam.xml", type);
      input::replaceAtPath(d, "Beams/column/Start", vec("45.0, 0.5, 11.05"));
      input::replaceAtPath(d, "Beams/column/End", vec("45.0, 0.5, 1.05"));
      if (rect) squareSections(d, {{"beam", 2.0}, {"column", 1.0}});
      input::replaceAtPath(d, "Contact/Pairs/end on beam/Friction Coefficient", 0.3);
      input::replaceAtPath(d, "Supports/column top/Displacement", vec("3.0, -0.2, -0.08"));
      input::replaceAtPath(d, "Load Stepping/Number of Increments", 8);
      const Worst w = runAndBalance(d, std::string(rect ? "end_rect_" : "end_circ_") + tag(type));
      EXPECT_GT(w.bodies, 0) << type;
    }
}

TEST(CsvBalance, EndToEndContact) {
  // input/columns_end_to_end.xml slid with friction (endToEndSlide): the upper end slides across the
  // lower one's face, the faces tilt and the rim presses, so the force acts off both axes. Each
  // strategy, both sections.
  for (const bool rect : {false, true})
    for (const std::string type : kStrategies) {
      const Worst w = runAndBalance(endToEndSlide(type, rect),
                                    std::string(rect ? "end_to_end_rect_" : "end_to_end_circ_") + tag(type));
      EXPECT_GT(w.bodies, 0) << type;
    }
}
