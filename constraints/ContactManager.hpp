// Beam-to-beam contact as a Contribution: finds the contact points of the declared beam pairs,
// keeps their history, and lets the configured ConstraintEnforcer turn each point's kinematics into
// residual and tangent terms. It composes the parts of the contact:
//  - ContactGeometry: the beams' contact lines, the pairs, the last converged state, the all-angle
//    blend of point and line contact;
//  - ContactSearch: the broad phase (boxes in a uniform grid), the narrow phase's choices shared
//    between ranks, and the overlaps no point can see;
//  - PointContact and LineContact: the narrow phase, geometry and kinematics of point contacts and
//    of the Gauss points of line contact (with a strategy's multiplier field on line nodes);
//  - ContactPointSet: the points (keyed by PointKey) with their life cycle and history;
//  - AutomaticPenalty: the beams' compliance handed to the strategy, and its relaxation;
//  - ContactReport: the table, VTK arrays, progress line and warnings.
// A strategy's multipliers are extra unknowns of the state (core::ExtraUnknowns, owner "contact",
// key the point's code, PointKey::code), as many as it asks for.
#pragma once
#include <array>
#include <functional>
#include <map>
#include <set>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "AutomaticPenalty.hpp"
#include "ConstraintEnforcer.hpp"
#include "ContactGeometry.hpp"
#include "ContactKinematics.hpp"
#include "ContactPointRecord.hpp"
#include "ContactPointSet.hpp"
#include "ContactReport.hpp"
#include "ContactSearch.hpp"
#include "LineContact.hpp"
#include "PointContact.hpp"
#include "PointKey.hpp"
#include "core/Contribution.hpp"
#include "elements/BeamSet.hpp"

namespace bc::constraints {

class ContactManager : public core::Contribution {
 public:
  ContactManager(std::shared_ptr<const elements::BeamSet> beams, std::vector<ContactPairSpec> pairs,
                 std::unique_ptr<ConstraintEnforcer> enforcer, ContactOptions options);
  ContactManager(const ContactManager&) = delete;  // its parts refer to each other
  ContactManager& operator=(const ContactManager&) = delete;

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
  void markIterate() override { set_.mark(); }
  void useCompliance(core::ComplianceFunction compliance) override { penalty_.useCompliance(std::move(compliance)); }
  void useResponse(core::ResponseFunction response) override { response_ = std::move(response); }
  // The strategy's estimates moved with Newton's step (ConstraintEnforcer::coupledConstraints).
  bool coupleStep(core::State& state, std::vector<double>& du, bool near) override;
  void useCommunicator(const Teuchos::RCP<const Teuchos::Comm<int>>& comm) override {
    comm_ = comm;
    search_.useCommunicator(comm);
  }
  static constexpr const char* kExtraOwner = kContactExtraOwner;
  double stepBound(const core::State& state, const std::vector<double>& du) const override;
  void returnToIterate() override { set_.returnToMark(); }
  std::string tableName() const override { return "contact_points.csv"; }
  std::string tableHeader() const override { return report_.tableHeader(); }
  std::vector<std::string> tableRows() const override { return report_.tableRows(set_.committed()); }
  std::string progressSummary() const override { return report_.progressSummary(set_.committed(), lastPasses_); }
  std::vector<std::string> warnings() const override { return report_.warnings(); }
  void appendVtk(const core::State& state, core::VtkMesh& mesh) const override;
  std::string vtkSeries() const override { return "contact"; }  // vtk/contact_N.vtu, contact.pvd

  // For tests: the current points and their results of the last commit.
  using Point = ContactPointRecord;
  const std::map<PointKey, Point>& points() const { return set_.current(); }
  const ConstraintEnforcer& enforcer() const { return *enforcer_; }
  // Whether the system gets rows of multipliers: the strategy's at points, or a nodal line field's.
  bool addsMultiplierRows() const { return enforcer_->addsMultiplierRows() || lines_.nodal(); }
  const std::vector<ContactPairSpec>& pairs() const { return geometry_.pairs(); }
  // The contact search's candidates at `s` (swept from the last converged state): (pair, element of
  // beam A, element of beam B), sorted. For tests and benchmarks of the search.
  std::vector<std::tuple<int, int, int>> candidates(const core::State& s) const { return search_.candidates(s); }
  int passes() const { return passes_; }
  // For tests of the refined field's tangent: the field of an element of a pair's beam A (edge 0) at
  // a level, whatever the gaps.
  void refineLineFieldAt(int pair, int element, int level) { lines_.setFieldLevel(pair, 0, element, level); }
  // The largest constraint violation (|g_N| of active points, |g_T| of sticking lines for the
  // strategies that enforce them exactly) after each pass of the increment solved last.
  const std::vector<double>& passViolations() const { return violations_; }
  // Kinematics of a point at a state (public for tests of the assembled contact tangent).
  ContactKinematics kinematics(const Point& p, const core::State& state, Variations order = Variations::Second) const;
  // The values and first variations (no second variations: K zero) where the point acts (or is a
  // point contact); for a line point that does not act, only the values (gaps, xi, eta, segment, the
  // axes' cosine): what the active set and the step's end judge a point by, at a fraction of the cost.
  ContactKinematics judgedKinematics(const Point& p, const core::State& state) const;
  // Whether judgedKinematics gave `p` its first variations at kinematics `k` (a point contact always).
  bool actsAt(const Point& p, const ContactKinematics& k) const;
  std::array<core::GlobalDof, kPairDofs> pointDofs(const Point& p) const { return geometry_.pointDofs(p); }
  // The point's multipliers in `state` (null when it has none) and how many there are.
  const double* multipliers(const Point& p, const core::State& state, int* count = nullptr) const {
    return pointMultipliers(p, state, count);
  }
  // The state that decides whether a point acts: its own, or for a Gauss point of a nodal line field
  // the state of its nearer line node with multipliers (null: none has any).
  const PointState* actingState(const Point& p) const;
  // The point as its strategy sees it, with kinematics `k` in `state`.
  ContactPoint strategyView(const Point& p, const ContactKinematics& k, const core::State& state) const {
    return geometry_.strategyView(p, k, state);
  }

 private:
  // The search's candidates at `s`, from point and line contact's narrow phases.
  std::map<PointKey, Candidate> detect(const core::State& s) const;
  // Closest points of a point's two lines in `s`, with the point's normal orientation and gap (a line
  // point: at its Gauss point of its segment, the segment's length in `segment`).
  ClosestPoints pointGeometry(const Point& p, const core::State& s, double* segment = nullptr) const;
  // Multipliers whose rows carry nothing at `state`: given up (the state starts afresh).
  void giveUpIdle(const core::State& state);
  std::vector<core::GlobalDof> blockDofs(const Point& p) const;
  // Whether this rank evaluates point p (block dofs `dofs`): connectivity and evaluate agree on it.
  static bool evaluatesHere(const Point& p, const std::vector<core::GlobalDof>& dofs, const OwnsDof& owns);
  // A line node's own rows (ConstraintEnforcer::lineNodeRows): its multipliers' dofs where this rank
  // evaluates them, else none; and their evaluation.
  std::vector<core::GlobalDof> nodeRows(const Point& p, const OwnsDof& owns) const;
  void evaluateNode(const Point& p, const std::vector<core::GlobalDof>& rows, const core::State& state,
                    core::AssemblySink& sink, bool tangent) const;
  // Whether an active point of pair `pi` near elements ea and eb holds them in `state` (they crossed):
  // one that penetrates, or with `penetrating` false any active one (it sees them).
  bool held(int pi, int ea, int eb, const core::State& state, bool penetrating = true) const;
  // The kinematics a point is judged by after a solve (values and first variations; a line node:
  // its weighted gap and slip of `gaps`), and whether it carries: a point whose blend weight is at
  // most kCarries carries (almost) nothing, and its strategy does not judge it. The second stage of
  // acceptSolution computes them again (from the same states: it runs only when no acceptNormal
  // changed one) rather than keeping them: with its (zero) second variations a ContactKinematics
  // takes 15 kB, and writing 150 MB of them for 10^4 points cost 80 us per point.
  ContactKinematics judge(const PointKey& key, const Point& p, const core::State& state,
                          const std::map<PointKey, LineContact::NodeGap>& gaps, bool& carries) const;
  // Lets go the points held in stick (AutomaticPenalty::held) whose law slips at the converged `state`;
  // whether any rank did.
  bool releaseHeld(const core::State& state);
  // The step bound of a line point (a Gauss point) for the full step `stepped()` from `state`.
  double lineStepBound(const Point& p, const core::State& state,
                       const std::function<const core::State&()>& stepped) const;
  // Commits a point (not a line node) at `state`: its strategy's state, its results and history.
  void commitPoint(Point& p, const core::State& state);

  std::unique_ptr<ConstraintEnforcer> enforcer_;
  ContactGeometry geometry_;
  PointContact pointContact_;
  LineContact lines_;
  ContactSearch search_;
  ContactPointSet set_;
  AutomaticPenalty penalty_;
  ContactReport report_;
  int numNodes_ = 0;
  int passes_ = 0;
  int gatePasses_ = 0;  // passes of the increment that only opened gates (acceptSolution)
  // The points whose state each pass of the increment changed (with its stage: 0 normal, 1 stick and
  // slip); a set seen before means the passes cycle, and from the pass `cycleFrom_` (0: none) one
  // point's change is applied per pass (discreteStates strategies).
  std::set<std::pair<int, std::vector<PointKey>>> changeSets_;
  int cycleFrom_ = 0;
  bool resumeLevels_ = false;  // the line field's refinement is renewed at the next prepareIteration
  // Per line node: the length of line its Gauss points cover at the iterate (int N_a ds over the
  // pieces the other beam covers; evaluateNode).
  std::map<PointKey, double> nodeCover_;
  int lastPasses_ = 0;
  double worstViolation_ = 0.0;
  std::vector<double> violations_;
  core::ResponseFunction response_;
  Teuchos::RCP<const Teuchos::Comm<int>> comm_;
  // An evaluation for the model's response (coupleStep), not a Newton iterate's: no friction watch.
  mutable bool quietEvaluation_ = false;
  // Coupled steps: off for the rest of the increment once the model's tangent was singular; the constraints
  // (point, gap, sliding directions) at the Newton iterate that last asked, and its number (iterate_
  // counts prepareIteration's calls): a step is coupled only when they are the same as at the
  // iterate before.
  bool responseFailed_ = false;
  long iterate_ = 0, signatureIterate_ = -2;
  std::vector<std::array<long long, 5>> signature_;
};

}  // namespace bc::constraints
