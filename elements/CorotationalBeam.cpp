#include "CorotationalBeam.hpp"

#include <stdexcept>

namespace bc::elements {

namespace {

template <class T> Mat3<T> promote(const Mat3d& A) {
  Mat3<T> B;
  for (int k = 0; k < 9; ++k) B.m[k] = T(A.m[k]);
  return B;
}

template <class T>
Mat3<T> corotatedFrameT(const Mat3<T>& T1, const Mat3<T>& T2, const Vec3<T>& x1, const Vec3<T>& x2) {
  using std::sqrt;
  Vec3<T> dx = x2 - x1;
  T invL = 1.0 / norm(dx);
  Vec3<T> e1 = invL * dx;
  Vec3<T> q = T(0.5) * (column(T1, 1) + column(T2, 1));
  Vec3<T> r3 = cross(e1, q);
  T invR3 = 1.0 / norm(r3);
  Vec3<T> e3 = invR3 * r3;
  Vec3<T> e2 = cross(e3, e1);
  return fromColumns(e1, e2, e3);
}

// Strain energy of the element for nodal positions x1, x2 and nodal rotations R1, R2.
template <class T>
T energyT(const BeamElementData& d, const Vec3<T>& x1, const Vec3<T>& x2, const Mat3<T>& R1, const Mat3<T>& R2) {
  const Mat3<T> T0 = promote<T>(d.T0);
  const Mat3<T> T1 = R1 * T0;
  const Mat3<T> T2 = R2 * T0;
  const Mat3<T> Rr = corotatedFrameT(T1, T2, x1, x2);
  const Mat3<T> RrT = transpose(Rr);
  const Vec3<T> th1 = logSO3(RrT * T1);
  const Vec3<T> th2 = logSO3(RrT * T2);
  const T ua = norm(x2 - x1) - d.L0;
  const T tor = th2[0] - th1[0];
  const double k = 2.0 / d.L0;
  return (0.5 * d.EA / d.L0) * ua * ua + (0.5 * d.GJ / d.L0) * tor * tor +
         (k * d.EIz) * (th1[2] * th1[2] + th1[2] * th2[2] + th2[2] * th2[2]) +
         (k * d.EIy) * (th1[1] * th1[1] + th1[1] * th2[1] + th2[1] * th2[1]);
}

}  // namespace

BeamElementData makeBeamElement(const Vec3d& X1, const Vec3d& X2, const Vec3d& sectionY, double EA, double GJ,
                                double EIy, double EIz) {
  BeamElementData d;
  d.X1 = X1; d.X2 = X2;
  const Vec3d axis = X2 - X1;
  d.L0 = norm(axis);
  if (!(d.L0 > 0.0)) throw std::invalid_argument("beam element of zero length");
  const Vec3d e1 = (1.0 / d.L0) * axis;
  Vec3d y = sectionY - dot(sectionY, e1) * e1;
  const double ny = norm(y);
  if (ny < 1e-8 * norm(sectionY) || !(ny > 0.0))
    throw std::invalid_argument("section orientation is parallel to the beam axis");
  const Vec3d e2 = (1.0 / ny) * y;
  const Vec3d e3 = cross(e1, e2);
  d.T0 = fromColumns(e1, e2, e3);
  d.EA = EA; d.GJ = GJ; d.EIy = EIy; d.EIz = EIz;
  return d;
}

double strainEnergy(const BeamElementData& d, const BeamElementState& s) {
  return energyT<double>(d, s.x1, s.x2, s.R1, s.R2);
}

Mat3d corotatedFrame(const BeamElementData& d, const BeamElementState& s) {
  return corotatedFrameT<double>(s.R1 * d.T0, s.R2 * d.T0, s.x1, s.x2);
}

void internalForce(const BeamElementData& d, const BeamElementState& s, Vector12& f) {
  using F = Sacado::Fad::SFad<double, 12>;
  Vec3<F> x1, x2, w1, w2;
  for (int k = 0; k < 3; ++k) {
    x1[k] = F(12, k, s.x1[k]);
    w1[k] = F(12, 3 + k, 0.0);
    x2[k] = F(12, 6 + k, s.x2[k]);
    w2[k] = F(12, 9 + k, 0.0);
  }
  const Mat3<F> R1 = expSO3SecondOrder(w1) * promote<F>(s.R1);
  const Mat3<F> R2 = expSO3SecondOrder(w2) * promote<F>(s.R2);
  const F E = energyT(d, x1, x2, R1, R2);
  for (int i = 0; i < 12; ++i) f[i] = E.dx(i);
}

void internalForceAndTangent(const BeamElementData& d, const BeamElementState& s, Vector12& f, Matrix12& K) {
  // Inner AD level: the virtual variation w (gives the force); outer level: the Newton increment
  // delta (gives the tangent). Rotations: R = exp(w) exp(delta) R_current, both at zero.
  using In = Sacado::Fad::SFad<double, 12>;
  using Out = Sacado::Fad::SFad<In, 12>;
  Vec3<Out> x1, x2, w1, w2, d1, d2;
  for (int k = 0; k < 3; ++k) {
    x1[k] = Out(12, k, In(12, k, s.x1[k]));
    x2[k] = Out(12, 6 + k, In(12, 6 + k, s.x2[k]));
    w1[k] = Out(In(12, 3 + k, 0.0));
    w2[k] = Out(In(12, 9 + k, 0.0));
    d1[k] = Out(12, 3 + k, In(0.0));
    d2[k] = Out(12, 9 + k, In(0.0));
  }
  const Mat3<Out> R1 = expSO3SecondOrder(w1) * (expSO3SecondOrder(d1) * promote<Out>(s.R1));
  const Mat3<Out> R2 = expSO3SecondOrder(w2) * (expSO3SecondOrder(d2) * promote<Out>(s.R2));
  const Out E = energyT(d, x1, x2, R1, R2);
  for (int i = 0; i < 12; ++i) {
    f[i] = E.val().dx(i);
    for (int j = 0; j < 12; ++j) K[12 * i + j] = E.dx(j).dx(i);
  }
}

}  // namespace bc::elements
