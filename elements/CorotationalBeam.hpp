// Two-node, 12-dof co-rotational 3D beam element (Euler-Bernoulli local element, linear elastic,
// large displacements and finite rotations, small strains). See docs/beam-element.md.
//
// Dofs of the element, in this order: [du1 (3), dphi1 (3), du2 (3), dphi2 (3)], where du are
// displacement increments and dphi are *spatial spin* increments: a nodal rotation is updated
// multiplicatively, R <- exp(skew(dphi)) R. The internal force is the derivative of the strain energy
// along these variations, and the tangent is the derivative of that force along the same update,
// so Newton with this tangent converges quadratically on the rotation manifold.
//
// Kinematics (Crisfield 1990; Battini & Pacoste 2002): the co-rotated frame has e1 along the current
// chord; e2, e3 follow the mean of the two nodal triads' second axes. Local deformational quantities:
// elongation l - L0 and the rotation vectors theta_i = log(Rr^T R_i T0) of each nodal triad relative
// to the co-rotated frame. Strain energy:
//   E = EA/(2 L0) (l-L0)^2 + GJ/(2 L0) (th2x-th1x)^2
//     + 2 EIz/L0 (th1z^2 + th1z th2z + th2z^2) + 2 EIy/L0 (th1y^2 + th1y th2y + th2y^2).
// The force is E's gradient along the spins, written out (energyGradient in CorotationalBeam.cpp:
// the co-rotated frame's spin and the inverse left Jacobian of the log map); the tangent is that
// gradient's derivative by forward automatic differentiation (Sacado) along the Newton increment.
// internalForceAndTangentFromEnergy gets both by nested AD of E alone (three to four times the cost):
// the tests compare the two to round-off, and each with central finite differences.
#pragma once
#include <array>

#include "core/SmallMath.hpp"

namespace bc::elements {

using namespace bc::math;  // Vec3, Mat3 and the SO(3) maps

struct BeamElementData {
  Vec3d X1{}, X2{};  // reference positions of the two nodes
  Mat3d T0{};  // reference element frame: columns e1 (axis), e2 (section y), e3 (section z)
  double L0 = 0.0;
  double EA = 0.0, GJ = 0.0, EIy = 0.0, EIz = 0.0;
};

struct BeamElementState {
  Vec3d x1{}, x2{};  // current nodal positions
  Mat3d R1{}, R2{};  // current nodal rotations (from the reference configuration)
};

using Vector12 = std::array<double, 12>;
using Matrix12 = std::array<double, 144>;  // row-major

// Builds the reference data of an element; `sectionY` is a direction not parallel to the axis that
// fixes the section's local y axis (it is orthogonalised against the axis).
BeamElementData makeBeamElement(const Vec3d& X1, const Vec3d& X2, const Vec3d& sectionY, double EA, double GJ,
                                double EIy, double EIz);

double strainEnergy(const BeamElementData& d, const BeamElementState& s);
void internalForce(const BeamElementData& d, const BeamElementState& s, Vector12& f);
void internalForceAndTangent(const BeamElementData& d, const BeamElementState& s, Vector12& f, Matrix12& K);
// The same by nested forward AD of the strain energy (the reference of the tests and bench_beam).
void internalForceAndTangentFromEnergy(const BeamElementData& d, const BeamElementState& s, Vector12& f, Matrix12& K);

// The co-rotated frame [e1 e2 e3] of the current state (for output and drawing).
Mat3d corotatedFrame(const BeamElementData& d, const BeamElementState& s);

}  // namespace bc::elements
