// The errors of the linear algebra (core/linalg): a failed solve, and a factorization (or any
// allocation) that cannot have its memory. They are in namespace bc::core with the rest of core, and
// Faults.hpp gives OutOfMemory to the code that reports it.
#pragma once
#include <new>
#include <stdexcept>
#include <string>

namespace bc::core {

// A linear solve failed (a singular matrix, a residual check that does not pass): a failure of the
// Newton step, which the load stepping meets by cutting the step.
class LinearSolveError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An allocation failed (the machine's or the process's memory is exhausted). what() is one line.
class OutOfMemory : public std::bad_alloc {
 public:
  explicit OutOfMemory(std::string what) : what_(std::move(what)) {}
  const char* what() const noexcept override { return what_.c_str(); }

 private:
  std::string what_;
};

// A factorization that needs more memory than it can have. Not a failure of the step (a smaller step
// needs the same): it ends the run, its message in status.txt, exit code 3 (out of memory).
using LinearSolverOutOfMemory = OutOfMemory;

// Whether `e` reports a failed allocation: std::bad_alloc, or Kokkos' report of one (a
// std::runtime_error of several lines starting "Kokkos failed to allocate memory for label ...").
bool isOutOfMemory(const std::exception& e);
// One line for a failed allocation, "out of memory (...)": what could not be allocated when the
// message says (Kokkos: the size and the view's label).
std::string outOfMemoryText(const std::exception& e);
// Throws OutOfMemory when `e` reports a failed allocation (to be called in a handler that would
// otherwise turn the failure into another error, such as a failed linear solve).
void rethrowIfOutOfMemory(const std::exception& e);

}  // namespace bc::core
