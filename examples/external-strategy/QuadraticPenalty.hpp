// A strategy written outside BeamContact: penalty with a quadratic normal law
//   lambda_N = -eps_Q g_N^2   while g_N < 0     (the reported normal force eps_Q g_N^2 >= 0)
// so the contact spring stiffens as it closes (stiffness 2 eps_Q |g_N|). Friction: BeamContact's
// regularized Coulomb law (eps_T times the elastic slip, return-mapped onto mu |lambda_N| with the
// deck's friction law). Parameters (sublist "Quadratic Penalty"): "Quadratic Penalty Parameter" eps_Q
// [force/length^2], "Tangential Penalty Parameter" eps_T [force/length].
#pragma once
#include <constraints/ConstraintEnforcer.hpp>
#include <core/Parameters.hpp>

namespace quadratic {

class QuadraticPenalty : public bc::constraints::ConstraintEnforcer {
 public:
  static const char* name() { return "Quadratic Penalty"; }
  static const char* description() { return "normal force eps_Q g_N^2, friction as the penalty method's"; }
  static const bc::core::ParameterSpec& spec();
  explicit QuadraticPenalty(const Teuchos::ParameterList& validated);

  // The friction forces of the last converged step (the trial force starts from them).
  struct State : bc::constraints::PointStateOf<State> {
    double lambdaT[2] = {0.0, 0.0};
    void fields(bc::constraints::StateFields& v) override {
      v.real("lambda_T1", lambdaT[0]);
      v.real("lambda_T2", lambdaT[1]);
    }
  };

  std::string type() const override { return name(); }
  std::unique_ptr<bc::constraints::PointState> newPointState() const override { return std::make_unique<State>(); }
  bool contributes(double gapN, const bc::constraints::PointState&) const override { return gapN < 0.0; }
  double activationGap(const bc::constraints::PointState&) const override { return 0.0; }
  bc::constraints::PointResult evaluate(const bc::constraints::ContactPoint& p, const bc::constraints::PointState& s,
                                        double* f, double* K) const override;
  bool acceptPoint(const bc::constraints::ContactPoint& p, bc::constraints::PointState& s,
                   double& worstViolation) const override;
  void commitPoint(const bc::constraints::ContactPoint& p, bc::constraints::PointState& s) const override;

 private:
  double quadratic_, tangential_;
};

}  // namespace quadratic
