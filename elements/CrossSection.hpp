// Cross-section properties of the beams: rectangle b x h (width b along the section's local y axis,
// height h along local z) and circle of radius r. The torsion constant of a rectangle is the
// Saint-Venant series (Timoshenko & Goodier, Theory of Elasticity, sec. 109):
//   J = a b^3 / 3 [1 - 192/pi^5 (b/a) sum_{n=1,3,5..} tanh(n pi a / (2 b)) / n^5],  a >= b,
// not b h^3 / 3 (that is the thin-strip limit). Units: lengths L, areas L^2, inertias L^4.
#pragma once
#include <string>

namespace bc::elements {

struct CrossSection {
  enum class Shape { Rectangle, Circle };
  Shape shape = Shape::Rectangle;
  double width = 0.0;  // b, along local y (rectangle)
  double height = 0.0;  // h, along local z (rectangle)
  double radius = 0.0;  // circle
  double givenTorsionConstant = 0.0;  // > 0: used instead of Saint-Venant's value (benchmarks stating GJ)

  double area() const;
  double inertiaY() const;  // integral of z^2: resists bending in the local x-z plane
  double inertiaZ() const;  // integral of y^2: resists bending in the local x-y plane
  double torsionConstant() const;

  static CrossSection rectangle(double width, double height);
  static CrossSection circle(double radius);
};

// Saint-Venant torsion constant of an a x b rectangle (any order of a, b), series to machine precision.
double rectangleTorsionConstant(double a, double b);

struct Material {
  double youngsModulus = 0.0;
  double poissonsRatio = 0.0;
  double shearModulus() const { return youngsModulus / (2.0 * (1.0 + poissonsRatio)); }
};

}  // namespace bc::elements
