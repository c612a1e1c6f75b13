// Tetrahedral meshes in doubles: background meshes (generated or read) and the unglued output.
// CGAL-free facade (dim3/tet_io.cpp reads and writes, dim3/background3.cpp generates).
//
// Orientation convention: every tet (v0, v1, v2, v3) is positively oriented, i.e. the determinant
// det(v1 - v0, v2 - v0, v3 - v0) > 0 (exactly; CGAL::orientation(v0, v1, v2, v3) == POSITIVE).
// Ids are 0-based everywhere in memory; file formats that count from 1 are converted on read
// and write.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "dim3/complex3.h"
#include "dim3/surface.h"

namespace imm::dim3 {

using Tet = std::array<int, 4>;

struct TetMesh {
  std::vector<Point3> vertices;
  std::vector<Tet> tets;       ///< positively oriented
  std::vector<int> reference;  ///< per tet (output: the owning graph node); may be empty
};

struct TetReadResult {
  TetMesh mesh;
  ValidationReport report;  ///< unreadable, bad indices, non-finite, degenerate tets (exit 2)
  /// Tets given with negative orientation and turned (two vertices swapped) on read.
  std::size_t reoriented = 0;
};

/// Reads a background tet mesh, chosen by the extension: Vega `.veg` (`*VERTICES`, `*ELEMENTS` /
/// `TET`; `*MATERIAL`, `*REGION`, `*SET`, `*INCLUDE`-free sections skipped), Medit `.mesh`
/// (`Dimension 3`, `Vertices`, `Tetrahedra`), TetGen `.node` / `.ele` (either name; the other file
/// beside it). Negatively oriented tets are turned; zero-volume tets, indices out of range,
/// non-finite coordinates and empty meshes are defects naming tet ids, vertex ids and coordinates.
TetReadResult read_tet_mesh(const std::string& path);

/// True when the extension is one `read_tet_mesh` takes (.veg .mesh .node .ele, any case).
bool is_tet_mesh_extension(const std::string& path);

/// Medit `.mesh` (MeshVersionFormatted 2, Dimension 3, 1-based; reference = `reference[t]`, 0 if
/// absent), full double precision.
std::string format_medit_3d(const TetMesh& mesh);
/// VTK XML unstructured grid (ASCII `.vtu`) with cell data "reference" (ParaView opens it).
std::string format_vtu(const TetMesh& mesh);
/// Vega `.veg` (1-based `*VERTICES`, `*ELEMENTS` / `TET`).
std::string format_veg(const TetMesh& mesh);

/// A background grid: cubes of side h = (longest side of `box`) / resolution covering `box` with a
/// margin of at least one cube, each split into 6 Kuhn (Freudenthal) tets around its main
/// diagonal (conforming across cubes, all positively oriented). `attempt` shifts the grid by a
/// small odd fraction of h (attempt 0: the base shift), so that a retry after a non-generic
/// contact with the input lands elsewhere.
/// @pre resolution >= 1, box finite with lo <= hi.
TetMesh make_grid_background(const Box3& box, int resolution, int attempt = 0);

}  // namespace imm::dim3
