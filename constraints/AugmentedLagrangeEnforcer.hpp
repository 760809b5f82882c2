// Augmented Lagrange method, Uzawa type: within an increment the multipliers are fixed estimates
// lambda_hat and the contact law is the penalty-regularized one around them
// (RegularizedContactLaw.hpp); when Newton has converged, lambda_hat <- lambda (normal and friction)
// and the increment is solved again, until every active point has |g_N| <= "Gap Tolerance" and every
// sticking line |g_T| <= "Gap Tolerance". The converged result therefore does not depend on the
// penalty parameters beyond that tolerance; they only change how many passes it takes.
// Parameters (sublist "Augmented Lagrange"): "Normal Penalty Parameter", "Tangential Penalty
// Parameter" [force/length] (each a number or "Automatic", PenaltyChoice.hpp), "Gap Tolerance"
// [length], "Maximum Augmentations", "Maximum Coupled Constraints" (the update coupled over the points,
// ConstraintEnforcer::coupledConstraints; docs/contact.md, "Cost of the augmentations").
//
// On lines (line contact) the multipliers live on the nodes of line A as Lagrange's do
// (LineField::Nodal, docs/contact.md "Augmented Lagrange on lines"): a line node's normal row is
// Lagrange's weighted gap, regularized by its estimate,
//     int N_a g_N ds - L_a (Lambda_a - lambda_hat_a) / eps_N = 0   (L_a = int N_a ds, a constant),
// so Lambda_a = lambda_hat_a + eps_N L_a g_a / W_a (the augmented law on the field's weighted gap);
// after each Newton solve lambda_hat_a <- Lambda_a until every active node's |g_a| is within Gap
// Tolerance. The fixed point is Lagrange's solution on the same field; eps_N enters the system as
// 1 / eps_N beside the multipliers, so a stiff eps_N (fewer passes) costs no conditioning. Each pass
// divides the error of a field mode of compliance c by 1 + eps_N c, and the shortest mode's c falls
// as h^4 when the beams are refined; so a node's eps_N is at least (1 - e) / (e c_a), e the Normal
// Target Error and c_a that mode's compliance there (ContactPoint::fieldCompliance): every mode's
// error then falls by e per pass, on any mesh. The line nodes' active set and friction rows are
// Lagrange's (its default Friction Complementarity Parameter).
#pragma once
#include "ConstraintEnforcer.hpp"
#include "LagrangeMultiplierEnforcer.hpp"
#include "PenaltyChoice.hpp"
#include "RegularizedContactLaw.hpp"
#include "core/Parameters.hpp"

namespace bc::constraints {

class AugmentedLagrangeEnforcer : public ConstraintEnforcer {
 public:
  static const char* name() { return "Augmented Lagrange"; }
  static const char* description() {
    return "penalty springs around multiplier estimates, augmented until the gaps meet Gap Tolerance";
  }
  static const core::ParameterSpec& spec();
  explicit AugmentedLagrangeEnforcer(const Teuchos::ParameterList& validated);

  // The multiplier estimates lambda_hat (normal and friction), updated at each augmentation, and the
  // point's penalty parameters when they are chosen automatically.
  // A line node (lineNode) keeps instead its field's active set and friction states (`field`) and
  // its normal estimate lambda_hat_a (lambdaN).
  struct State : PointStateOf<State> {
    double lambdaN = 0.0;
    double lambdaT[2] = {0.0, 0.0};
    // Over-relaxation of the Uzawa update (normal, tangential lines): lambda_hat <- lambda_hat +
    // omega eps g, omega from the gap's reduction between the increment's passes (acceptPoint), kept
    // from one increment to the next; and the gaps of the last pass of this increment (0: none yet).
    double omega[3] = {1.0, 1.0, 1.0};
    double lastGap[3] = {0.0, 0.0, 0.0};
    // The forces converged in the last increment (commitPoint extrapolates from them).
    double committedN = 0.0;
    double committedT[2] = {0.0, 0.0};
    PointPenalties penalties;
    // While a failed increment is retried with the active set fixed (fixActiveSet): in it for the
    // Newton solve.
    bool engaged = false;
    bool lineNode = false;
    LagrangeMultiplierEnforcer::State field;
    void fields(StateFields& v) override {
      if (lineNode) {
        field.fields(v);
        v.real("lambda_hat_N", lambdaN);
        return;
      }
      v.real("lambda_N", lambdaN);
      v.real("lambda_T1", lambdaT[0]);
      v.real("lambda_T2", lambdaT[1]);
      v.real("omega_N", omega[0]);
      v.real("omega_T1", omega[1]);
      v.real("omega_T2", omega[2]);
      v.real("last_gap_N", lastGap[0]);
      v.real("last_gap_T1", lastGap[1]);
      v.real("last_gap_T2", lastGap[2]);
      v.real("committed_N", committedN);
      v.real("committed_T1", committedT[0]);
      v.real("committed_T2", committedT[1]);
      v.flag("engaged", engaged);
      penalties.fields(v);
    }
  };

  std::string type() const override { return name(); }
  std::unique_ptr<PointState> newPointState() const override;
  LineField lineField() const override { return LineField::Nodal; }
  std::unique_ptr<PointState> newLineNodeState() const override;
  int multipliers(const PointState& s) const override;
  bool lineNodeRows() const override { return true; }
  // A line node's regularization -L_a (Lambda_N - lambda_hat_N) / eps_N on its normal row.
  void evaluateLineNode(const ContactPoint& node, const PointState& s, double length, double* f,
                        double* K) const override;
  bool wantsCompliance(const PointState& s) const override;
  void setCompliance(PointState& s, const double compliance[3]) const override;
  // Automatic eps_T: chosen again from the tangential compliances times 10^relaxations.
  void relaxTangential(PointState& s, const double compliance[3], int relaxations) const override;
  bool contributes(double gapN, const PointState& s) const override;
  double activationGap(const PointState& s) const override;
  PointResult evaluate(const ContactPoint& p, const PointState& s, double* f, double* K) const override;
  bool acceptNormal(const ContactPoint& p, PointState& s) const override;
  bool acceptPoint(const ContactPoint& p, PointState& s, double& worstViolation) const override;
  int maximumPasses() const override { return maxPasses_; }
  // A failed increment whose active set changed within Newton's iterations is retried with the points
  // that act fixed for each Newton solve (AutomaticPenalty::relaxAfterFailure), as Penalty's are: an
  // engaged point takes the linear law lambda_hat_N + eps_N g_N in tension too, the others nothing;
  // after the solve, points whose law presses join and points in tension leave. Not with a
  // Regularization Gap (the retry would solve the linear law's problem). Line nodes keep their field's
  // active set.
  bool canFixActiveSet() const override { return !(regularization_ > 0.0); }
  bool holdsFriction() const override { return true; }
  void fixActiveSet(bool on) const override { fixed_ = on && canFixActiveSet(); }
  void engage(PointState& s, bool acts) const override { stateOf<State>(s).engaged = acts; }
  // The normal gap of a point in contact beyond the smooth onset (its estimate moves the slipping
  // lines' forces with the normal force) and each sticking line's gap; the update adds the deltas to
  // the estimates.
  int maximumCoupledConstraints() const override { return maxCoupled_; }
  int coupledConstraints(const ContactPoint& p, const PointState& s, CoupledConstraint out[3]) const override;
  void coupledUpdate(PointState& s, const CoupledConstraint* c, int n, const double* delta) const override;
  // acceptPoint has already set the estimates to the converged forces: report and keep those
  // (recomputing lambda_hat + eps g would count the last augmentation twice).
  PointResult reportedForces(const ContactPoint& p, const PointState& s) const override;
  // A new increment: no last pass to measure the gaps' reduction against.
  void commitPoint(const ContactPoint& p, PointState& s) const override;
  // The point's (eps_N, eps_T), open or not; a line node's (eps_N, 0).
  std::vector<double> outputValues(const ContactPoint&, const PointState& s) const override;

 private:
  // A line node's eps_N (lineEpsN).
  double lineEpsN(const ContactPoint& node) const;
  // A point's forces by the law around its estimates (no assembly), and whether they lie within the
  // smooth onset of the Regularization Gap (below eps_N g0 / 2).
  PointResult lawForces(const ContactPoint& p, const State& h) const;
  bool inOnset(const PointResult& r, const State& h) const;
  // The line nodes' active set and friction rows (Lagrange's, with this strategy's Gap Tolerance
  // and Maximum Augmentations).
  LagrangeMultiplierEnforcer field_;
  // The law's parameters: eps_N, eps_T (given once here, or chosen per point), the tolerance and g0.
  PenaltyChoice choice_;
  double tolerance_;
  double regularization_;  // "Regularization Gap" g0 (smoothedAugmentedLaw)
  int maxPasses_;
  int maxCoupled_;  // "Maximum Coupled Constraints"
  mutable bool fixed_ = false;  // fixActiveSet: the retries of an increment, until a step is accepted
  // The point's normal law: smoothed around its estimate, or, fixed for a retry, linear (and bilateral)
  // while it is engaged; whether it acts at all.
  NormalLaw normalLaw(const State& h, double epsN) const;
  bool fixedOut(const State& h) const { return fixed_ && !h.engaged; }
};

}  // namespace bc::constraints
