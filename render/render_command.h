// `immerse render IN -o OUT.png [options]`: a picture of the user's own input or output with one
// command. The program's command line (app/) hands the arguments after `render` to this
// function, which parses them, renders and maps failures to the exit codes of DESIGN §3.
//
//   surface (.obj .off .ply .stl)     the surface, its intersecting triangles red and its
//                                     intersection curves as tubes (exact complex; skipped with a
//                                     note when the surface is not valid input)
//   tet mesh (.mesh .veg .node .ele)  the boundary with element edges, copies coloured by
//                                     reference (graph node), optional cut-away and exploded view
//   curves (.txt, 2D .svg)            the curves as SVG, converted to PNG by rsvg-convert
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace imm::render {

/// The help text of `immerse render`.
const char* render_command_help();

/// Runs `immerse render` with `args` (the arguments after "render").
/// @return 0 written; 2 unreadable or invalid input; 64 bad command line; 1 the renderer is
/// missing or failed, or the picture cannot be written.
int run_render_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace imm::render
