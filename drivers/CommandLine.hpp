// The command line's conventions, one table of options per subcommand driving both the parsing and
// its --help (beamcontact <command> --help):
//   --name VALUE and --name=VALUE alike; -o / -q where an option has a short form; options and the
//   positional arguments in any order ("--" ends the options); -h or --help anywhere prints the help.
// A usage error is a UsageError: one line naming the problem, which the program ends with
// "(see beamcontact <command> --help)" and exit code 1.
#pragma once
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace bc::drivers::cli {

struct UsageError : std::runtime_error {
  UsageError(const std::string& command, const std::string& message) : std::runtime_error(message), command(command) {}
  std::string command;  // "run", "generate grid", ...: its --help is the hint
};

struct Option {
  Option(std::string name, char shortName, std::string value, std::string defaultText, std::string meaning,
         bool repeat = false, bool optionalValue = false, std::string implicit = "")
      : name(std::move(name)),
        shortName(shortName),
        value(std::move(value)),
        defaultText(std::move(defaultText)),
        meaning(std::move(meaning)),
        repeat(repeat),
        optionalValue(optionalValue),
        implicit(std::move(implicit)) {}
  std::string name;  // long name, without "--"
  char shortName = 0;  // -x, or 0: none
  std::string value;  // what the value is (DIR, N, ...); empty: a flag, given or not
  std::string defaultText;  // what applies when the option is left out
  std::string meaning;
  bool repeat = false;  // may be given more than once (each value kept)
  bool optionalValue = false;  // the value may be left out (then `implicit`): --timing [N]
  std::string implicit;
};

struct Positional {
  std::string name;  // DECK.xml
  std::string meaning;
};

struct Command {
  Command() = default;
  Command(std::string name, std::string summary, std::vector<Positional> positionals, std::vector<Option> options,
          std::string notes = "")
      : name(std::move(name)),
        summary(std::move(summary)),
        positionals(std::move(positionals)),
        options(std::move(options)),
        notes(std::move(notes)) {}
  std::string name;  // as typed after "beamcontact": "run", "generate grid"
  std::string summary;  // what the command does (a paragraph, lines of up to 100 characters)
  std::vector<Positional> positionals;  // all required, in order
  std::vector<Option> options;  // -h, --help is added
  std::string notes;  // printed after the options
};

struct Parsed {
  bool help = false;  // -h or --help was given: nothing else was checked
  std::vector<std::string> positionals;
  std::map<std::string, std::vector<std::string>> values;  // flags: {""}
  bool has(const std::string& name) const { return values.count(name) > 0; }
  std::string get(const std::string& name, const std::string& fallback = "") const {
    const auto it = values.find(name);
    return it == values.end() ? fallback : it->second.back();
  }
  std::vector<std::string> all(const std::string& name) const {
    const auto it = values.find(name);
    return it == values.end() ? std::vector<std::string>() : it->second;
  }
};

// Reads `args` (the words after the command's name) by `command`'s table; throws UsageError.
Parsed parse(const Command& command, const std::vector<std::string>& args);

// The command's --help text: usage line, summary, positionals, every option with its default and
// meaning, and, where it cites docs/, the documentationNote().
std::string help(const Command& command);
// "docs/ above is DIR\n": where the documentation that help texts cite as docs/ is (installed:
// share/beamcontact/docs; core::documentationDirectory()).
std::string documentationNote();

}  // namespace bc::drivers::cli
