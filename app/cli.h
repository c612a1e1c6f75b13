// The `immerse` command line (DESIGN §3): subcommands, option parsing, exit codes, reports.
//
// One binary for every dimension; the dimension is taken from the input file. The library calls
// never print or exit (CONVENTIONS "Errors"): this layer maps their results to exit codes and
// messages, and writes every output through write_file_atomic (core/atomic_file.h), so an output
// file is either complete or absent.
//
//   immerse                              the main job on a bundled default input, into ./out/
//   immerse check IN                     validate the input, list every defect
//   immerse cells IN [--json OUT]        the cell complex (paper §4)
//   immerse immersions IN [...]          the immersion search (paper §6, Algorithm 1)
//   immerse mesh IN [...]                the full pipeline (paper §7)
//   immerse generate NAME [params] [-o OUT] | generate --list
//
// `immerse help` / `immerse CMD --help` print the options of each command.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "core/exit_codes.h"

namespace imm {

/// Where `run_cli` prints, and whether progress messages are wanted (stderr is a terminal).
struct CliEnvironment {
  std::ostream& out;            ///< results and listings
  std::ostream& err;            ///< errors, notes, progress and the one-line timing summary
  bool show_progress = false;   ///< forward library progress callbacks to `err`
};

/// Runs `immerse` with `args` (argv without the program name) and returns the exit code.
/// Library exceptions (imm::InvariantError, std::exception) are caught, reported on `err` and
/// mapped to kExitInternalError. Outputs go to the paths named on the command line (or ./out/ for
/// the default job), each written to a temporary name and renamed.
int run_cli(const std::vector<std::string>& args, const CliEnvironment& env);

}  // namespace imm
