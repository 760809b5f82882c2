// Fixed-size 3-vectors and 3x3 matrices, templated on the scalar so that the same kinematics code
// runs on double and on Sacado forward-AD types. Also the SO(3) maps used by the finite-rotation
// update: exp (Rodrigues) and log (via the unit quaternion, stable at zero angle).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <Sacado.hpp>

namespace bc::math {

// Innermost double of a (possibly nested) forward-AD value; used for branch decisions only.
template <class T> double val(const T& x) { return Sacado::ScalarValue<T>::eval(x); }

template <class T> struct Vec3 {
  T v[3];
  T& operator[](int i) { return v[i]; }
  const T& operator[](int i) const { return v[i]; }
};

// Row-major 3x3: m[3*i + j] is row i, column j.
template <class T> struct Mat3 {
  T m[9];
  T& operator()(int i, int j) { return m[3 * i + j]; }
  const T& operator()(int i, int j) const { return m[3 * i + j]; }
};

using Vec3d = Vec3<double>;
using Mat3d = Mat3<double>;

template <class T> Vec3<T> operator+(const Vec3<T>& a, const Vec3<T>& b) {
  return {{a[0] + b[0], a[1] + b[1], a[2] + b[2]}};
}
template <class T> Vec3<T> operator-(const Vec3<T>& a, const Vec3<T>& b) {
  return {{a[0] - b[0], a[1] - b[1], a[2] - b[2]}};
}
template <class T, class S> Vec3<T> operator*(const S& s, const Vec3<T>& a) { return {{s * a[0], s * a[1], s * a[2]}}; }
template <class T> T dot(const Vec3<T>& a, const Vec3<T>& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
template <class T> Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
  return {{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
}
template <class T> T norm(const Vec3<T>& a) {
  using std::sqrt;
  return sqrt(dot(a, a));
}

template <class T> Mat3<T> identity3() {
  Mat3<T> I;
  for (int k = 0; k < 9; ++k) I.m[k] = T(0.0);
  I(0, 0) = I(1, 1) = I(2, 2) = T(1.0);
  return I;
}

template <class T> Mat3<T> operator*(const Mat3<T>& A, const Mat3<T>& B) {
  Mat3<T> C;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) C(i, j) = A(i, 0) * B(0, j) + A(i, 1) * B(1, j) + A(i, 2) * B(2, j);
  return C;
}
template <class T> Vec3<T> operator*(const Mat3<T>& A, const Vec3<T>& x) {
  return {{A(0, 0) * x[0] + A(0, 1) * x[1] + A(0, 2) * x[2], A(1, 0) * x[0] + A(1, 1) * x[1] + A(1, 2) * x[2],
           A(2, 0) * x[0] + A(2, 1) * x[1] + A(2, 2) * x[2]}};
}
template <class T> Mat3<T> transpose(const Mat3<T>& A) {
  Mat3<T> B;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) B(i, j) = A(j, i);
  return B;
}
template <class T> Vec3<T> column(const Mat3<T>& A, int j) { return {{A(0, j), A(1, j), A(2, j)}}; }
template <class T> Mat3<T> fromColumns(const Vec3<T>& a, const Vec3<T>& b, const Vec3<T>& c) {
  Mat3<T> A;
  for (int i = 0; i < 3; ++i) {
    A(i, 0) = a[i];
    A(i, 1) = b[i];
    A(i, 2) = c[i];
  }
  return A;
}
template <class T> Mat3<T> skew(const Vec3<T>& w) {
  Mat3<T> W;
  W(0, 0) = T(0.0);
  W(0, 1) = -w[2];
  W(0, 2) = w[1];
  W(1, 0) = w[2];
  W(1, 1) = T(0.0);
  W(1, 2) = -w[0];
  W(2, 0) = -w[1];
  W(2, 1) = w[0];
  W(2, 2) = T(0.0);
  return W;
}

// exp(skew(w)) truncated after the quadratic term: exact in value, first and second derivatives
// at w = 0, which is all the AD tangent needs (it differentiates at zero spin only).
template <class T> Mat3<T> expSO3SecondOrder(const Vec3<T>& w) {
  Mat3<T> W = skew(w);
  Mat3<T> W2 = W * W;
  Mat3<T> E = identity3<T>();
  for (int k = 0; k < 9; ++k) E.m[k] = E.m[k] + W.m[k] + 0.5 * W2.m[k];
  return E;
}

// Exact exponential map (Rodrigues), double precision.
inline Mat3d expSO3(const Vec3d& w) {
  const double a = norm(w);
  const Mat3d W = skew(w);
  const Mat3d W2 = W * W;
  double c1, c2;
  if (a < 1e-6) {
    c1 = 1.0 - a * a / 6.0;
    c2 = 0.5 - a * a / 24.0;
  } else {
    c1 = std::sin(a) / a;
    c2 = (1.0 - std::cos(a)) / (a * a);
  }
  Mat3d R = identity3<double>();
  for (int k = 0; k < 9; ++k) R.m[k] += c1 * W.m[k] + c2 * W2.m[k];
  return R;
}

// Logarithm of a rotation matrix: the rotation vector with angle in [0, pi]. Extracts the quaternion
// by Shepperd's method (largest component first) and uses a series for small angles, so it is smooth
// (and AD-differentiable) at the identity.
template <class T> Vec3<T> logSO3(const Mat3<T>& R) {
  using std::atan2;
  using std::sqrt;
  const double tr = val(R(0, 0)) + val(R(1, 1)) + val(R(2, 2));
  T q0, q1, q2, q3;
  const double d0 = val(R(0, 0)), d1 = val(R(1, 1)), d2 = val(R(2, 2));
  if (tr >= d0 && tr >= d1 && tr >= d2) {
    q0 = 0.5 * sqrt(1.0 + R(0, 0) + R(1, 1) + R(2, 2));
    T s = 0.25 / q0;
    q1 = (R(2, 1) - R(1, 2)) * s;
    q2 = (R(0, 2) - R(2, 0)) * s;
    q3 = (R(1, 0) - R(0, 1)) * s;
  } else if (d0 >= d1 && d0 >= d2) {
    q1 = 0.5 * sqrt(1.0 + R(0, 0) - R(1, 1) - R(2, 2));
    T s = 0.25 / q1;
    q0 = (R(2, 1) - R(1, 2)) * s;
    q2 = (R(0, 1) + R(1, 0)) * s;
    q3 = (R(0, 2) + R(2, 0)) * s;
  } else if (d1 >= d2) {
    q2 = 0.5 * sqrt(1.0 - R(0, 0) + R(1, 1) - R(2, 2));
    T s = 0.25 / q2;
    q0 = (R(0, 2) - R(2, 0)) * s;
    q1 = (R(0, 1) + R(1, 0)) * s;
    q3 = (R(1, 2) + R(2, 1)) * s;
  } else {
    q3 = 0.5 * sqrt(1.0 - R(0, 0) - R(1, 1) + R(2, 2));
    T s = 0.25 / q3;
    q0 = (R(1, 0) - R(0, 1)) * s;
    q1 = (R(0, 2) + R(2, 0)) * s;
    q2 = (R(1, 2) + R(2, 1)) * s;
  }
  if (val(q0) < 0.0) {
    q0 = -q0;
    q1 = -q1;
    q2 = -q2;
    q3 = -q3;
  }
  T s2 = q1 * q1 + q2 * q2 + q3 * q3;  // sin^2(angle/2)
  T factor;  // angle / sin(angle/2)
  if (val(s2) < 1e-10) {
    // 2 atan(s/c)/s = (2/c) (1 - s^2/(3 c^2)) + O(s^4)
    factor = (2.0 / q0) * (1.0 - s2 / (3.0 * q0 * q0));
  } else {
    T s = sqrt(s2);
    factor = 2.0 * atan2(s, q0) / s;
  }
  return {{factor * q1, factor * q2, factor * q3}};
}

// Closest points of the segments [a1, a2] and [b1, b2] (parameters clamped to [0, 1]): the minimum of
// a convex quadratic over the unit square, at its stationary point if inside, else on an edge.
struct SegmentClosest {
  double s = 0.0, t = 0.0, distance = 0.0;
};
inline SegmentClosest segmentClosest(const Vec3d& a1, const Vec3d& a2, const Vec3d& b1, const Vec3d& b2) {
  const Vec3d u = a2 - a1, v = b2 - b1, w = a1 - b1;
  const double uu = dot(u, u), uv = dot(u, v), vv = dot(v, v);
  SegmentClosest best{0.0, 0.0, std::numeric_limits<double>::infinity()};
  auto consider = [&](double s, double t) {
    const double d = norm(a1 + s * u - b1 - t * v);
    if (d < best.distance) best = {s, t, d};
  };
  auto onB = [&](const Vec3d& p) { return vv > 0 ? std::clamp(dot(p - b1, v) / vv, 0.0, 1.0) : 0.0; };
  auto onA = [&](const Vec3d& p) { return uu > 0 ? std::clamp(dot(p - a1, u) / uu, 0.0, 1.0) : 0.0; };
  consider(0.0, onB(a1));
  consider(1.0, onB(a2));
  consider(onA(b1), 0.0);
  consider(onA(b2), 1.0);
  const double det = uu * vv - uv * uv;
  if (det > 1e-12 * uu * vv) {
    const double s = (uv * dot(v, w) - vv * dot(u, w)) / det, t = (uu * dot(v, w) - uv * dot(u, w)) / det;
    if (s > 0 && s < 1 && t > 0 && t < 1) consider(s, t);
  }
  return best;
}

}  // namespace bc::math
