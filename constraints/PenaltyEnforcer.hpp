// Penalty method (seed paper (3.1), (3.7)-(3.8), (4.4), (4.10), (4.12)): normal force eps_N g_N while
// penetrating, tangential forces eps_T times the elastic slip, return-mapped onto the Coulomb limit
// (RegularizedContactLaw.hpp). Parameters (sublist "Penalty"): "Normal Penalty Parameter" eps_N,
// "Tangential Penalty Parameter" eps_T [force/length], each a number or "Automatic" (PenaltyChoice.hpp).
//
// On lines (line contact) a spring acts at every Gauss point by default ("Line Springs" = "Gauss
// Points"). With "Nodes" the springs act on the nodes of line A instead, on Lagrange's field: the
// traction lambda = sum_b N_b Lambda_b is linear between the nodes, and a line node's normal row is
// Lagrange's weighted gap less its spring's stretch, the compliance lumped on the node (a perturbed
// Lagrangian; LineContact::evaluateNodal takes the row with the node's own multiplier),
//     int N_a (g_N - Lambda_a / eps_N) ds = 0   over what B covers of the node's elements,
// so Lambda_a = eps_N g_a, g_a the node's weighted gap: a node acts where that gap is closed, its
// traction has its sign, and a penetration d that is the same everywhere gives the traction eps_N d,
// whatever B covers. The field bends as finely as the elements do; springs at every Gauss point over-constrain elements
// that bend less finely than the penalty's wavelength (4 EI / eps_N)^(1/4) (docs/contact.md, "Penalty springs that
// over-constrain a line"). The line nodes' active set is Lagrange's, and so are their friction rows with springs eps_T
// in them: a sticking node's row int N_a (g_T - (Lambda_T,a - Lambda_T,a,n) / eps_T) ds = 0, so that Lambda_T,a =
// Lambda_T,a,n + eps_T g_T,a (its weighted slip) as at a Gauss point (Isotropic Coulomb only: input/Deck.cpp refuses
// Per Line friction with it).
#pragma once
#include "ConstraintEnforcer.hpp"
#include "LagrangeMultiplierEnforcer.hpp"
#include "PenaltyChoice.hpp"
#include "RegularizedContactLaw.hpp"
#include "core/Parameters.hpp"

namespace bc::constraints {

class PenaltyEnforcer : public ConstraintEnforcer {
 public:
  static const char* name() { return "Penalty"; }
  static const char* description() {
    return "normal and stick springs eps_N, eps_T; the gap is of order force / eps_N";
  }
  static const core::ParameterSpec& spec();
  explicit PenaltyEnforcer(const Teuchos::ParameterList& validated);

  // The friction forces of the last converged step (the trial force starts from them) and the
  // point's penalty parameters when they are chosen automatically. A line node (Line Springs = Nodes)
  // keeps its field's active set and friction states instead (`field`).
  struct State : PointStateOf<State> {
    double lambdaT[2] = {0.0, 0.0};
    PointPenalties penalties;
    bool engaged = false;  // Active Set = Between Solves: in the active set for the Newton solve
    bool lineNode = false;
    LagrangeMultiplierEnforcer::State field;
    double committedT[2] = {0.0, 0.0};  // a line node's friction multipliers of the last converged step
    void fields(StateFields& v) override {
      if (lineNode) {
        field.fields(v);
        v.real("committed_T1", committedT[0]);
        v.real("committed_T2", committedT[1]);
        return;
      }
      v.real("lambda_T1", lambdaT[0]);
      v.real("lambda_T2", lambdaT[1]);
      penalties.fields(v);
      v.flag("engaged", engaged);
    }
  };

  std::string type() const override { return name(); }
  std::unique_ptr<PointState> newPointState() const override;
  LineField lineField() const override { return nodal_ ? LineField::Nodal : LineField::PerPoint; }
  std::unique_ptr<PointState> newLineNodeState() const override;
  int multipliers(const PointState& s) const override;
  bool lineFieldPenalized() const override { return nodal_; }
  // lambdaN / eps_N with a given eps_N (Automatic: 0, the node's eps_N is not the Gauss point's).
  double lineFieldGap(double lambdaN) const override {
    return nodal_ && !choice_.automatic() ? lambdaN / choice_.given()[0] : 0.0;
  }
  bool wantsCompliance(const PointState& s) const override {
    const State& h = stateOf<State>(s);
    return !h.lineNode && h.penalties.waiting();
  }
  void setCompliance(PointState& s, const double compliance[3]) const override;
  // Automatic eps_T: chosen again from the tangential compliances times 10^relaxations.
  void relaxTangential(PointState& s, const double compliance[3], int relaxations) const override;
  bool contributes(double gapN, const PointState& s) const override;
  double activationGap(const PointState& s) const override;
  bool acceptNormal(const ContactPoint& p, PointState& s) const override;
  // (Line nodes change their active set between solves, as Lagrange's field does.)
  int maximumPasses() const override { return betweenSolves() || nodal_ ? kPassesBetweenSolves : 1; }
  // (Not with a Regularization Gap: the retry would solve the linear law's problem.)
  bool canFixActiveSet() const override { return !(regularization_ > 0.0); }
  bool holdsFriction() const override { return true; }
  void fixActiveSet(bool on) const override { fixedForRetry_ = on && canFixActiveSet(); }
  void engage(PointState& s, bool acts) const override { stateOf<State>(s).engaged = acts; }
  PointResult evaluate(const ContactPoint& p, const PointState& s, double* f, double* K) const override;
  bool acceptPoint(const ContactPoint& p, PointState& s, double& worstViolation) const override;
  void commitPoint(const ContactPoint& p, PointState& s) const override;
  // The point's (eps_N, eps_T) while it penetrates, else 0 (a line node's: its eps_N, 0).
  std::vector<double> outputValues(const ContactPoint& p, const PointState& s) const override;
  PointResult reportedForces(const ContactPoint& p, const PointState& s) const override;

 private:
  // The law's parameters: eps_N, eps_T (given once here, or chosen per point) and g0.
  PenaltyChoice choice_;
  double regularization_;  // "Regularization Gap" g0 (smoothedPenaltyLaw)
  // "Active Set" = "Between Solves": the points that act are fixed for a Newton solve (their springs
  // hold in tension too) and changed after it, as Lagrange multipliers' are.
  bool betweenSolves_ = false;
  mutable bool fixedForRetry_ = false;  // fixActiveSet: the retries of an increment, until a step is accepted
  bool betweenSolves() const { return betweenSolves_ || fixedForRetry_; }
  // The normal law: smoothed by the Regularization Gap, or, fixed between solves, linear (and
  // bilateral: regularizedEvaluate's last argument) while the point is engaged.
  NormalLaw normalLaw(double epsN) const;
  // Line Springs = Nodes: the line nodes' rows are Lagrange's (its default Gap Tolerance and friction
  // complementarity parameter; no gap tolerance decides anything but when an open node joins).
  bool nodal_ = false;
  LagrangeMultiplierEnforcer field_;
  // A line's eps_N: the given one, or (Automatic) from the shortest field mode's compliance at the
  // point's node with the Normal Target Error, as Augmented Lagrange's line nodes choose theirs.
  double lineEpsN(const ContactPoint& p) const;
  // The springs' compliances 1 / eps_N, 1 / eps_T and the node's committed friction multipliers.
  LagrangeMultiplierEnforcer::Compliance lineCompliance(const ContactPoint& p, const State& h) const;
  static constexpr int kPassesBetweenSolves = 50;
};

}  // namespace bc::constraints
