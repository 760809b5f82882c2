// Model generators: many-beam decks from a few parameters (beamcontact generate KIND [options]).
#pragma once
#include <string>
#include <vector>

namespace bc::drivers {

// Writes the deck for `args` (args[0] = "generate", args[1] = the kind, then --option value pairs) to
// --output FILE or standard output (--help: prints the options); returns the exit code. Throws
// cli::UsageError on a bad command line, core::InputError on values the generator cannot use.
int generateDeck(const std::vector<std::string>& args);

}  // namespace bc::drivers
