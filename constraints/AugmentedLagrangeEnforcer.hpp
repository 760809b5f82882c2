// Augmented Lagrange method, Uzawa type: within an increment the multipliers are fixed estimates
// lambda_hat and the contact law is the penalty-regularized one around them
// (RegularizedContactLaw.hpp); when Newton has converged, lambda_hat <- lambda (normal and friction)
// and the increment is solved again, until every active point has |g_N| <= "Gap Tolerance" and every
// sticking line |g_T| <= "Gap Tolerance". The converged result therefore does not depend on the
// penalty parameters beyond that tolerance; they only change how many passes it takes.
// Parameters (sublist "Augmented Lagrange"): "Normal Penalty Parameter", "Tangential Penalty
// Parameter" [force/length] (each a number or "Automatic", PenaltyChoice.hpp), "Gap Tolerance"
// [length], "Maximum Augmentations".
#pragma once
#include "ConstraintEnforcer.hpp"
#include "PenaltyChoice.hpp"
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
  struct State : PointStateOf<State> {
    double lambdaN = 0.0;
    double lambdaT[2] = {0.0, 0.0};
    PointPenalties penalties;
    void fields(StateFields& v) override {
      v.real("lambda_N", lambdaN);
      v.real("lambda_T1", lambdaT[0]);
      v.real("lambda_T2", lambdaT[1]);
      penalties.fields(v);
    }
  };

  std::string type() const override { return name(); }
  std::unique_ptr<PointState> newPointState() const override;
  bool wantsCompliance(const PointState& s) const override { return stateOf<State>(s).penalties.waiting(); }
  void setCompliance(PointState& s, const double compliance[3]) const override;
  // Automatic eps_T: chosen again from the tangential compliances times 10^relaxations.
  void relaxTangential(PointState& s, const double compliance[3], int relaxations) const override;
  bool contributes(double gapN, const PointState& s) const override;
  double activationGap(const PointState& s) const override {
    const State& h = stateOf<State>(s);
    h.penalties.require();
    return 0.5 * regularization_ - h.lambdaN / choice_.at(h.penalties)[0];
  }
  PointResult evaluate(const ContactPoint& p, const PointState& s, double* f, double* K) const override;
  bool acceptPoint(const ContactPoint& p, PointState& s, double& worstViolation) const override;
  int maximumPasses() const override { return maxPasses_; }
  // acceptPoint has already set the estimates to the converged forces: report and keep those
  // (recomputing lambda_hat + eps g would count the last augmentation twice).
  PointResult reportedForces(const ContactPoint& p, const PointState& s) const override;
  // The point's (eps_N, eps_T), open or not.
  std::vector<double> outputValues(const ContactPoint&, const PointState& s) const override {
    return choice_.outputValues(stateOf<State>(s).penalties);
  }

 private:
  // The law's parameters: eps_N, eps_T (given once here, or chosen per point), the tolerance and g0.
  PenaltyChoice choice_;
  double tolerance_;
  double regularization_;  // "Regularization Gap" g0 (smoothedAugmentedLaw)
  int maxPasses_;
};

}  // namespace bc::constraints
