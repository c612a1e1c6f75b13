// The command line of `immerse`, parsed by CLI11: one table per command (its options, typed and
// validated, with their help), from which CLI11 builds the parser and the generated help.
// A parse either yields a CommandLine for the command to run, or an exit code (help printed: 0;
// usage error printed: kExitUsage, i.e. 64).
#pragma once

#include <cstddef>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "app/cli.h"

namespace imm::cli {

/// What an option takes. Integer and Real are checked by CLI11 before the command runs.
enum class ValueKind {
  Flag,     ///< no value
  Text,     ///< any non-empty text (a path, a name)
  Integer,  ///< a whole decimal integer in [low, high]
  Real,     ///< a finite real number > 0
};

struct OptionSpec {
  std::string name;                  ///< "--json", "-o"
  ValueKind kind = ValueKind::Flag;
  std::string value_name;            ///< shown in the help ("OUT", "N")
  std::string help;                  ///< one paragraph; wrapped by the formatter
  long long low = 0;                 ///< Integer: inclusive range
  long long high = std::numeric_limits<long long>::max();
};

/// One subcommand: its synopsis, description, positional arguments and options.
struct CommandSpec {
  std::string name;                 ///< "mesh"
  std::string usage;                ///< after "usage: immerse ": "mesh IN [options]"
  std::string description;          ///< paragraphs printed before the options
  std::string footer;               ///< printed after the options (exit codes)
  std::string positional_name = "IN";
  std::string positional_help;
  std::size_t min_positional = 1;
  std::size_t max_positional = 1;
  std::string missing_positional = "missing input file";
  std::vector<OptionSpec> options;
};

/// A parsed command line: positional arguments, options with values, flags (option names as
/// written in the table, e.g. "--json").
struct CommandLine {
  std::vector<std::string> positional;
  std::map<std::string, std::string> values;
  std::set<std::string> flags;

  [[nodiscard]] bool has(const std::string& name) const {
    return flags.count(name) != 0 || values.count(name) != 0;
  }
  [[nodiscard]] std::optional<std::string> value(const std::string& name) const {
    const auto it = values.find(name);
    if (it == values.end()) return std::nullopt;
    return it->second;
  }
  /// The value of an Integer option (already range-checked by the parser).
  [[nodiscard]] std::optional<long long> integer(const std::string& name) const;
  /// The value of a Real option (already checked finite and positive by the parser).
  [[nodiscard]] std::optional<double> real(const std::string& name) const;
};

/// The help of `spec`: "usage: immerse <usage>", the description, the generated option list,
/// the footer.
std::string command_help(const CommandSpec& spec);

/// Prints "immerse COMMAND: message", the command's usage line and a pointer to its --help.
/// `spec` may be null (a top-level error). @return kExitUsage.
int print_usage_error(const CliEnvironment& env, const CommandSpec* spec, const std::string& message);

/// Parses `args` (the command's arguments, without the command name) against `spec` with CLI11.
/// @return nullopt when the command is to run with `out`; otherwise the exit code after printing
/// the help (0) or a usage error (64).
std::optional<int> parse_command(const CliEnvironment& env, const CommandSpec& spec,
                                 const std::vector<std::string>& args, CommandLine& out);

}  // namespace imm::cli
