// The beams of a model as a Contribution: a list of co-rotational elements over the global nodes,
// with their sections and materials, evaluated element by element into the assembly sink.
#pragma once
#include <string>
#include <vector>

#include "CorotationalBeam.hpp"
#include "CrossSection.hpp"
#include "core/Contribution.hpp"

namespace bc::elements {

struct Beam {
  std::string name;
  CrossSection section;
  Material material;
  Vec3d sectionY{};  // direction fixing the section's local y axis
  std::vector<int> nodes;  // global node ids, in order along the beam
};

struct BeamElement {
  int beam = 0;  // index into beams()
  int index = 0;  // element index within the beam
  int node1 = 0, node2 = 0;
  BeamElementData data;
};

class BeamSet : public core::Contribution {
 public:
  // Adds a beam whose nodes (already placed in `reference`) are `nodes`; returns its index.
  int addBeam(const Beam& beam, const std::vector<Vec3d>& reference);

  const std::vector<Beam>& beams() const { return beams_; }
  const std::vector<BeamElement>& elements() const { return elements_; }

  std::string name() const override { return "beams"; }
  void connectivity(const OwnsDof& owns, std::vector<std::vector<core::GlobalDof>>& blocks) const override;
  void evaluate(const core::State& state, const OwnsDof& owns, core::AssemblySink& sink, bool tangent) const override;
  double energy(const core::State& state, const OwnsDof& owns) const override;
  void appendVtk(const core::State& state, core::VtkMesh& mesh) const override;

  // The small-strain check: after each converged step, every element's axial strain (l - L0) / L0 and
  // bending strain (the curvature at its ends times the distance of the section's farthest fibre) are
  // compared with kStrainLimit; each beam that exceeds it is a warning naming the first T.
  static constexpr double kStrainLimit = 0.05;
  struct Strains {
    double axial = 0.0, bending = 0.0;
  };
  static Strains elementStrains(const BeamElement& e, const CrossSection& section, const core::State& s);
  void stepConverged(const core::State& state, double T) override;
  std::vector<std::string> warnings() const override;

  static BeamElementState elementState(const BeamElement& e, const core::State& s);
  static std::array<core::GlobalDof, 12> elementDofs(const BeamElement& e);

 private:
  std::vector<Beam> beams_;
  std::vector<BeamElement> elements_;
  // Per beam: the first T at which a strain exceeded kStrainLimit (< 0: none yet), the strains of the
  // beam's worst element then, and the largest strain of any later step with its T.
  struct StrainExcess {
    double firstT = -1.0;
    Strains first;
    double largest = 0.0, largestT = 0.0;
  };
  std::vector<StrainExcess> strainExcess_;
};

}  // namespace bc::elements
