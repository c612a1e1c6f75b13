// Scenes of the project's 3D objects: an input surface with its intersecting triangles in red
// and its intersection curves as tubes (Figs. 1, 17, 20, 22, 24), a tet mesh as its boundary
// with element edges, a cut-away that exposes the tets inside, the copies coloured by
// immersion-graph node (the Medit/.vtu reference) and pulled apart (exploded) so overlapping
// copies can be told apart, per-vertex scalar fields, and the input surface carried by an
// embedding into a (deformed) tet mesh. Uses the CGAL-free dim3 facades only.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "dim3/complex3.h"
#include "dim3/mesh3.h"
#include "dim3/surface.h"
#include "dim3/tet_mesh.h"
#include "render/scene.h"

namespace imm::render {

/// Per input triangle of the complex's surface: true when it crosses another triangle (the
/// exact refinement cut it into several sub-triangles). Paper §4.1.
std::vector<bool> intersecting_triangles(const dim3::Complex& complex);

/// The surface as one part: `intersecting` (per triangle, may be empty) drawn in
/// colors::kIntersecting, the rest in `color`.
Part surface_part(const dim3::Surface& surface, const std::vector<bool>& intersecting = {},
                  const Color& color = colors::kSurface, bool smooth = false);

/// A scene of the surface (surface_part) and, when `complex` is given, its intersection curves
/// (the arcs) as thin dark red tubes.
Scene surface_scene(const dim3::Surface& surface, const dim3::Complex* complex = nullptr, bool smooth = false);

/// A half-space kept by a cut-away: points with normal . p <= offset.
struct CutPlane {
  Vec3 normal{1, 0, 0};
  double offset = 0.0;
};
/// The plane across `axis` (0, 1, 2) at `fraction` (0..1) of `bounds` along it; keep the lower
/// side (or the upper side when `keep_upper`).
CutPlane cut_across(const dim3::Box3& bounds, int axis, double fraction, bool keep_upper = false);
dim3::Box3 tet_mesh_bounds(const dim3::TetMesh& mesh);
/// A view looking obliquely at the face a cut_across(axis, ..., keep_upper) leaves open, with
/// `up` the world axis pointing up in the picture.
View view_facing_cut(int axis, bool keep_upper, int up = 1);

struct TetStyle {
  enum class ColorBy {
    Single,     ///< one colour (`color`)
    Reference,  ///< palette(reference): the immersion-graph node owning each copy
    Flag,       ///< `flag[t]` != 0 in `highlight`, the others in `color`
    Scalar,     ///< `vertex_scalar` (per mesh vertex) through the colour map
  };
  ColorBy color_by = ColorBy::Reference;
  Color color = colors::kSurface;
  Color highlight = palette(1);
  std::vector<int> flag;             ///< per tet, for ColorBy::Flag
  std::vector<double> vertex_scalar;  ///< per vertex, for ColorBy::Scalar
  std::optional<CutPlane> cut;        ///< keep tets whose centroid is on the kept side
  /// Pull the copies apart: every reference's tets move by explode * (centroid of that
  /// reference's tets - centroid of all tets). 0: in place.
  double explode = 0.0;
  bool edges = true;  ///< element edges on the drawn boundary
};

/// The boundary of the kept tets (faces not shared by two kept tets: copies that are unglued
/// from each other show their faces), one part per colour group. Tets with fewer than 4
/// distinct vertices are skipped.
Scene tet_mesh_scene(const dim3::TetMesh& mesh, const TetStyle& style = {});

/// Where the embedding puts each input vertex in `mesh` (the output mesh, or the same mesh
/// deformed: the .emb weights carry the surface along): sum of weights times tet corners.
/// @pre embedding has one entry per surface vertex, each element a tet of `mesh`.
dim3::Surface embedded_surface(const dim3::Surface& surface, const dim3::TetMesh& mesh,
                               const std::vector<dim3::EmbeddedVertex3>& embedding);

}  // namespace imm::render
