// 3D input: a closed triangle mesh (possibly several components), as read from a file, before
// any exact processing. CGAL-free: included by the CLI, the tests and the generators.
//
// Ids are 0-based in file order. Polygon faces (OBJ/OFF/PLY quads, n-gons) are fan-triangulated
// from their first vertex on load; `source_face` maps every triangle back to its file face.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/diagnostics.h"

namespace imm::dim3 {

using Point3 = std::array<double, 3>;
using Triangle = std::array<std::uint32_t, 3>;

/// Orientation convention: counter-clockwise seen from outside, i.e. the normal
/// (v1 - v0) x (v2 - v0) points out of the enclosed volume (winding number +1 inside).
/// The largest absolute coordinate of a 3D input (README, Limits): validate_surface refuses larger
/// ones with an OutOfRange defect (exit 2).
inline constexpr double kMaxCoordinate3 = 1e300;

struct Surface {
  std::vector<Point3> vertices;
  std::vector<Triangle> triangles;
  /// File face of each triangle (equal to the triangle id when the file had only triangles).
  std::vector<std::uint32_t> source_face;

  [[nodiscard]] std::size_t vertex_count() const { return vertices.size(); }
  [[nodiscard]] std::size_t triangle_count() const { return triangles.size(); }
};

struct SurfaceReadResult {
  Surface surface;
  ValidationReport report;  ///< read errors (unreadable, empty, non-finite); empty when read fine
};

/// Reads OBJ, OFF, PLY (ASCII or binary) or STL (ASCII or binary), chosen by the extension.
/// STL files are welded: vertices with exactly equal coordinates become one vertex.
/// OBJ: `mtllib`/`usemtl`/`vt`/`vn`/`g`/`o`/`s` lines are ignored (a missing .mtl is harmless),
/// `f a/b/c ...` and negative (relative) indices are accepted.
SurfaceReadResult read_surface(const std::string& path);

/// True when the extension is one `read_surface` takes (.obj .off .ply .stl, any case).
bool is_surface_extension(const std::string& path);

/// The checks that need no intersection test, each defect naming triangle ids, vertex ids and
/// coordinates: empty, non-finite coordinates, vertex index out of range, degenerate triangles
/// (repeated vertex or exactly collinear corners), duplicate vertices (same exact coordinates,
/// both used), duplicate faces (same vertex set), open boundary edges, non-manifold edges and
/// vertices, inconsistently oriented neighbours. (Non-orientable closed manifolds show up as
/// inconsistent orientation.) Every defect is reported, not only the first (capped per kind).
ValidationReport validate_surface(const Surface& surface);

/// Writes OBJ / OFF text with full double precision (round-trips exactly).
std::string format_obj(const Surface& surface);
std::string format_off(const Surface& surface);

/// "(x, y, z)" with the shortest round-tripping decimals, for messages.
std::string format_point(const Point3& p);

/// Signed volume enclosed (sum of signed tetrahedra with the origin), in doubles: for display and
/// quick sanity checks only; exact volumes come from the cell complex.
double signed_volume(const Surface& surface);

/// Concatenates b after a (b's ids shifted): several components are one input (paper §6.2).
Surface merge(const Surface& a, const Surface& b);

}  // namespace imm::dim3
