#include "BeamSet.hpp"

#include "core/Provenance.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

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

BeamSet::Strains BeamSet::elementStrains(const BeamElement& e, const CrossSection& section, const core::State& state) {
  const BeamElementState s = elementState(e, state);
  const BeamElementData& d = e.data;
  const Mat3d RrT = transpose(corotatedFrame(d, s));
  const Vec3d th1 = logSO3(RrT * (s.R1 * d.T0)), th2 = logSO3(RrT * (s.R2 * d.T0));
  Strains out;
  out.axial = std::abs(norm(s.x2 - s.x1) - d.L0) / d.L0;
  // The local element's deflection is cubic, so its curvature is linear along it and largest at an
  // end: (4 th1 + 2 th2) / L0 at the first, (2 th1 + 4 th2) / L0 at the second (a circular arc:
  // th2 = -th1 = phi / 2, curvature phi / L0). Bending about local y (th[1]) strains the fibres at
  // z = +-h/2, about local z (th[2]) those at y = +-b/2; a circle's farthest fibre is at r from the
  // resultant's axis.
  for (int end = 0; end < 2; ++end) {
    const double a = end == 0 ? 4.0 : 2.0, c = end == 0 ? 2.0 : 4.0;
    const double ky = std::abs(a * th1[1] + c * th2[1]) / d.L0, kz = std::abs(a * th1[2] + c * th2[2]) / d.L0;
    const double fibre = section.shape == CrossSection::Shape::Circle
                             ? section.radius * std::sqrt(ky * ky + kz * kz)
                             : 0.5 * section.height * ky + 0.5 * section.width * kz;
    out.bending = std::max(out.bending, fibre);
  }
  return out;
}

void BeamSet::stepConverged(const core::State& state, double T) {
  strainExcess_.resize(beams_.size());
  std::vector<Strains> worst(beams_.size());
  for (const BeamElement& e : elements_) {
    const Strains s = elementStrains(e, beams_[e.beam].section, state);
    Strains& w = worst[e.beam];
    if (std::max(s.axial, s.bending) > std::max(w.axial, w.bending)) w = s;
  }
  for (std::size_t b = 0; b < beams_.size(); ++b) {
    const double strain = std::max(worst[b].axial, worst[b].bending);
    if (!(strain > kStrainLimit)) continue;
    StrainExcess& x = strainExcess_[b];
    if (x.firstT < 0.0) {
      x.firstT = T;
      x.first = worst[b];
    }
    if (strain > x.largest) {
      x.largest = strain;
      x.largestT = T;
    }
  }
}

std::vector<std::string> BeamSet::warnings() const {
  std::vector<std::string> w;
  for (std::size_t b = 0; b < strainExcess_.size(); ++b) {
    const StrainExcess& x = strainExcess_[b];
    if (x.firstT < 0.0) continue;
    const bool axial = x.first.axial >= x.first.bending;
    std::ostringstream s;
    s << std::setprecision(4) << "beam \"" << beams_[b].name << "\" is strained beyond the beam model's "
      << 100.0 * kStrainLimit << " % from T = " << x.firstT << " (" << (axial ? "axial" : "bending") << " strain "
      << 100.0 * (axial ? x.first.axial : x.first.bending) << " %; largest " << 100.0 * x.largest
      << " % at T = " << x.largestT
      << "): the model assumes small strains, so its results from there are not the material's "
      << "(" << core::documentationPage("beam-element.md") << ")";
    w.push_back(s.str());
  }
  return w;
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
  const char* forces[6] = {"axial force", "shear force y",    "shear force z",
                           "torque",      "bending moment y", "bending moment z"};
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
        outline.emplace_back(cs.radius * std::cos(twoPi * k / kCircleSides),
                             cs.radius * std::sin(twoPi * k / kCircleSides));
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
