#include "ContactKinematics.hpp"

#include <cmath>

namespace bc::constraints {

using namespace bc::elements;

namespace {

template <class T> Mat3<T> promote(const Mat3d& A) {
  Mat3<T> B;
  for (int k = 0; k < 9; ++k) B.m[k] = T(A.m[k]);
  return B;
}
template <class T> Vec3<T> promote(const Vec3d& a) { return {{T(a[0]), T(a[1]), T(a[2])}}; }

// Closest points of the lines pA1 + xi (pA2 - pA1) and pB1 + eta (pB2 - pB1): the orthogonality
// conditions are linear in (xi, eta) for straight lines; Cramer's rule.
template <class T>
void solveClosest(const Vec3<T>& pA1, const Vec3<T>& pA2, const Vec3<T>& pB1, const Vec3<T>& pB2, T& xi, T& eta) {
  const Vec3<T> a = pA2 - pA1, b = pB2 - pB1, d = pB1 - pA1;
  const T aa = dot(a, a), ab = dot(a, b), bb = dot(b, b), ad = dot(a, d), bd = dot(b, d);
  // a.(d + eta b - xi a) = 0, b.(d + eta b - xi a) = 0
  const T det = aa * bb - ab * ab;
  xi = (ad * bb - ab * bd) / det;
  eta = (ab * ad - aa * bd) / det;
}

template <class T>
struct Gaps {
  T gN, gT1, gT2, xi, eta;
};

template <class T>
Gaps<T> gaps(const Vec3<T>& xA1, const Vec3<T>& xA2, const Vec3<T>& xB1, const Vec3<T>& xB2, const Mat3<T>& RA1,
             const Mat3<T>& RA2, const Mat3<T>& RB1, const Mat3<T>& RB2, const LinePairInput& in, double sigma,
             double xiPrev, double etaPrev) {
  using std::sqrt;
  const Vec3<T> oA = promote<T>(in.oA), oB = promote<T>(in.oB);
  const Vec3<T> pA1 = xA1 + RA1 * oA, pA2 = xA2 + RA2 * oA;
  const Vec3<T> pB1 = xB1 + RB1 * oB, pB2 = xB2 + RB2 * oB;
  Gaps<T> g;
  solveClosest(pA1, pA2, pB1, pB2, g.xi, g.eta);
  const Vec3<T> tA = pA2 - pA1, tB = pB2 - pB1;
  const Vec3<T> pA = pA1 + g.xi * tA, pB = pB1 + g.eta * tB;
  const Vec3<T> c = cross(tB, tA);
  const T nc = sqrt(dot(c, c));
  const T s = sigma / nc;
  const Vec3<T> n = s * c;
  g.gN = dot(pB - pA, n) - in.radiusSum;
  g.gT1 = (g.xi - xiPrev) * sqrt(dot(tA, tA));
  g.gT2 = (g.eta - etaPrev) * sqrt(dot(tB, tB));
  return g;
}

}  // namespace

ClosestPoints closestPoints(const LinePairInput& in) {
  ClosestPoints cp;
  const Vec3d pA1 = in.xA1 + in.RA1 * in.oA, pA2 = in.xA2 + in.RA2 * in.oA;
  const Vec3d pB1 = in.xB1 + in.RB1 * in.oB, pB2 = in.xB2 + in.RB2 * in.oB;
  const Vec3d tA = pA2 - pA1, tB = pB2 - pB1;
  const Vec3d c = cross(tB, tA);
  cp.sinAngle = norm(c) / (norm(tA) * norm(tB));
  if (!(cp.sinAngle > 1e-12)) return cp;
  solveClosest(pA1, pA2, pB1, pB2, cp.xi, cp.eta);
  cp.pA = pA1 + cp.xi * tA;
  cp.pB = pB1 + cp.eta * tB;
  cp.cA = in.xA1 + cp.xi * (in.xA2 - in.xA1);
  cp.cB = in.xB1 + cp.eta * (in.xB2 - in.xB1);
  const Vec3d n = (1.0 / norm(c)) * c;
  cp.sigma = dot(n, cp.cB - cp.cA) >= 0.0 ? 1.0 : -1.0;
  cp.normal = cp.sigma * n;
  cp.distance = norm(cp.pB - cp.pA);
  cp.gap = dot(cp.pB - cp.pA, cp.normal) - in.radiusSum;
  return cp;
}

ContactKinematics contactKinematics(const LinePairInput& in, double sigma, double xiPrev, double etaPrev) {
  // Inner level: virtual variation w (gives R); outer: Newton increment (gives K). Rotations are
  // R = exp(w) exp(delta) R_current, as for the beam element.
  using In = Sacado::Fad::SFad<double, kPairDofs>;
  using Out = Sacado::Fad::SFad<In, kPairDofs>;
  const Vec3d* x[4] = {&in.xA1, &in.xA2, &in.xB1, &in.xB2};
  const Mat3d* R[4] = {&in.RA1, &in.RA2, &in.RB1, &in.RB2};
  Vec3<Out> xs[4];
  Mat3<Out> Rs[4];
  for (int node = 0; node < 4; ++node) {
    Vec3<Out> w, d;
    for (int k = 0; k < 3; ++k) {
      const int iu = 6 * node + k, ir = 6 * node + 3 + k;
      xs[node][k] = Out(kPairDofs, iu, In(kPairDofs, iu, (*x[node])[k]));
      w[k] = Out(In(kPairDofs, ir, 0.0));
      d[k] = Out(kPairDofs, ir, In(0.0));
    }
    Rs[node] = expSO3SecondOrder(w) * (expSO3SecondOrder(d) * promote<Out>(*R[node]));
  }
  const Gaps<Out> g = gaps(xs[0], xs[1], xs[2], xs[3], Rs[0], Rs[1], Rs[2], Rs[3], in, sigma, xiPrev, etaPrev);
  ContactKinematics out;
  out.xi = g.xi.val().val();
  out.eta = g.eta.val().val();
  const Out* src[3] = {&g.gN, &g.gT1, &g.gT2};
  GapDerivatives* dst[3] = {&out.normal, &out.tangent1, &out.tangent2};
  for (int q = 0; q < 3; ++q) {
    dst[q]->value = src[q]->val().val();
    for (int i = 0; i < kPairDofs; ++i) {
      dst[q]->R[i] = src[q]->val().dx(i);
      for (int j = 0; j < kPairDofs; ++j) dst[q]->K[kPairDofs * i + j] = src[q]->dx(j).dx(i);
    }
  }
  return out;
}

}  // namespace bc::constraints
