// Beam-to-beam contact as a Contribution: finds the contact points of the declared beam pairs,
// keeps their history, and lets the configured ConstraintEnforcer turn each point's kinematics into
// residual and tangent terms.
//
// Contact lines: the four edges of a rectangular section (offsets +-b/2 e2 +-h/2 e3 from the axis),
// the axis of a circular one (the radii enter the gap). A contact point is identified by its beam
// pair and its two lines; per iteration it lies on the element pair where the closest points of the
// two lines fall inside both elements (a point on a shared node is taken once). Only lines facing
// the other beam take part, so a pair of rectangular beams has at most 2 x 2 = 4 points.
//
// Search: the elements' bounding boxes (inflated by "Search Margin") are hashed into a uniform grid,
// so candidate element pairs are found without testing all pairs. Elements that share a node (beams
// joined there) or whose nodes are pinned together are never a candidate pair.
//
// History per point: the contact coordinates of the last converged step (the tangential gaps are
// measured from them, mapped on the current configuration), the normal orientation, and the
// strategy's own point state (opaque here). A strategy's multipliers are extra unknowns of the state
// (core::ExtraUnknowns, owner "contact", key the point's code, PointKey::code), as many as it asks for.
// When a point moves to a neighbouring element within a step, its tangential gap is the parameter
// difference times the current element's line length (exact within one element).
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

#include "ConstraintEnforcer.hpp"
#include "ContactKinematics.hpp"
#include "PointKey.hpp"
#include "core/Contribution.hpp"
#include "elements/BeamSet.hpp"

namespace bc::constraints {

struct ContactPairSpec {
  int beamA = 0, beamB = 0;
  double friction = 0.0;
  std::string name;
};

struct ContactOptions {
  double searchMargin = 0.0;           // added to the bounding boxes [length]
  double minimumSinAngle = 1e-3;       // lines closer to parallel are skipped (point contact undefined)
  bool allowInitialPenetration = false;
  FrictionLaw frictionLaw = FrictionLaw::IsotropicCoulomb;
  // All-angle contact of two circular beams (radians): line contact (Gauss points along the line,
  // frictionless) below lineAngle, point contact above pointAngle, a C1 blend of the two between;
  // lineAngle 0 switches line contact off. Gauss points per element of beam A.
  double lineAngle = 5.0 * M_PI / 180.0;
  double pointAngle = 15.0 * M_PI / 180.0;
  int lineGaussPoints = 6;
  // Pairs of distinct nodes joined without sharing a node (pinned joints): elements meeting there
  // are no contact candidates, like elements that share a node.
  std::vector<std::pair<int, int>> joinedNodes;
};

// A strategy's point state with value semantics (copied by clone, so points can be committed,
// marked and restored).
class PointStateHolder {
 public:
  PointStateHolder() = default;
  explicit PointStateHolder(std::unique_ptr<PointState> s) : s_(std::move(s)) {}
  PointStateHolder(const PointStateHolder& o) : s_(o.s_ ? o.s_->clone() : nullptr) {}
  PointStateHolder& operator=(const PointStateHolder& o) {
    if (this != &o) s_ = o.s_ ? o.s_->clone() : nullptr;
    return *this;
  }
  PointStateHolder(PointStateHolder&&) = default;
  PointStateHolder& operator=(PointStateHolder&&) = default;
  PointState& operator*() const { return *s_; }

 private:
  std::unique_ptr<PointState> s_;
};

class ContactManager : public core::Contribution {
 public:
  ContactManager(std::shared_ptr<const elements::BeamSet> beams, std::vector<ContactPairSpec> pairs,
                 std::unique_ptr<ConstraintEnforcer> enforcer, ContactOptions options);

  // Checks the initial state (penetration) and finds the first candidates.
  void initialize(core::State& state);

  std::string name() const override { return "contact"; }
  void connectivity(const OwnsDof& owns, std::vector<std::vector<core::GlobalDof>>& blocks) const override;
  void evaluate(const core::State& state, const OwnsDof& owns, core::AssemblySink& sink, bool tangent) const override;
  std::string failureHint(const Teuchos::Comm<int>& comm) const override;
  bool prepareIteration(core::State& state) override;
  bool acceptSolution(core::State& state) override;
  void commitStep(const core::State& state) override;
  void restoreStep() override;
  void saveCommitted(core::CheckpointOut& out) const override;
  void loadCommitted(core::CheckpointIn& in, const core::State& committed) override;
  void markIterate() override { marked_ = points_; }
  void useCompliance(core::ComplianceFunction compliance) override { compliance_ = std::move(compliance); }
  void useCommunicator(const Teuchos::RCP<const Teuchos::Comm<int>>& comm) override { comm_ = comm; }
  static constexpr const char* kExtraOwner = "contact";
  double stepBound(const core::State& state, const std::vector<double>& du) const override;
  void returnToIterate() override { points_ = marked_; }
  std::string tableName() const override { return "contact_points.csv"; }
  std::string tableHeader() const override;
  std::vector<std::string> tableRows() const override;
  std::string progressSummary() const override;
  std::vector<std::string> warnings() const override;
  void appendVtk(const core::State& state, core::VtkMesh& mesh) const override;

  // For tests: the current points and their results of the last commit.
  struct Point {
    // A point contact joins two lines, a Gauss point of line contact lies on a segment of line A, a
    // line node carries a strategy's multiplier field on line A (PointKey). A line node's elements
    // are one element of beam A at its node.
    PointKey key;
    bool node() const { return key.kind == PointKey::Kind::LineNode; }
    bool line() const { return key.kind == PointKey::Kind::Gauss; }
    int gauss() const { return key.gauss; }
    int edge() const { return key.edge; }
    int face() const { return key.face; }
    int elementA = 0, elementB = 0;  // indices into the beam set's element list
    double sigma = 1.0;
    double xiPrev = 0.0, etaPrev = 0.0;  // previous converged point, as beam coordinates (element + xi)
    // Line points: d eta / d xi at the last converged state (LineHistory), the Gauss point's parameter
    // on A's element at the last detection, and the length of line A it stood for at the last commit.
    double etaRate = 0.0, xi = 0.0, length = 0.0;
    PointStateHolder state;  // the strategy's
    int extraOffset = -1, extraCount = 0;  // its multipliers in State::extra (as laid out last)
    // Last committed values, for output: the normal gap (a line node: its field-weighted gap) and
    // the following.
    double gap = 0.0;
    PointResult result;
    // The beams' compliance at the point (ConstraintEnforcer::setCompliance; 0: not asked for).
    double compliance[3] = {0.0, 0.0, 0.0};
    Vec3d position{};
    Vec3d normal{};          // unit normal (from beam A to beam B)
    Vec3d normalForce{};     // the force the point applies on beam B: its normal part ...
    Vec3d tangentialForce{};  // ... and its tangential part (global components)
  };
  const std::map<PointKey, Point>& points() const { return points_; }
  const ConstraintEnforcer& enforcer() const { return *enforcer_; }
  const std::vector<ContactPairSpec>& pairs() const { return pairs_; }
  // The contact search's candidates at `s` (swept from the last converged state): (pair, element of
  // beam A, element of beam B), sorted. For tests and benchmarks of the search.
  std::vector<std::tuple<int, int, int>> candidates(const core::State& s) const;
  int passes() const { return passes_; }
  // The largest constraint violation (|g_N| of active points, |g_T| of sticking lines for the
  // strategies that enforce them exactly) after each pass of the increment solved last.
  const std::vector<double>& passViolations() const { return violations_; }
  // Kinematics of a point at a state (public for tests of the assembled contact tangent).
  ContactKinematics kinematics(const Point& p, const core::State& state,
                               Variations order = Variations::Second) const;
  // The values and first variations (no second variations: K zero) where the point acts (or is a
  // point contact); for a line point that does not act, only the values (gaps, xi, eta, segment, the
  // axes' cosine): what the active set and the step's end judge a point by, at a fraction of the cost.
  ContactKinematics judgedKinematics(const Point& p, const core::State& state) const;
  std::array<core::GlobalDof, kPairDofs> pointDofs(const Point& p) const;
  // The point's multipliers in `state` (null when it has none) and how many there are.
  const double* multipliers(const Point& p, const core::State& state, int* count = nullptr) const;
  // The state that decides whether a point acts: its own, or for a Gauss point of a nodal line field
  // the state of its nearer line node with multipliers (null: none has any).
  const PointState* actingState(const Point& p) const;
  // The point as its strategy sees it, with kinematics `k` in `state`.
  ContactPoint strategyView(const Point& p, const ContactKinematics& k, const core::State& state) const;

 private:
  struct Line {
    double cy = 0.0, cz = 0.0;  // offset in the section's (y, z)
    double radius = 0.0;
  };
  struct Candidate {
    int elementA, elementB;
    ClosestPoints cp;
  };
  LinePairInput lineInput(int elementA, int lineA, int elementB, int lineB, const core::State& s) const;
  // The candidates of the state's element pairs: the closest points of each element pair's lines
  // (the narrow phase) for the pairs of the broad phase (forEachElementPair). With a communicator of
  // several ranks each rank evaluates a contiguous share of the pairs and the ranks exchange their
  // choices; the result is the same on every rank and the same as the whole search's on one.
  std::map<PointKey, Candidate> detect(const core::State& s) const;
  // The narrow phase of one element pair, the broad phase's `visit`-th: offers each candidate it
  // finds with how far outside its elements' centres it lies and an order (see detect).
  void narrowPhase(int pair, int elementA, int elementB, long long visit, const core::State& s,
                   const std::function<void(const PointKey&, const Candidate&, double, long long)>&
                       offer) const;
  // Calls visit(pair, elementA, elementB) for the element pairs of the contact pairs whose bounding
  // boxes, swept from the last converged state to `s`, overlap.
  void forEachElementPair(const core::State& s, const std::function<void(int, int, int)>& visit) const;
  bool nearElement(int element, double xi) const;
  double referenceSigma(int eA, int lA, int eB, int lB, const ClosestPoints& current) const;
  LinePairInput axisInput(int eA, int eB, const core::State& s) const;
  // Line contact's input of a line point: the axes (circular sections) or an edge of A on a face of B
  // (rectangular sections; faces 0..3 = +y, +z, -y, -z of the section).
  LinePairInput lineContactInput(const Point& p, const core::State& s) const;
  LinePairInput faceInput(int eA, int edgeA, int eB, int faceB, const core::State& s) const;
  // Rectangular sections in line contact: the two edges of A on its face towards B and B's face
  // towards A, from the elements' places and turns in `s`.
  std::pair<std::array<int, 2>, int> facing(int eA, int eB, const core::State& s) const;
  bool rectangles(int pair) const;
  // The angles (radians) below which a pair is in line contact and above which in point contact.
  std::pair<double, double> blendAngles(int pair) const;
  // Closest points of a point's two lines in `s`, with the point's normal orientation and gap (a line
  // point: at its Gauss point of its segment, the segment's length in `segment`).
  ClosestPoints pointGeometry(const Point& p, const core::State& s, double* segment = nullptr) const;
  // Line contact's input of the segment of element eA (its edge `edge`) on element eB (its face
  // `face`): lineInput or faceInput with the planes of eB's nodes.
  LinePairInput segmentInput(int pair, int eA, int eB, int edge, int face, const core::State& s) const;
  // A line point's history (element parameters) and its slip along B at `cp` in `s` since then, as
  // segmentKinematics measures it.
  LineHistory lineHistory(const Point& p) const;
  double lineSlip(const Point& p, const ClosestPoints& cp, const core::State& s) const;
  // Per element: the reference normals of the segment planes at its two nodes (the mean unit axis of
  // the beam's elements meeting there).
  std::vector<std::array<Vec3d, 2>> segmentPlanes_;
  double beamCoordinate(int element, double xi) const;
  bool withinElement(int element, double xi) const;
  void checkNoPassThrough(const core::State& state) const;
  // Overlaps no contact point can see (at a free beam end, or between nearly parallel beams): an
  // error (InputError at the start, else the increment fails).
  void checkNoUnseenContact(const core::State& state, bool atStart) const;
  // Asks the state's extra unknowns for the multipliers every point's strategy wants now (values of
  // points that keep theirs are kept); true if the layout changed.
  bool layoutMultipliers(core::State& state);
  // Hands the points whose strategy state waits for it the structure's compliance there (at the last
  // converged state, along the gaps' variations at `state`); nothing before the solver gave the
  // compliance function.
  void giveCompliance(const core::State& state);
  core::ComplianceFunction compliance_;
  Teuchos::RCP<const Teuchos::Comm<int>> comm_;  // the ranks that share the narrow phase (detect)
  // Automatic tangential parameters are lowered tenfold (their compliances handed on times
  // tangentialRelaxation_) when a Newton solve fails with slip directions cycling (failureHint sets
  // cycling_, restoreStep relaxes), at most kMaxRelaxations times; the run then warns.
  static constexpr int kMaxRelaxations = 6;
  void handCompliance(Point& p) const;
  double tangentialRelaxation_ = 1.0;
  int relaxations_ = 0;
  mutable bool cycling_ = false;
  std::vector<core::GlobalDof> blockDofs(const Point& p) const;
  // Whether this rank evaluates point p (block dofs `dofs`): connectivity and evaluate agree on it.
  static bool evaluatesHere(const Point& p, const std::vector<core::GlobalDof>& dofs, const OwnsDof& owns);

  std::shared_ptr<const elements::BeamSet> beams_;
  std::vector<ContactPairSpec> pairs_;
  std::unique_ptr<ConstraintEnforcer> enforcer_;
  ContactOptions options_;
  std::vector<std::vector<Line>> lines_;  // per beam
  std::set<std::pair<int, int>> joined_;  // options_.joinedNodes, both orders
  // (beam A, beam B) -> index into pairs_ (hashed: the search looks a pair up for every two
  // elements whose boxes overlap, 10^5 pairs on the 316 x 316 crossed layers).
  static std::uint64_t beamPairKey(int a, int b) { return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b); }
  std::unordered_map<std::uint64_t, int> pairIndex_;
  std::set<int> freeEnd_;                 // nodes at a beam end that no other element or pin uses
  std::vector<double> inscribed_;         // per beam: radius of the largest circle in its section
  std::vector<double> gaussXi_, gaussWeight_;  // line contact: Gauss points on [0, 1], weights summing to 1
  bool lineContact_ = false;              // the strategy enforces lines and lineAngle > 0
  bool nodalLines_ = false;               // ... with a multiplier field on the nodes of line A
  // Nodal line fields. The field's nodes are beam A's nodes, except its two end nodes: their shape
  // functions are merged into their neighbours' (the field is constant on a beam's end elements;
  // a beam of one element has one multiplier node). An end node's own multiplier would constrain
  // the gap where the supports of both beams often fix it already (rods held at the same ends), so
  // the constraints would be redundant and the multipliers undetermined. fieldNode(element, side)
  // is the node carrying the multipliers of the element's node `side` (0, 1); fieldShares(p) the
  // distinct field nodes of a Gauss point with their shape values N (summing to 1) and their
  // records (null where none exists).
  int fieldNode(int element, int side) const;
  struct FieldShare {
    int node = -1;
    double N = 0.0, slope = 0.0;  // N at the point's xi and dN / dxi
    const Point* record = nullptr;
  };
  std::vector<FieldShare> fieldShares(const Point& p, double xi) const;
  // Per field node: the weighted gap int N_a g_N ds / int N_a ds and the weight int N_a ds (Gauss
  // weights times lengths times the line points' blend weights) at `s`.
  struct NodeGap {
    double weighted = 0.0, weight = 0.0, full = 0.0;  // full: the weight without the blend
    double weightedSlip = 0.0;                          // int N_a g_T2 ds / int N_a ds
  };
  std::map<PointKey, NodeGap> nodeGaps(const core::State& s) const;
  // The view a strategy gets of a line node (its weighted gap, its multipliers).
  ContactPoint nodeView(const Point& node, const ContactKinematics& k, const core::State& s) const;
  // Evaluates a Gauss point of a nodal line field: residual and tangent over blockDofs(p).
  bool evaluateNodal(const Point& p, const ContactKinematics& k, const core::State& s, std::vector<double>& f,
                     std::vector<double>* K, PointResult* result) const;
  std::set<int> frictionlessLines_;       // pairs with friction whose line points carried force
  std::map<int, std::pair<double, Vec3d>> unresolvedLines_;  // nodal line fields: pair -> deepest penetration, where
  std::map<int, std::pair<double, Vec3d>> unseenBetween_;    // pair -> deepest overlap between Gauss points, where
  std::map<int, std::pair<double, Vec3d>> deepPoints_;       // pair -> deepest active point beyond kDeep, where
  // After a step: records overlaps of line contact between the Gauss points (warnings()).
  void checkLineResolution(const core::State& state);
  // All-angle contact: whether the pair blends point and line contact (both beams circular and the
  // strategy enforces lines); the angle of two elements' axes in `s`; whether an element pair has
  // line points / point contacts (by its angle at the last converged state, with margins beyond the
  // blend so a pair that turns within an increment has both); and the blend weight of a point at its
  // axes' cosine (point contact zeta, line point 1 - zeta), with its gradient in the 24 dofs from
  // the cosine's first variation.
  bool blends(int pair) const;
  double axisAngle(int elementA, int elementB, const core::State& s) const;
  bool inLineContact(int pair, int elementA, int elementB) const;
  bool inPointContact(int pair, int elementA, int elementB) const;
  double blendWeight(const Point& p, double cosine, const double* cosineR, Vector24* gradient) const;
  // The length of line A a Gauss point stands for (its weight times its segment's reference length).
  double lineWeight(const Point& p, double segment) const;
  std::map<PointKey, Point> points_, committed_, marked_;
  // This rank's slipping points in the present Newton solve of the increment: the friction force at
  // the last tangent assembly and how often it reversed against the one before (failureHint).
  struct FrictionWatch {
    std::array<double, 2> force{};
    int reversals = 0;
  };
  mutable std::map<PointKey, FrictionWatch> frictionWatch_;
  core::State reference_;  // the last converged state (orientation of new points, swept search)
  int numNodes_ = 0;
  int passes_ = 0;
  int lastPasses_ = 0;
  double worstViolation_ = 0.0;
  std::vector<double> violations_;
};

}  // namespace bc::constraints
