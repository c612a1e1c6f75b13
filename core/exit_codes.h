// The exit codes of `immerse` (DESIGN §3), shared by the program (app/), the public API's error
// values and the Python module, so that every way in reports a verdict with the same number.
#pragma once

namespace imm {

/// Exit codes (DESIGN §3; documented in `immerse --help`).
inline constexpr int kExitOk = 0;              ///< success (and, for `immersions`/`mesh`, immersible)
inline constexpr int kExitInternalError = 1;   ///< a bug (InvariantError) or an output that could not be written
inline constexpr int kExitInvalidInput = 2;    ///< the input is defective (every defect is listed)
inline constexpr int kExitNotImmersible = 3;   ///< valid input, no (simple) immersion, or search budget exhausted
inline constexpr int kExitUsage = 64;          ///< bad command line (EX_USAGE of sysexits.h)

}  // namespace imm
