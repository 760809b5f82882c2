// Penalty method (seed paper (3.1), (3.7)-(3.8), (4.4), (4.10), (4.12)): normal force eps_N g_N while
// penetrating, tangential forces eps_T times the elastic slip, return-mapped onto the Coulomb limit
// (RegularizedContactLaw.hpp). Parameters (sublist "Penalty"): "Normal Penalty Parameter" eps_N,
// "Tangential Penalty Parameter" eps_T [force/length], each a number or "Automatic" (PenaltyChoice.hpp).
#pragma once
#include "ConstraintEnforcer.hpp"
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
  // point's penalty parameters when they are chosen automatically.
  struct State : PointStateOf<State> {
    double lambdaT[2] = {0.0, 0.0};
    PointPenalties penalties;
    bool engaged = false;  // Active Set = Between Solves: in the active set for the Newton solve
    void fields(StateFields& v) override {
      v.real("lambda_T1", lambdaT[0]);
      v.real("lambda_T2", lambdaT[1]);
      penalties.fields(v);
      v.flag("engaged", engaged);
    }
  };

  std::string type() const override { return name(); }
  std::unique_ptr<PointState> newPointState() const override;
  bool wantsCompliance(const PointState& s) const override { return stateOf<State>(s).penalties.waiting(); }
  void setCompliance(PointState& s, const double compliance[3]) const override;
  // Automatic eps_T: chosen again from the tangential compliances times 10^relaxations.
  void relaxTangential(PointState& s, const double compliance[3], int relaxations) const override;
  bool contributes(double gapN, const PointState& s) const override {
    return betweenSolves() ? stateOf<State>(s).engaged : gapN <= 0.0;
  }
  double activationGap(const PointState& s) const override {
    return betweenSolves() ? ConstraintEnforcer::activationGap(s) : 0.0;
  }
  bool acceptNormal(const ContactPoint& p, PointState& s) const override;
  int maximumPasses() const override { return betweenSolves() ? kPassesBetweenSolves : 1; }
  // (Not with a Regularization Gap: the retry would solve the linear law's problem.)
  bool canFixActiveSet() const override { return !(regularization_ > 0.0); }
  void fixActiveSet(bool on) const override { fixedForRetry_ = on && canFixActiveSet(); }
  void engage(PointState& s, bool acts) const override { stateOf<State>(s).engaged = acts; }
  PointResult evaluate(const ContactPoint& p, const PointState& s, double* f, double* K) const override;
  bool acceptPoint(const ContactPoint& p, PointState& s, double& worstViolation) const override;
  void commitPoint(const ContactPoint& p, PointState& s) const override;
  // The point's (eps_N, eps_T) while it penetrates, else 0.
  std::vector<double> outputValues(const ContactPoint& p, const PointState& s) const override;

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
  static constexpr int kPassesBetweenSolves = 50;
};

}  // namespace bc::constraints
