#include "CrossSection.hpp"

#include <algorithm>
#include <cmath>

namespace bc::elements {

double rectangleTorsionConstant(double a, double b) {
  if (a < b) std::swap(a, b);
  const double pi = std::acos(-1.0);
  double sum = 0.0;
  for (int n = 1; n < 200; n += 2) {
    const double term = std::tanh(n * pi * a / (2.0 * b)) / std::pow(n, 5);
    sum += term;
    if (term < 1e-18 * sum) break;
  }
  return a * b * b * b / 3.0 * (1.0 - 192.0 / std::pow(pi, 5) * (b / a) * sum);
}

double CrossSection::area() const {
  return shape == Shape::Rectangle ? width * height : std::acos(-1.0) * radius * radius;
}
double CrossSection::inertiaY() const {
  return shape == Shape::Rectangle ? width * height * height * height / 12.0
                                   : std::acos(-1.0) * std::pow(radius, 4) / 4.0;
}
double CrossSection::inertiaZ() const {
  return shape == Shape::Rectangle ? height * width * width * width / 12.0
                                   : std::acos(-1.0) * std::pow(radius, 4) / 4.0;
}
double CrossSection::torsionConstant() const {
  if (givenTorsionConstant > 0.0) return givenTorsionConstant;
  return shape == Shape::Rectangle ? rectangleTorsionConstant(width, height)
                                   : std::acos(-1.0) * std::pow(radius, 4) / 2.0;
}
CrossSection CrossSection::rectangle(double w, double h) {
  CrossSection s;
  s.shape = Shape::Rectangle;
  s.width = w;
  s.height = h;
  return s;
}
CrossSection CrossSection::circle(double r) {
  CrossSection s;
  s.shape = Shape::Circle;
  s.radius = r;
  return s;
}

}  // namespace bc::elements
