// The verdict messages every front end gives (the `immerse` program prefixes "immerse: ", the C++
// API and the Python module carry them in their exceptions): one wording, written once. Each
// message names the input as 'NAME' and has no trailing line break.
#pragma once

#include <cstddef>
#include <string>

#include "core/diagnostics.h"
#include "core/graph_search.h"

namespace imm {

/// How a front end names the options a verdict points to: the program's flags, or the library's
/// parameters (the C++ API's MeshOptions/SearchOptions fields and the Python keywords).
struct OptionNames {
  const char* immersion;   ///< which immersion to mesh
  const char* max_states;  ///< the search's state budget
  const char* time_limit;  ///< the search's time budget
};
inline constexpr OptionNames kProgramOptions{"--immersion", "--max-states", "--time-limit"};
inline constexpr OptionNames kLibraryOptions{"immersion", "max_states", "time_limit"};

/// "1 patch", "2 patches".
std::string plural(std::size_t n, const std::string& word, const std::string& words = "");

/// "invalid input 'NAME': N defects" and one line per defect (at most `max_lines`, then
/// "... and N more"). Exit code 2.
std::string invalid_input_message(const std::string& name, const ValidationReport& report, std::size_t max_lines);

/// "cannot mesh 'NAME'[ HOW]: N defects" and the defects (a background that does not cover the
/// input, a non-generic contact with the background, a cut mesh that doubles cannot hold).
/// Exit code 2.
std::string cannot_mesh_message(const std::string& name, const ValidationReport& report, std::size_t max_lines,
                                const std::string& how = "");

/// "'NAME' is not immersible: REASON" (an inverted region). Exit code 3.
std::string not_immersible_message(const std::string& name, const std::string& reason);

/// "'NAME' is not immersible: N local folds (no perturbation removes a fold, ...)" and every
/// fold. Exit code 3.
std::string local_folds_message(const std::string& name, const ValidationReport& folds);

/// The verdict of a search without immersions: not immersible (naming the rule and what is in
/// conflict), not simply immersible (a self-connecting cell), or undecided (budget, pointing to
/// the budget options as `names` spells them). Exit code 3.
std::string no_immersion_message(const std::string& name, const SearchResult& r, const OptionNames& names);

/// "--immersion K: 'NAME' has only N immersions (numbered from 0)[; the search stopped early ...]"
/// with the option names as `names` spells them.
std::string immersion_index_message(std::size_t k, const std::string& name, std::size_t found, bool complete,
                                    const OptionNames& names);

}  // namespace imm
