// Coulomb friction as a reusable piece: the return mapping of a trial friction force onto the limit
// mu |lambda_N| for either friction law, for any normal law (any strategy may call it).
//
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

#include "ConstraintEnforcer.hpp"

namespace bc::constraints::cone {

inline double value(double x) { return x; }
template <class T> double value(const T& x) { return Sacado::ScalarValue<T>::eval(x); }

// M g: the covariant components of the vector g^1 a - g^2 b in the basis (a, -b).
template <class T> void metric(const T& c, const T g[2], T out[2]) {
  out[0] = g[0] - c * g[1];
  out[1] = -c * g[0] + g[1];
}

// |v|_{M^-1}^2 = v^T M^-1 v, M^-1 = [1 c; c 1] / (1 - c^2).
template <class T> T lengthSquared(const T& c, const T v[2]) {
  return (v[0] * v[0] + 2.0 * c * v[0] * v[1] + v[1] * v[1]) / (1.0 - c * c);
}

// Projection of v onto the disk |v|_{M^-1} <= radius (radius <= 0: the origin). Returns true when v
// lay outside (slip).
template <class T> bool project(const T& c, const T& radius, const T v[2], T out[2]) {
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

namespace bc::constraints {

// The return mapping: the friction force components `out` for the trial components `trial` and the
// limit `radius` = mu |lambda_N| (<= 0: no friction force can be carried). Isotropic Coulomb projects
// the vector onto |lambda_T|_{M^-1} <= radius (c = cosine of the lines' angle); Per Line clamps each
// component to [-radius, radius]. `slip[i]` tells whether line i slips. Differentiable: with Sacado
// types the derivatives of `out` are those of the mapping (consistent tangents).
template <class T>
void returnMap(FrictionLaw law, const T& c, const T& radius, const T trial[2], T out[2], bool slip[2]) {
  if (law == FrictionLaw::IsotropicCoulomb) {
    slip[0] = slip[1] = cone::project(c, radius, trial, out);
    return;
  }
  for (int i = 0; i < 2; ++i) {
    if (!(cone::value(radius) > 0.0)) {
      out[i] = T(0.0);
      slip[i] = true;
    } else if (std::abs(cone::value(trial[i])) <= cone::value(radius)) {
      out[i] = trial[i];
      slip[i] = false;
    } else {
      out[i] = cone::value(trial[i]) >= 0.0 ? T(radius) : T(-radius);
      slip[i] = true;
    }
  }
}

// The trial friction force of a regularized (penalty-type) friction law: lambda_hat_T + eps_T times
// the elastic slip, measured as M g_T for Isotropic Coulomb (the slip vector's components conjugate
// to the force components) and as g_Ti on each line for Per Line.
template <class T>
void frictionTrial(FrictionLaw law, const T& c, const T g[2], const double lambdaHat[2], double epsT, T trial[2]) {
  T Mg[2];
  if (law == FrictionLaw::IsotropicCoulomb) {
    cone::metric(c, g, Mg);
  } else {
    Mg[0] = g[0];
    Mg[1] = g[1];
  }
  for (int i = 0; i < 2; ++i) trial[i] = lambdaHat[i] + epsT * Mg[i];
}

}  // namespace bc::constraints
