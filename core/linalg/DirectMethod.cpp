#include "DirectMethod.hpp"

#include <stdexcept>

#include "SerialKlu.hpp"
#include "SerialUmfpack.hpp"

namespace bc::core {

const std::vector<DirectMethodEntry>& directMethods() {
  static const std::vector<DirectMethodEntry> entries = {
      {"KLU2",
       "no dense kernels, a matrix of the last one's pattern refactored with its pivot order (the faster on "
       "small or nearly banded matrices: docs/scale.md, \"The default solver\")",
       false,
       [](const Comm&, const ReuseSettings& reuse) { return oneProcessLu(std::make_unique<SerialKlu>(), reuse); }},
      {"UMFPACK",
       "multifrontal with dense (BLAS) kernels, 3 to 6 times faster factorizations at 10^5 rows (most on "
       "Lagrange multiplier saddle points), the faster from a few thousand rows of beams coupled by contact "
       "with Reuse Factorization",
       false,
       [](const Comm&, const ReuseSettings& reuse) { return oneProcessLu(std::make_unique<SerialUmfpack>(), reuse); }},
      {"MUMPS",
       "multifrontal with dense kernels, the matrix factored where its rows are by all ranks together (the "
       "others gather it to rank 0)",
       true, [](const Comm& comm, const ReuseSettings& reuse) { return makeMumpsMethod(comm, reuse); }},
  };
  return entries;
}

std::vector<std::string> directMethodNames() {
  std::vector<std::string> names;
  for (const auto& e : directMethods()) names.push_back(e.name);
  return names;
}

std::string directMethodsDoc() {
  std::string doc;
  for (const auto& e : directMethods()) doc += (doc.empty() ? "" : "; ") + e.name + ": " + e.doc;
  return doc;
}

std::unique_ptr<DirectMethod> makeDirectMethod(const std::string& name, const Comm& comm, const ReuseSettings& reuse) {
  for (const auto& e : directMethods())
    if (e.name == name) {
      auto method = e.make(comm, reuse);
      return e.distributed || comm.getSize() == 1 ? std::move(method) : gatheredToRank0(std::move(method));
    }
  throw std::invalid_argument("no sparse LU factorization named \"" + name + "\"");
}

}  // namespace bc::core
