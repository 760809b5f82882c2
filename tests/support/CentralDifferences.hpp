// Central differences against a derivative written out: the one loop of every tangent check (beam
// element, contact kinematics, the assembled tangent, the contact contribution).
#pragma once
#include <algorithm>
#include <cmath>

namespace bc::test {

// The largest |derivative - central difference| and the largest |derivative| over the entries checked.
struct CentralDifferenceError {
  double error = 0.0;
  double largest = 0.0;
};

// For each column j < `columns` that skip(j) leaves in, in this order: values(j, h) and values(j, -h)
// (the function with unknown j moved by +h and by -h) and derivative(j) (column j of the derivative
// written out); then, for each row i < `rows` that skip(i) leaves in,
// (values(j, h)[i] - values(j, -h)[i]) / (2 h) against derivative(j)[i].
template <class Values, class Derivative, class Skip>
CentralDifferenceError centralDifferences(int rows, int columns, double h, Values values, Derivative derivative,
                                          Skip skip) {
  CentralDifferenceError e;
  for (int j = 0; j < columns; ++j) {
    if (skip(j)) continue;
    const auto plus = values(j, h);
    const auto minus = values(j, -h);
    const auto column = derivative(j);
    for (int i = 0; i < rows; ++i) {
      if (skip(i)) continue;
      e.error = std::max(e.error, std::abs((plus[i] - minus[i]) / (2 * h) - column[i]));
      e.largest = std::max(e.largest, std::abs(column[i]));
    }
  }
  return e;
}

// Every row and column checked.
template <class Values, class Derivative>
CentralDifferenceError centralDifferences(int rows, int columns, double h, Values values, Derivative derivative) {
  return centralDifferences(rows, columns, h, values, derivative, [](int) { return false; });
}

}  // namespace bc::test
