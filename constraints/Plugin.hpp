// The entry point of a plug-in library (see input/Plugins.hpp): in one .cpp of the library write
//   BEAMCONTACT_PLUGIN(bc::constraints::registerEnforcer<MyStrategy>();)
// and load it with `beamcontact run deck.xml --plugin libmine.so` (a deck's "Plugins" names what it
// needs; --plugin allows it). The macro also records the BeamContact version the library is built
// against: a library built against another version is refused.
#pragma once
#include "EnforcerRegistry.hpp"
#include "core/Version.hpp"

#define BEAMCONTACT_PLUGIN(...)                                                                \
  extern "C" __attribute__((visibility("default"))) const char* beamcontact_plugin_version() { \
    return BEAMCONTACT_VERSION;                                                                \
  }                                                                                            \
  extern "C" __attribute__((visibility("default"))) void beamcontact_plugin_register() { __VA_ARGS__ }
