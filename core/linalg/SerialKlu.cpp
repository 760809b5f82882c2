#include "SerialKlu.hpp"

#include <algorithm>
#include <stdexcept>

// KLU2's headers define their templates in the namespace they are included in (as Amesos2 does).
namespace KLU2 {
#include <klu2_defaults.hpp>
#include <klu2_analyze.hpp>
#include <klu2_factor.hpp>
#include <klu2_tsolve.hpp>
// klu2.h declares klu_refactor with Entry values, klu2_refactor.hpp defines it with double values:
// two templates that no call can choose between. The definition is taken under its own name.
// It also calls klu_scale with NULL for the (template) workspace pointer, which deduces nothing: this
// overload takes that call.
inline int klu_scale(int scale, int n, int Ap[], int Ai[], double Ax[], double Rs[], decltype(NULL),
                     klu_common<double, int>* common) {
  return klu_scale<double, int>(scale, n, Ap, Ai, Ax, Rs, static_cast<int*>(nullptr), common);
}
#undef KLU_refactor
#define KLU_refactor klu_refactor_definition
#include <klu2_refactor.hpp>
#undef KLU_refactor
#include <klu2_free_symbolic.hpp>
#include <klu2_free_numeric.hpp>
#include <klu2_diagnostics.hpp>
}  // namespace KLU2

#include "Errors.hpp"

namespace bc::core {

struct SerialKlu::Data {
  KLU2::klu_common<double, int> common;
  KLU2::klu_symbolic<double, int>* symbolic = nullptr;
  KLU2::klu_numeric<double, int>* numeric = nullptr;

  void release() {
    if (numeric) ::KLU2::klu_free_numeric<double, int>(&numeric, &common);
    if (symbolic) ::KLU2::klu_free_symbolic<double, int>(&symbolic, &common);
    numeric = nullptr;
    symbolic = nullptr;
  }
};

SerialKlu::SerialKlu() : d_(std::make_unique<Data>()) {
  ::KLU2::klu_defaults<double, int>(&d_->common);
  pivotTolerance_ = d_->common.tol;
}

// KLU2 takes the diagonal when it is at least `tol` times the column's largest entry; with a
// tolerance of 1e-300 any nonzero diagonal passes and a zero one does not (with zero it would).
void SerialKlu::preferDiagonalPivots(bool on) { d_->common.tol = on ? 1e-300 : pivotTolerance_; }

SerialKlu::~SerialKlu() { d_->release(); }

bool SerialKlu::factored() const { return d_->numeric != nullptr; }

void SerialKlu::factor(const Matrix& A, bool refactor, const double* given) {
  const auto local = A.getLocalMatrixHost();
  double* values = const_cast<double*>(given ? given : local.values.data());
  // A refactorization needs the very same compressed rows as the factorization it reuses.
  if (!(refactor && factored() && pattern_.same(A))) {
    d_->release();
    pattern_.take(A);
    auto& p = pattern_;
    d_->symbolic = ::KLU2::klu_analyze<double, int>(p.n, p.rowStart.data(), p.columns.data(), &d_->common);
    // KLU2 returns null also when an allocation fails (its status says which): that is the memory's
    // limit, not the matrix's.
    const auto outOfMemory = [&](const char* stage) {
      if (d_->common.status == KLU_OUT_OF_MEMORY)
        throw LinearSolverOutOfMemory(std::string("out of memory (KLU2 could not allocate its ") + stage + " of " +
                                      std::to_string(p.n) +
                                      " rows; the model is too large for this machine's or this process's memory)");
    };
    if (!d_->symbolic) {
      outOfMemory("analysis");
      throw std::runtime_error("KLU2 analysis failed");
    }
    d_->numeric =
        ::KLU2::klu_factor<double, int>(p.rowStart.data(), p.columns.data(), values, d_->symbolic, &d_->common);
    if (!d_->numeric) {
      outOfMemory("factorization");
      throw std::runtime_error("KLU2 numeric factorization failed (singular matrix)");
    }
    ::KLU2::klu_flops<double, int>(d_->symbolic, d_->numeric, &d_->common);
    setIterationsWorth(d_->common.flops, double(d_->numeric->lnz) + d_->numeric->unz + d_->numeric->nzoff,
                       double(p.columns.size()));
    return;
  }
  // A pivot of the old order that is zero now: factor afresh, with pivoting.
  if (!::KLU2::klu_refactor_definition<double, int>(pattern_.rowStart.data(), pattern_.columns.data(), values,
                                                    d_->symbolic, d_->numeric, &d_->common))
    factor(A, false, given);
}

void SerialKlu::solve(const double* b, double* x) const {
  std::copy(b, b + pattern_.n, x);
  if (!::KLU2::klu_tsolve<double, int>(d_->symbolic, d_->numeric, pattern_.n, 1, x, &d_->common))
    throw std::runtime_error("KLU2 solve failed");
}

}  // namespace bc::core
