// Medit .mesh text (INRIA's keyword format, 1-based indices), for either dimension: `Dimension
// D`, `Vertices` (D coordinates and a reference each) and the elements of the dimension
// (`Triangles` for D = 2, `Tetrahedra` for D = 3: D + 1 vertex indices and a reference each).
// Every other section (Edges, Corners, Ridges, Required*, Normals, the other dimension's
// elements, ...) is skipped: it holds numbers only, so it ends at the next keyword. '#' starts a
// comment anywhere. Numbers are parsed correctly rounded (std::from_chars), so a written mesh
// reads back bit for bit.
//
// The parser stops at the first syntax error, with its file and line; what the indices and
// coordinates mean (range, finiteness, orientation) is checked by the dimension's reader
// (dim2/background.cpp, dim3/tet_io.cpp), which knows its defects.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/dim_traits.h"

namespace imm {

/// A Medit mesh as written in the file: element indices made 0-based, not checked yet.
template <int D>
struct MeditMesh {
  std::vector<std::array<double, D>> vertices;
  std::vector<std::uint64_t> vertex_line;  ///< the line of each vertex, for messages
  std::vector<std::array<long long, D + 1>> elements;
  std::vector<int> reference;  ///< per element
  std::vector<std::uint64_t> element_line;
};

/// Parses Medit text of dimension D. `file` names it in messages.
/// @return the first syntax error as "file:line: what was expected", empty when it parsed
template <int D>
std::string parse_medit(std::string_view text, const std::string& file, MeditMesh<D>& mesh);

/// Medit text (MeshVersionFormatted 2, Dimension D, 1-based) of `vertices` (reference 0) and
/// `elements` with their `reference` (0 where absent), coordinates as shortest round-trip
/// decimals.
template <int D>
std::string format_medit(const std::vector<std::array<double, D>>& vertices,
                         const std::vector<std::array<int, D + 1>>& elements,
                         const std::vector<int>& reference);

extern template std::string parse_medit<2>(std::string_view, const std::string&, MeditMesh<2>&);
extern template std::string parse_medit<3>(std::string_view, const std::string&, MeditMesh<3>&);
extern template std::string format_medit<2>(const std::vector<std::array<double, 2>>&,
                                            const std::vector<std::array<int, 3>>&,
                                            const std::vector<int>&);
extern template std::string format_medit<3>(const std::vector<std::array<double, 3>>&,
                                            const std::vector<std::array<int, 4>>&,
                                            const std::vector<int>&);

}  // namespace imm
