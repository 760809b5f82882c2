// The entry point of a plug-in library (see input/Plugins.hpp): in one .cpp of the library write
//   BEAMCONTACT_PLUGIN(bc::constraints::registerEnforcer<MyStrategy>();)
// and load it with `beamcontact run deck.xml --plugin libmine.so` or the deck's "Plugins".
#pragma once
#include "EnforcerRegistry.hpp"

#define BEAMCONTACT_PLUGIN(...) \
  extern "C" __attribute__((visibility("default"))) void beamcontact_plugin_register() { __VA_ARGS__ }
