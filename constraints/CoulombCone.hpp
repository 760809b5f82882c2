// The isotropic Coulomb cone in the components of the tangential gaps (see ConstraintEnforcer.hpp):
// the tangential gaps g = (g_T1, g_T2) are lengths along two lines whose unit tangents a, b meet
// with cosine c, so the slip vector s = g_T1 a - g_T2 b has |s|^2 = g^T M g with M = [1 -c; -c 1];
// the force components lambda_T conjugate to g belong to the physical force F_T = Q M^-1 lambda_T
// (Q = [a, -b]), whose length is |lambda_T|_{M^-1} = sqrt(lambda_T^T M^-1 lambda_T).
// Written for plain doubles and for Sacado forward AD types, so that the strategies get the
// consistent tangent of the return mapping by differentiation, not by hand.
#pragma once
#include <cmath>

#include <Sacado.hpp>

namespace bc::constraints::cone {

inline double value(double x) { return x; }
template <class T>
double value(const T& x) {
  return Sacado::ScalarValue<T>::eval(x);
}

// M g: the covariant components of the vector g^1 a - g^2 b in the basis (a, -b).
template <class T>
void metric(const T& c, const T g[2], T out[2]) {
  out[0] = g[0] - c * g[1];
  out[1] = -c * g[0] + g[1];
}

// |v|_{M^-1}^2 = v^T M^-1 v, M^-1 = [1 c; c 1] / (1 - c^2).
template <class T>
T lengthSquared(const T& c, const T v[2]) {
  return (v[0] * v[0] + 2.0 * c * v[0] * v[1] + v[1] * v[1]) / (1.0 - c * c);
}

// Projection of v onto the disk |v|_{M^-1} <= radius (radius <= 0: the origin). Returns true when v
// lay outside (slip).
template <class T>
bool project(const T& c, const T& radius, const T v[2], T out[2]) {
  using std::sqrt;
  if (!(value(radius) > 0.0)) {
    out[0] = out[1] = T(0.0);
    return true;
  }
  const T n2 = lengthSquared(c, v);
  if (std::sqrt(value(n2)) <= value(radius)) {
    out[0] = v[0];
    out[1] = v[1];
    return false;
  }
  const T scale = radius / sqrt(n2);
  out[0] = scale * v[0];
  out[1] = scale * v[1];
  return true;
}

}  // namespace bc::constraints::cone
