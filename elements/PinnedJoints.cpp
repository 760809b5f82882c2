#include "PinnedJoints.hpp"

namespace bc::elements {

using core::GlobalDof;

bool PinnedJoints::prepareIteration(core::State& state) {
  std::map<core::ExtraUnknowns::Key, int> wanted;
  for (std::size_t j = 0; j < joints_.size(); ++j) wanted[{static_cast<long long>(j)}] = 3;
  const bool changed = state.extra.request(kExtraOwner, wanted);
  numNodes_ = state.numNodes();
  offsets_.assign(joints_.size(), -1);
  for (std::size_t j = 0; j < joints_.size(); ++j)
    offsets_[j] = state.extra.find(kExtraOwner, {static_cast<long long>(j)})->offset;
  return changed;
}

std::vector<GlobalDof> PinnedJoints::blockDofs(std::size_t j) const {
  std::vector<GlobalDof> d;
  for (int node : {joints_[j].nodeA, joints_[j].nodeB})
    for (int k = 0; k < 3; ++k) d.push_back(GlobalDof(core::kDofsPerNode) * node + k);
  for (int k = 0; k < 3; ++k) d.push_back(GlobalDof(core::kDofsPerNode) * numNodes_ + offsets_[j] + k);
  return d;
}

void PinnedJoints::connectivity(const OwnsDof& owns, std::vector<std::vector<GlobalDof>>& blocks) const {
  for (std::size_t j = 0; j < joints_.size(); ++j) {
    auto d = blockDofs(j);
    if (owns(d[0])) blocks.push_back(std::move(d));
  }
}

void PinnedJoints::evaluate(const core::State& state, const OwnsDof& owns, core::AssemblySink& sink,
                            bool tangent) const {
  constexpr int n = 9;
  for (std::size_t j = 0; j < joints_.size(); ++j) {
    const auto d = blockDofs(j);
    if (!owns(d[0])) continue;
    double f[n] = {}, K[n * n] = {};
    const Vec3d gap = state.position[joints_[j].nodeA] - state.position[joints_[j].nodeB];
    for (int k = 0; k < 3; ++k) {
      const double lambda = state.extra[offsets_[j] + k];
      f[k] += lambda;
      f[3 + k] -= lambda;
      f[6 + k] += gap[k];
      K[n * k + 6 + k] = 1.0;
      K[n * (3 + k) + 6 + k] = -1.0;
      K[n * (6 + k) + k] = 1.0;
      K[n * (6 + k) + 3 + k] = -1.0;
    }
    sink.add(d.data(), n, f, tangent ? K : nullptr);
  }
}

Vec3d PinnedJoints::force(const core::State& state, std::size_t j) const {
  const auto* block = state.extra.find(kExtraOwner, {static_cast<long long>(j)});
  Vec3d F{};
  if (block)
    for (int k = 0; k < 3; ++k) F[k] = -state.extra[block->offset + k];
  return F;
}

}  // namespace bc::elements
