// Model generators: many-beam decks from a few parameters (beamcontact generate KIND [options]).
#pragma once
#include <string>
#include <vector>

namespace bc::drivers {

// Writes the deck for `args` (args[0] = "generate", args[1] = the kind, then --option value pairs) to
// --output FILE or standard output; returns the exit code. Throws core::InputError on bad options.
int generateDeck(const std::vector<std::string>& args);

}  // namespace bc::drivers
