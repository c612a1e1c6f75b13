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
/// beside it), Gmsh `.msh` 4.1 ASCII (`$Nodes`, `$Elements` of type 4, or 11 whose corners come
/// first; other element types, `$PhysicalNames` and unknown sections skipped; vertices in node-tag
/// order, tets in element-tag order; reference = the first physical tag of the tet's volume
/// entity minus one, -1 for an entity without one). Negatively oriented tets are turned; zero-volume tets, indices out of range,
/// non-finite coordinates and empty meshes are defects naming tet ids, vertex ids and coordinates.
/// Large Vega and TetGen files are parsed, and every file's tets oriented, on `threads` threads
/// (0: one per hardware thread); the result, messages included, is the same for every count.
TetReadResult read_tet_mesh(const std::string& path, unsigned threads = 0);

/// True when the extension is one `read_tet_mesh` takes (.veg .mesh .node .ele .msh, any case).
bool is_tet_mesh_extension(const std::string& path);

/// Medit `.mesh` (MeshVersionFormatted 2, Dimension 3, 1-based; reference = `reference[t]`, 0 if
/// absent), full double precision.
std::string format_medit_3d(const TetMesh& mesh);
/// VTK XML unstructured grid (ASCII `.vtu`) with cell data "reference" (ParaView opens it).
std::string format_vtu(const TetMesh& mesh);
/// Vega `.veg` (1-based `*VERTICES`, `*ELEMENTS` / `TET`).
std::string format_veg(const TetMesh& mesh);

/// Gmsh `.msh` 4.1 ASCII, as Gmsh documents it: one volume entity (tag k + 1) per distinct
/// reference, in increasing order, whose physical group is the reference + 1 (Gmsh tags are
/// strictly positive, so graph node k is physical volume k + 1, named "node k" in
/// `$PhysicalNames`); a reference < 0 gives an entity without a physical group. Every vertex is
/// node tag v + 1 (one block, classified on the first entity), every tet element tag t + 1 of type
/// 4 (4-node tetrahedron, Gmsh's vertex order is ours: positive orientation), grouped into one
/// block per entity, so that tags keep the output order the embedding (`.emb`) refers to.
/// Coordinates round-trip exactly.
std::string format_gmsh(const TetMesh& mesh);

/// TetGen `.node` and `.ele` texts (1-based, TetGen's default): `.node` 'N 3 0 0' and
/// 'index x y z'; `.ele` 'M 4 1' and 'index v0 v1 v2 v3 region' with the reference as the region
/// attribute (0 if absent). Vertex order as in memory: positive orientation.
struct TetGenTexts {
  std::string node;
  std::string ele;
};
TetGenTexts format_tetgen(const TetMesh& mesh);

/// The two paths of a TetGen mesh named by either of them: 'x.node' or 'x.ele' -> {x.node, x.ele}.
std::array<std::string, 2> tetgen_paths(const std::string& path);

/// Face-connected components of a tet mesh: tets sharing a face (the same three output vertices)
/// are in one component. An unglued mesh's overlapping parts share no face, so this counts the
/// solids a simulation sees (the comb's teeth apart, Fig. 21).
std::size_t face_connected_components(const TetMesh& mesh);

/// A background grid: cubes of side h = (longest side of `box`) / resolution covering `box` with a
/// margin of at least one cube, each split into 6 Kuhn (Freudenthal) tets around its main
/// diagonal (conforming across cubes, all positively oriented). `attempt` shifts the grid by a
/// small odd fraction of h (attempt 0: the base shift), so that a retry after a non-generic
/// contact with the input lands elsewhere.
/// @pre resolution >= 1, box finite with lo <= hi.
TetMesh make_grid_background(const Box3& box, int resolution, int attempt = 0);

}  // namespace imm::dim3
