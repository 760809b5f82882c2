// How a contact constraint is enforced: the strategy interface. Read this file to write a strategy;
// docs/contact.md walks through one ("your first strategy in 15 minutes").
//
// A strategy sees one contact point at a time (ContactPoint): its kinematics (gaps g_N, g_T1, g_T2,
// each with its first variation R and linearized variation K, ContactKinematics.hpp), the friction
// coefficient and law, and its multipliers if it owns any. It adds the point's residual and tangent,
// and decides what happens when Newton has converged (change an active set, augment, accept). The
// contact manager does search, bookkeeping, assembly and output; it never looks inside a strategy.
//
// What a strategy owns:
//  - its parameters: a static spec() (core::ParameterSpec: names, defaults, ranges, docs), from which
//    the deck's "Contact/Enforcement/<name>" sublist is validated and documented;
//  - its per-point state: a struct derived from PointStateOf<...>, made by newPointState(), carried
//    from step to step (restored when a step is cut, written to checkpoints through fields());
//  - its multipliers: multipliers(state) says how many unknowns a point needs now; the manager asks
//    the core allocator (core::ExtraUnknowns) for them and hands their values in ContactPoint::lambda;
//  - its construction: a constructor from its validated sublist, registered with
//    registerEnforcer<MyStrategy>() (EnforcerRegistry.hpp) or from a plug-in library.
//
// Sign conventions: lambda_N <= 0 is the normal contact force conjugate to g_N (the paper's (3.2);
// the reported normal force is -lambda_N >= 0); lambda_Ti is the friction force conjugate to g_Ti.
// The residual of a point is f = lambda_N R_N + lambda_T1 R_T1 + lambda_T2 R_T2 (+ the multipliers'
// own rows), the tangent K its derivative with respect to the point's 24 nodal dofs (translations
// and spin increments of the four nodes) and multipliers. Friction laws (Contact/Friction Law,
// return mappings in CoulombFriction.hpp, usable by any strategy):
//  - Isotropic Coulomb: the tangential force vector obeys |F_T| <= mu |lambda_N|; with the slip vector
//    s = g_T1 a - g_T2 b (a, b unit line tangents, c = a . b) the components conjugate to (g_T1, g_T2)
//    give |F_T|^2 = lambda_T^T M^-1 lambda_T, M = [1 -c; -c 1];
//  - Per Line: |lambda_Ti| <= mu |lambda_N| for each line on its own (the seed paper's (4.3)).
#pragma once
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "ContactKinematics.hpp"

namespace bc::constraints {

enum class FrictionLaw { IsotropicCoulomb, PerLine };

// Visits the fields of a point state by name (checkpoints write and read them through this).
class StateFields {
 public:
  virtual ~StateFields() = default;
  virtual void real(const char* name, double& value) = 0;
  virtual void flag(const char* name, bool& value) = 0;
};

// A strategy's per-point state. Derive from PointStateOf<YourState> (it supplies clone()) and list
// every member in fields() so that a restart continues exactly.
class PointState {
 public:
  virtual ~PointState() = default;
  virtual std::unique_ptr<PointState> clone() const = 0;
  virtual void fields(StateFields& visit) {}
};
template <class Self> class PointStateOf : public PointState {
 public:
  std::unique_ptr<PointState> clone() const override { return std::make_unique<Self>(static_cast<const Self&>(*this)); }
};
// The state with no fields (strategies that keep nothing between steps).
struct NoPointState : PointStateOf<NoPointState> {};

// The typed view of a state the strategy made itself (newPointState).
template <class S> S& stateOf(PointState& s) { return static_cast<S&>(s); }
template <class S> const S& stateOf(const PointState& s) { return static_cast<const S&>(s); }

// One contact point as a strategy sees it.
struct ContactPoint {
  const ContactKinematics& kinematics;
  double friction = 0.0;  // Coulomb coefficient mu of the pair
  FrictionLaw law = FrictionLaw::IsotropicCoulomb;
  const double* lambda = nullptr;  // the point's multipliers (multipliers(state) of them), or null
  // Its share where point and line contact are blended (all-angle contact of circular beams): the
  // manager scales the point's residual and tangent by it; in (0, 1], 1 elsewhere. A strategy that
  // judges constraint violations may weigh them by it.
  double weight = 1.0;
  // Whether a slip is measured along each tangential gap. A Gauss point of line contact measures the
  // slip along the axes (g_T2) but none across them (g_T1 = 0, no variation): a strategy treats that
  // direction as frictionless (its multiplier row lambda_T1 = 0).
  bool measured[2] = {true, true};
  // A node of a nodal line field (and a Gauss point acting through it): the beams' compliance to the
  // field's shortest mode there, a traction alternating from node to node (wavelength 2 h, h the
  // shortest of line A's elements at the node): (h / pi)^4 (1 / EI_A + 1 / EI_B) [length^2 / force],
  // EI each beam's stiffer bending stiffness. 0 elsewhere.
  double fieldCompliance = 0.0;
  // 10^n after n Newton solves failed with slip directions cycling (ContactManager's retry; 1 before):
  // a strategy whose friction rows have a parameter that only steers Newton, not the solution (Lagrange
  // multipliers' Friction Complementarity Parameter), divides it by this (relaxesFrictionSteering).
  double frictionRelaxation = 1.0;
  // The point's friction force reversed its direction twice in this Newton solve (slip directions cycling):
  // a strategy whose friction force is a return mapping may take a secant of it in its tangent, which
  // changes Newton's path, not the solution (the residual stays the law's).
  bool secantFriction = false;
  // The point's friction force reversed three times in this increment's Newton solves: a strategy whose
  // friction force is a return mapping may hold it in stick (its trial force, not projected on the
  // cone) until a converged state where the law slips there (ContactManager::releaseHeld then lets it
  // go and Newton solves again). Where the law sticks at the converged state, its force is the trial,
  // so the accepted state is the law's.
  bool heldFriction = false;
};

// The forces of a point: for output, the progress line and the stopping tests.
struct PointResult {
  bool active = false;
  double lambdaN = 0.0;
  double lambdaT[2] = {0.0, 0.0};
  bool slip[2] = {false, false};
};

// The factor by which `relaxations` tangential relaxations (ConstraintEnforcer::relaxTangential)
// scale the tangential compliances: 10^relaxations, formed by repeated products (inf beyond range).
double tangentialRelaxationFactor(int relaxations);

class ConstraintEnforcer {
 public:
  virtual ~ConstraintEnforcer() = default;
  // The name under Contact/Enforcement/Type (the registry's key).
  virtual std::string type() const = 0;

  // --- per-point state and multipliers -------------------------------------------------------------
  virtual std::unique_ptr<PointState> newPointState() const { return std::make_unique<NoPointState>(); }
  // Unknowns the point owns now (asked at the start of every Newton iteration; 0: none). A point
  // whose count changes gets fresh (zero) values.
  virtual int multipliers(const PointState& s) const { return 0; }

  // --- within Newton ---------------------------------------------------------------------------------
  // True when a point with normal gap `gapN` takes part in the system now (penalty: gapN < 0). Only
  // the gap is known here: the kinematics with their derivatives are computed for points that pass.
  virtual bool contributes(double gapN, const PointState& s) const = 0;
  // Adds the point's residual f (size 24 + multipliers) and tangent K (square, row-major; null for a
  // residual-only evaluation); returns its forces. f and K arrive zeroed.
  virtual PointResult evaluate(const ContactPoint& p, const PointState& s, double* f, double* K) const = 0;
  // Where the point's force switches on within Newton, as a gap (penalty 0): a Newton step that would
  // carry an open point past it is shortened so the next tangent sees the point. Infinite for
  // strategies whose active set changes only between Newton solves.
  virtual double activationGap(const PointState& s) const { return -std::numeric_limits<double>::infinity(); }

  // --- parameters chosen from the structure (e.g. automatic penalty parameters) ---------------------
  // True while the point's state waits for the structure's compliance at the point. The manager then
  // computes c = (c_N, c_T1, c_T2) [length/force]: v^T K^-1 v for v the first variations R of g_N,
  // g_T1, g_T2 (a unit force along each gap), K the tangent of the beams without contact at the last
  // converged state, times the weight the manager puts on the point (a Gauss point of line contact:
  // the length it stands for); 0 where a gap has no variation. It hands c to setCompliance once,
  // before the point is evaluated.
  virtual bool wantsCompliance(const PointState& s) const { return false; }
  // True when the strategy's friction rows have a parameter that steers Newton only (any value has the
  // same solution) and that it lowers by ContactPoint::frictionRelaxation: after a Newton solve fails
  // with slip directions cycling, the retry then relaxes it (Lagrange multipliers: c_T of Isotropic
  // Coulomb's complementarity function).
  virtual bool relaxesFrictionSteering() const { return false; }
  // True when the strategy's friction force honours ContactPoint::heldFriction (a return mapping held
  // in stick: the regularized law's strategies); the manager holds points only then.
  virtual bool holdsFriction() const { return false; }
  virtual void setCompliance(PointState& s, const double compliance[3]) const {}
  // When Newton solves fail with slip directions cycling, the manager relaxes the tangential law of
  // the points it handed a compliance, for the retry: it counts the relaxations of the run
  // (`relaxations` = 1, 2, ..., at most 6; kept in checkpoints) and calls this for each such point
  // with its compliance as handed to setCompliance (and for a point found later, with the run's count
  // when it is > 0). The strategy decides what relaxing means. By default the tangential compliances
  // times 10^relaxations go to setCompliance: automatic tangential parameters tenfold lower each time.
  virtual void relaxTangential(PointState& s, const double compliance[3], int relaxations) const;

  // --- when Newton has converged for an increment ---------------------------------------------------
  // Here (acceptNormal, acceptPoint, reportedForces, commitPoint) a point's kinematics carry the gaps'
  // values and first variations R; their second variations K are not computed (zero).
  // First stage, for every point: the normal active set; return false if it changed (the increment
  // is solved again), and leave `s` as it was when returning true. Only when no point changed there
  // does the second stage run.
  virtual bool acceptNormal(const ContactPoint& p, PointState& s) const { return true; }
  // Second stage: friction states, augmentation. Return false to solve the increment again.
  // `worstViolation` collects the largest constraint violation (stopping test and output).
  virtual bool acceptPoint(const ContactPoint& p, PointState& s, double& worstViolation) const = 0;
  // Line contact (nearly parallel circular beams): the contact manager hands a strategy the Gauss
  // points along line A (each standing for a length of it; the manager weights the residual and
  // tangent by that length, so the law acts per unit length). Where the strategy's multipliers live:
  //  - PerPoint: each Gauss point is a point like any other, with its own state and multipliers.
  //    Right for strategies without multipliers (Penalty). A multiplier (or an augmented estimate) per
  //    Gauss point over-constrains a line (more constraints than the beams have dofs there: not a
  //    stable discretization).
  //  - Nodal: a mortar field on the nodes of line A. Each node of beam A in line contact with a pair
  //    is a "line node": it has a state (newPointState) and multipliers(state) unknowns Lambda_a. A
  //    Gauss point at xi of an element with nodes a, b sees lambda = N_a Lambda_a + N_b Lambda_b
  //    (N linear; a node without multipliers counts zero) and the state of the nearer node that has
  //    multipliers; it takes part when that node's state contributes(). Its multiplier rows are
  //    tested with the same N (node a's rows are the integral of N_a times the point's rows, the
  //    manager does that). The active set is the nodes': acceptNormal, acceptPoint, reportedForces
  //    and commitPoint see a node as a point whose kinematics carry only the weighted gap
  //    g_a = int N_a g_N ds / int N_a ds (normal.value; tangential values 0, no derivatives) and
  //    whose lambda is Lambda_a.
  //  - None: the strategy cannot enforce lines; nearly parallel beams then stop the run as an unseen
  //    contact.
  enum class LineField { None, PerPoint, Nodal };
  virtual LineField lineField() const { return LineField::PerPoint; }
  // Nodal fields: the state of a line node (by default a point's). A strategy whose points and line
  // nodes differ (multipliers on the nodes only) tells them apart here.
  virtual std::unique_ptr<PointState> newLineNodeState() const { return newPointState(); }
  // Nodal fields: rows a line node adds of its own, beyond the integrals of its Gauss points' rows
  // (e.g. a regularization of its multipliers). `length` is the node's share of line A's reference
  // length (int N_a ds over beam A's elements, a constant); f (multipliers(s) entries) and K (square,
  // row-major, over the node's multipliers; null for a residual only) arrive zeroed. The node's view
  // carries its multipliers and fieldCompliance.
  virtual bool lineNodeRows() const { return false; }
  // Nodal fields: the normal gap a Gauss point of a line keeps under the field's traction lambdaN at
  // it (a penalty on the nodes: lambdaN / eps_N; exact constraints: 0). Penetration beyond it is the
  // field's, not the strategy's: the field is refined there and warns of an unresolved zone.
  virtual double lineFieldGap(double lambdaN) const { return 0.0; }
  // Nodal fields: true when every line node's row is a penalty's (regularized by 1 / eps_N with no
  // estimate that converges to the exact constraint). Such a node may act where supports hold the
  // gap (its row stays independent of theirs), so beam ends keep their nodes (LineContact::setInitial
  // merges them for exact constraints).
  virtual bool lineFieldPenalized() const { return false; }
  virtual void evaluateLineNode(const ContactPoint& node, const PointState& s, double length, double* f,
                                double* K) const {}
  // --- estimates moved with Newton's step (optional) -------------------------------------------------
  // A strategy whose points act through estimates of their forces (an augmented Lagrange method: the
  // law is a penalty around the estimate) may let them move within Newton's iterations. Near the
  // solution (core::Physics::coupleStep) the manager asks each acting point for its constraints g = 0
  // (coupledConstraints: which gap, and the residual's derivative with respect to the constraint's
  // estimate as coefficients of the first variations R_N, R_T1, R_T2) and solves, over all points at
  // once, D delta = g + R du (du Newton's step, D_ij = R_i^T K^-1 F_j with K the model's tangent and F_j
  // the derivative): the estimates' changes that close every gap at the end of the step, a Newton step
  // on the motion and the estimates together. It hands each point its deltas (coupledUpdate, in the
  // order of coupledConstraints) and adds -K^-1 F delta to the step. Only point contacts are coupled
  // (no line point among the contact points), at most maximumCoupledConstraints() constraints (each
  // costs a solve with K per coupled step), and only once the constraints are the same as at the
  // iterate before; otherwise, and when D is singular, the step is Newton's alone (when K is singular:
  // for the rest of the increment). The fixed point is the strategy's own (its acceptPoint still
  // decides): only the way there changes.
  struct CoupledConstraint {
    int gap = 0;  // 0: g_N, 1: g_T1, 2: g_T2 (and the estimate of that force)
    // F_j as coefficients of (R_N, R_T1, R_T2): e.g. a slipping line's force follows the normal one.
    double force[3] = {0.0, 0.0, 0.0};
  };
  virtual int maximumCoupledConstraints() const { return 0; }
  virtual int coupledConstraints(const ContactPoint& p, const PointState& s, CoupledConstraint out[3]) const {
    return 0;
  }
  virtual void coupledUpdate(PointState& s, const CoupledConstraint* c, int n, const double* delta) const {}
  // Upper bound on the Newton solves of one increment (active-set or augmentation passes).
  virtual int maximumPasses() const { return 1; }
  // Whether acceptNormal and acceptPoint change only a point's discrete state (active or not, stick
  // or slip) and keep no estimate that moves from pass to pass (Lagrange multipliers'): then, when
  // the passes of an increment cycle, the contact applies one point's change per pass
  // (ContactManager::acceptSolution). An augmentation must move every point each pass: false.
  virtual bool discreteStates() const { return false; }
  // For the retries of an increment in which many points joined and left the active set within
  // Newton's iterations (AutomaticPenalty::failureHint): whether the strategy can fix the points that
  // act for each Newton solve, as Lagrange multipliers' are (the default: no); on = true does so, each
  // committed point told by engage() whether it acted at the last converged state; on = false once a
  // step is accepted.
  virtual bool canFixActiveSet() const { return false; }
  virtual void fixActiveSet(bool on) const {}
  virtual void engage(PointState& s, bool acts) const {}
  // The forces at the converged state, for output (before commitPoint). By default the evaluation
  // without assembly.
  virtual PointResult reportedForces(const ContactPoint& p, const PointState& s) const;
  // The increment is accepted: keep what the next increment needs (e.g. the friction forces).
  virtual void commitPoint(const ContactPoint& p, PointState& s) const {}

  // --- output and capabilities -------------------------------------------------------------------------
  // The columns the strategy adds to contact_points.csv after the common ones (names, one word each),
  // and their values at a converged point (as many; the same p and s as reportedForces, before
  // commitPoint). By default the penalty parameters (eps_N, eps_T), 0 for a strategy without them, so
  // that every strategy's table has the same columns.
  virtual std::vector<std::string> outputColumns() const { return {"normal_penalty", "tangential_penalty"}; }
  virtual std::vector<double> outputValues(const ContactPoint& p, const PointState& s) const { return {0.0, 0.0}; }
  // Whether multipliers(state) can be > 0: the strategy adds rows of multipliers to the global system
  // (a preconditioner built for nodal dofs only, such as MueLu's, cannot take them). Input and the
  // solvers ask this instead of the strategy's name; a strategy with multipliers says so.
  virtual bool addsMultiplierRows() const { return false; }
};

}  // namespace bc::constraints
