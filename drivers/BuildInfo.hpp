// How this program was built: version, git commit, build type, Trilinos, MPI library, compiler
// (core/Provenance.hpp). Defined in BuildInfo.cpp, which cmake/BuildInfo.cmake writes into the build
// folder at every build: the commit is the first 12 hex digits of HEAD, "-dirty" when tracked files
// differed from it, "unknown" outside a git checkout.
#pragma once
#include "core/Provenance.hpp"

namespace bc::drivers {

// version, commit, build_type, trilinos, mpi, compiler (what `beamcontact --version` prints).
core::Fields buildProvenance();

}  // namespace bc::drivers
