// The BeamContact version, as the top-level CMakeLists.txt's project() states it (CMake checks that the
// two agree). Results, checkpoints and plug-ins record it; a plug-in built against another version is
// refused (constraints/Plugin.hpp).
#pragma once

#ifndef BEAMCONTACT_VERSION  // a test plug-in poses as built against another version (tests/CMakeLists.txt)
#define BEAMCONTACT_VERSION "0.1.0"
#endif

namespace bc::core {
inline constexpr const char* kVersion = BEAMCONTACT_VERSION;
}  // namespace bc::core
