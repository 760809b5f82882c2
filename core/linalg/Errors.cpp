#include "Errors.hpp"

namespace bc::core {

bool isOutOfMemory(const std::exception& e) {
  if (dynamic_cast<const std::bad_alloc*>(&e)) return true;
  const std::string what = e.what();
  return what.find("Kokkos failed to allocate memory") != std::string::npos ||
         what.find("likely due to insufficient memory") != std::string::npos;
}

std::string outOfMemoryText(const std::exception& e) {
  const std::string what = e.what();
  // A failed allocation of ours says what ran out (OutOfMemory, which LinearSolverOutOfMemory names).
  if (dynamic_cast<const std::bad_alloc*>(&e) && what != std::bad_alloc().what() && !what.empty() &&
      what.find('\n') == std::string::npos)
    return what.find("out of memory") != std::string::npos ? what : "out of memory: " + what;
  const std::string kLabel = "memory for label \"", kSize = "Allocation of size ";
  std::string detail;
  const auto size = what.find(kSize);
  if (size != std::string::npos) {
    const auto from = size + kSize.size(), to = what.find(" failed", from);
    if (to != std::string::npos && to - from < 40) detail = what.substr(from, to - from);
  }
  const auto label = what.find(kLabel);
  if (label != std::string::npos) {
    const auto from = label + kLabel.size(), to = what.find('"', from);
    if (to != std::string::npos && to - from < 200)
      detail = (detail.empty() ? "" : detail + " ") + "for \"" + what.substr(from, to - from) + "\"";
  }
  if (!detail.empty()) detail = "Kokkos could not allocate " + detail + "; ";
  return "out of memory (" + detail + "the model is too large for this machine's or this process's memory)";
}

void rethrowIfOutOfMemory(const std::exception& e) {
  if (isOutOfMemory(e)) throw OutOfMemory(outOfMemoryText(e));
}

}  // namespace bc::core
