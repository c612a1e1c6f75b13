// `immerse render IN -o OUT.png [options]`: a picture of the user's own input or output with one
// command. The program's command line (app/cli_render.cpp) parses the options into a
// RenderRequest; render_picture() reads the input, builds the scene, renders it and maps failures
// to the exit codes of DESIGN §3.
//
//   surface (.obj .off .ply .stl)     the surface, its intersecting triangles red and its
//                                     intersection curves as tubes (exact complex; skipped with a
//                                     note when the surface is not valid input)
//   tet mesh (.mesh .veg .node .ele)  the boundary with element edges, copies coloured by
//                                     reference (graph node), optional cut-away and exploded view
//   curves (.txt, 2D .svg)            the curves as SVG, converted to PNG by rsvg-convert
#pragma once

#include <optional>
#include <ostream>
#include <string>

#include "render/povray.h"
#include "render/scene.h"

namespace imm::render {

/// A cut-away of a tet mesh: keep the tets whose centroid lies below the plane across `axis` at
/// `fraction` of the bounding box (above it with `keep_upper`).
struct CutRequest {
  int axis = 2;
  double fraction = 0.5;
  bool keep_upper = false;
};

/// What `immerse render` draws and how.
struct RenderRequest {
  std::string input;                ///< surface, tet mesh or curves, by extension
  std::string output;               ///< the picture (.png)
  RenderOptions options;            ///< size, antialiasing, shadows, timeout, kept scene
  View view;                        ///< camera (azimuth, elevation, up axis)
  bool view_given = false;          ///< false: with a cut, the camera faces the cut
  std::optional<CutRequest> cut;    ///< tet meshes only
  double explode = 0.0;             ///< tet meshes: copies pulled apart by this times their offset
  bool color_by_node = true;        ///< tet meshes: colour by reference (graph node), else one colour
  bool edges = true;                ///< tet meshes: element edges
  bool intersections = true;        ///< surfaces: compute and draw the intersecting triangles
  bool ground = true;               ///< ground plane and shadow
};

/// Renders `request`, reporting on `out` (the picture written) and `err` (failures).
/// @return 0 written; 2 unreadable or invalid input; 64 an input type it cannot draw, or a cut
/// that leaves nothing; 1 the renderer is missing or failed, or the picture cannot be written.
int render_picture(const RenderRequest& request, std::ostream& out, std::ostream& err);

}  // namespace imm::render
