// KLU2 called directly on a one-process matrix, so that Newton's later matrices of the same pattern
// are refactored with the pivot order of the last full factorization (klu_refactor: no pivot search,
// no new allocation) instead of factored afresh as Amesos2 does. Its own translation unit: KLU2's
// templates are instantiated here.
#pragma once
#include <memory>

#include "SerialLu.hpp"

namespace bc::core {

class SerialKlu : public SerialLu {
 public:
  SerialKlu();
  ~SerialKlu() override;
  std::string name() const override { return "KLU2"; }
  // `refactor` keeps the last pivot order (a zero pivot in that order: factored afresh).
  using SerialLu::factor;
  void factor(const Matrix& A, bool refactor, const double* values) override;
  void preferDiagonalPivots(bool on) override;
  void solve(const double* b, double* x) const override;
  bool factored() const override;
  bool refactorKeepsPivots() const override { return true; }

 private:
  struct Data;
  std::unique_ptr<Data> d_;
  double pivotTolerance_ = 0.001;  // the library default, restored by preferDiagonalPivots(false)
};

}  // namespace bc::core
