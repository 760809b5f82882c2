// Reads a BeamContact XML deck (a Teuchos ParameterList named "BeamContact"), validates every
// sublist against its component's specification and builds the Model. See docs/input.md and
// `beamcontact --print-valid-parameters` for the reference.
#pragma once
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Teuchos_ParameterList.hpp>

#include "core/Model.hpp"
#include "core/Parameters.hpp"
#include "core/StaticSolver.hpp"
#include "elements/BeamSet.hpp"

namespace bc::constraints {
class ContactManager;
}

namespace bc::input {

struct Problem {
  core::Model model;
  std::shared_ptr<elements::BeamSet> beams;
  std::map<std::string, int> beamIndex;  // beam name -> index in beams->beams()
  int joints = 0;  // beam ends joined to a node of another beam (rigid or pinned)
  std::vector<std::pair<int, int>> pins;  // node pairs of the pinned joints
  std::shared_ptr<constraints::ContactManager> contact;  // null without a Contact sublist
  core::SolverSettings solver;
  Teuchos::ParameterList linearSolver;  // validated "Linear Solver" sublist
  std::string outputDirectory;
  bool writeVtk = true;
  int checkpointEvery = 0;  // Output/Checkpoint Every
  int vtkEvery = 1;  // Output/VTK Every (0: only vtkAt)
  std::vector<double> vtkAt;  // Output/VTK At: increasing load factors in (0, 1]
  bool vtkCompression = true;  // Output/VTK Compression
  Teuchos::ParameterList effective;  // the whole deck with defaults filled in
};

// Parses the file (with `sha256`, also the digest of the text read); throws core::InputError naming
// the file for a missing file or malformed XML.
Teuchos::ParameterList readDeckFile(const std::string& path, std::string* sha256 = nullptr);
// Validates `deck` (defaults are filled in place) and builds the problem. The enforcement strategies
// must be registered first (constraints::registerBuiltinEnforcers()). `deckName` names the default
// results directory ("results/<deckName>").
Problem buildProblem(Teuchos::ParameterList deck, const std::string& deckName);
// The deck's fingerprint for checkpoints: the effective parameters without the Output sublist.
std::string deckFingerprint(const Problem& problem);
// The documented reference of every parameter.
Teuchos::ParameterList referenceParameters();

}  // namespace bc::input
