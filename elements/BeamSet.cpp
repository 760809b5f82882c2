#include "BeamSet.hpp"

#include <cmath>

namespace bc::elements {

using core::GlobalDof;
using core::kDofsPerNode;

int BeamSet::addBeam(const Beam& beam, const std::vector<Vec3d>& reference) {
  const int b = static_cast<int>(beams_.size());
  beams_.push_back(beam);
  const CrossSection& s = beam.section;
  const double E = beam.material.youngsModulus, G = beam.material.shearModulus();
  for (std::size_t k = 0; k + 1 < beam.nodes.size(); ++k) {
    BeamElement e;
    e.beam = b;
    e.index = static_cast<int>(k);
    e.node1 = beam.nodes[k];
    e.node2 = beam.nodes[k + 1];
    e.data = makeBeamElement(reference[e.node1], reference[e.node2], beam.sectionY, E * s.area(),
                             G * s.torsionConstant(), E * s.inertiaY(), E * s.inertiaZ());
    elements_.push_back(e);
  }
  return b;
}

std::array<GlobalDof, 12> BeamSet::elementDofs(const BeamElement& e) {
  std::array<GlobalDof, 12> dofs;
  for (int k = 0; k < 6; ++k) {
    dofs[k] = GlobalDof(kDofsPerNode) * e.node1 + k;
    dofs[6 + k] = GlobalDof(kDofsPerNode) * e.node2 + k;
  }
  return dofs;
}

BeamElementState BeamSet::elementState(const BeamElement& e, const core::State& s) {
  return BeamElementState{s.position[e.node1], s.position[e.node2], s.rotation[e.node1], s.rotation[e.node2]};
}

void BeamSet::connectivity(const OwnsDof& owns, std::vector<std::vector<GlobalDof>>& blocks) const {
  for (const BeamElement& e : elements_) {
    const auto dofs = elementDofs(e);
    if (owns(dofs[0])) blocks.emplace_back(dofs.begin(), dofs.end());
  }
}

void BeamSet::evaluate(const core::State& state, const OwnsDof& owns, core::AssemblySink& sink, bool tangent) const {
  Vector12 f;
  Matrix12 K;
  for (const BeamElement& e : elements_) {
    const auto dofs = elementDofs(e);
    if (!owns(dofs[0])) continue;
    const BeamElementState s = elementState(e, state);
    if (tangent) {
      internalForceAndTangent(e.data, s, f, K);
      sink.add(dofs.data(), 12, f.data(), K.data());
    } else {
      internalForce(e.data, s, f);
      sink.add(dofs.data(), 12, f.data(), nullptr);
    }
  }
}

double BeamSet::energy(const core::State& state, const OwnsDof& owns) const {
  double E = 0.0;
  for (const BeamElement& e : elements_)
    if (owns(elementDofs(e)[0])) E += strainEnergy(e.data, elementState(e, state));
  return E;
}

void BeamSet::appendVtk(const core::State& state, core::VtkMesh& mesh) const {
  // Each element is drawn as a prism of its real cross-section between its two nodal triads:
  // a hexahedron for a rectangle, twelve wedges around the axis for a circle, and as a line cell on
  // its centreline. Every point of a nodal section carries the node's triad (its section axes e1
  // along the beam, e2, e3: "triad e1" .. "triad e3"); every cell of the element its section forces
  // in the element's co-rotated frame, from the internal forces at its second node (constant along a
  // linear element): axial force N (tension > 0), shear forces Vy, Vz, torque T, bending moments My,
  // Mz.
  constexpr int kCircleSides = 12;
  const double twoPi = 2.0 * std::acos(-1.0);
  const char* forces[6] = {"axial force", "shear force y", "shear force z", "torque", "bending moment y",
                           "bending moment z"};
  for (const char* name : forces) mesh.cellScalars[name];
  for (const char* name : {"triad e1", "triad e2", "triad e3"}) mesh.pointVectors[name];
  for (const BeamElement& e : elements_) {
    const elements::BeamElementState es{state.position[e.node1], state.position[e.node2], state.rotation[e.node1],
                                        state.rotation[e.node2]};
    Vector12 f;
    internalForce(e.data, es, f);
    const Mat3d frame = corotatedFrame(e.data, es);
    const Vec3d f2{f[6], f[7], f[8]}, m2{f[9], f[10], f[11]};
    double section[6];
    for (int a = 0; a < 3; ++a) {
      section[a] = dot(f2, column(frame, a));
      section[3 + a] = dot(m2, column(frame, a));
    }
    const std::size_t firstCell = mesh.cellTypes.size();
    const Beam& beam = beams_[e.beam];
    const CrossSection& cs = beam.section;
    std::vector<std::pair<double, double>> outline;  // section points in local (y, z)
    if (cs.shape == CrossSection::Shape::Rectangle) {
      const double y = 0.5 * cs.width, z = 0.5 * cs.height;
      outline = {{-y, -z}, {y, -z}, {y, z}, {-y, z}};
    } else {
      for (int k = 0; k < kCircleSides; ++k)
        outline.emplace_back(cs.radius * std::cos(twoPi * k / kCircleSides), cs.radius * std::sin(twoPi * k / kCircleSides));
    }
    const int base = static_cast<int>(mesh.points.size());
    const int perEnd = static_cast<int>(outline.size()) + 1;  // centre first
    for (int end = 0; end < 2; ++end) {
      const int node = end == 0 ? e.node1 : e.node2;
      const Mat3d Tref = e.data.T0;
      const Mat3d Tcur = state.rotation[node] * e.data.T0;
      const Vec3d& X = state.reference[node];
      const Vec3d& x = state.position[node];
      mesh.addPoint(x, x - X);
      for (const auto& [py, pz] : outline) {
        const Vec3d cur = x + py * column(Tcur, 1) + pz * column(Tcur, 2);
        const Vec3d ref = X + py * column(Tref, 1) + pz * column(Tref, 2);
        mesh.addPoint(cur, cur - ref);
      }
      for (int k = 0; k < perEnd; ++k)
        for (int a = 0; a < 3; ++a)
          mesh.setPointVector(std::string("triad e") + char('1' + a), base + end * perEnd + k, column(Tcur, a));
    }
    mesh.cellTypes.push_back(3);  // VTK_LINE: the centreline
    mesh.cells.push_back({base, base + perEnd});
    mesh.cellBeam.push_back(e.beam);
    mesh.cellElement.push_back(e.index);
    if (cs.shape == CrossSection::Shape::Rectangle) {
      mesh.cellTypes.push_back(12);  // VTK_HEXAHEDRON
      mesh.cells.push_back({base + 1, base + 2, base + 3, base + 4, base + perEnd + 1, base + perEnd + 2,
                            base + perEnd + 3, base + perEnd + 4});
      mesh.cellBeam.push_back(e.beam);
      mesh.cellElement.push_back(e.index);
    } else {
      for (int k = 0; k < kCircleSides; ++k) {
        const int a = 1 + k, b = 1 + (k + 1) % kCircleSides;
        mesh.cellTypes.push_back(13);  // VTK_WEDGE
        mesh.cells.push_back({base, base + a, base + b, base + perEnd, base + perEnd + a, base + perEnd + b});
        mesh.cellBeam.push_back(e.beam);
        mesh.cellElement.push_back(e.index);
      }
    }
    for (std::size_t c = firstCell; c < mesh.cellTypes.size(); ++c)
      for (int k = 0; k < 6; ++k) mesh.setCellScalar(forces[k], static_cast<int>(c), section[k]);
  }
}

}  // namespace bc::elements
