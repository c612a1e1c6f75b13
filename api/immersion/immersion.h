// The public C++ API of immersion (Li & Barbič 2018, "Immersion of Self-Intersecting Solids and
// Surfaces"): read an input, build its exact cell complex, search its immersions, mesh one.
//
// A thin layer over the libraries (core/, dim2/, dim3/), beside the `immerse` program and the
// Python module: it converts plain arrays in and out, calls, and reports failures as
// immersion::Error with the messages the program prints (without its "immerse: " prefix) and
// the program's exit code. It holds no algorithm. This header needs only the standard library:
// the libraries' types stay behind it (installed as `libimmersion`, found with
// `find_package(immersion)`, linked as `immersion::immersion`).
//
//   immersion::Surface s = immersion::read_surface("quintupleTorus.obj");
//   immersion::Immersions<3> found = immersion::find_immersions(s);       // throws if none
//   immersion::MeshOptions options;
//   options.background = "quintupleTorus.veg";
//   immersion::SimplexMesh<3> mesh = immersion::mesh_immersion(found, options);
//   // mesh.vertices, mesh.elements (positively oriented tets), mesh.node (graph node per tet),
//   // mesh.embedding (where each input vertex is): ready for a simulator.
//
// Ids are 0-based everywhere, in input (file) order, as in the program's messages and files.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace immersion {

/// Version of the library (the CMake package's version).
std::string version();

// ---- errors ------------------------------------------------------------------------------------

/// What went wrong, with the exit code `immerse` gives for it (DESIGN §3).
enum class ErrorKind {
  InvalidInput,   ///< the input (or a background mesh) is defective: exit code 2
  NotImmersible,  ///< valid input without a (simple) immersion, or a search budget ran out: 3
  Internal,       ///< a bug, or a file that cannot be read or written: 1
};

/// The exit code `immerse` gives for a kind: 2, 3 or 1.
constexpr int exit_code_of(ErrorKind kind) {
  return kind == ErrorKind::InvalidInput ? 2 : kind == ErrorKind::NotImmersible ? 3 : 1;
}

/// Thrown by every function below. what() is the program's message without "immerse: ", e.g.
/// "invalid input 'a.obj': 2 defects\n<one line per defect>" or
/// "'fig8.txt' is not immersible: Rule 5 ...".
class Error : public std::runtime_error {
 public:
  Error(ErrorKind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}
  [[nodiscard]] ErrorKind kind() const { return kind_; }
  /// 2, 3 or 1, as `immerse` exits.
  [[nodiscard]] int exit_code() const { return exit_code_of(kind_); }

 private:
  ErrorKind kind_;
};

// ---- inputs ------------------------------------------------------------------------------------

/// 2D input: closed polygonal curves. Curve k joins its vertices in order and closes back to the
/// first; a counter-clockwise outer curve encloses winding number +1. Vertex and segment ids are
/// global in curve order (curve 0's vertices first), as in the program's messages.
struct Curves {
  std::vector<std::vector<std::array<double, 2>>> curves;
  /// How messages name the input ("'name'"); the path for read_curves.
  std::string name = "<arrays>";
};

/// 3D input: a closed, consistently oriented triangle mesh (several components allowed),
/// triangles counter-clockwise seen from outside.
struct Surface {
  std::vector<std::array<double, 3>> vertices;   ///< V, #V x 3
  std::vector<std::array<int, 3>> triangles;     ///< F, #F x 3, indices into vertices
  std::string name = "<arrays>";
};

/// Reads 2D curves: text (`x y` per line, a blank line ends a curve), SVG, OBJ `v`/`l`.
/// @throws Error InvalidInput naming every defect (file, curve, vertex ids, coordinates).
Curves read_curves(const std::string& path);

/// Reads a 3D surface: OBJ, OFF, PLY, STL (polygons fan-triangulated).
/// @throws Error InvalidInput naming every read defect.
Surface read_surface(const std::string& path);

// ---- the cell complex (paper §4) -----------------------------------------------------------------

namespace detail {
template <int D>
struct ComplexData;
template <int D>
struct ImmersionsData;
}  // namespace detail

/// The exact cell complex: regions of space cut by the input, their winding numbers, cells
/// (regions of non-zero winding), patches (pieces of the input between intersection curves)
/// and arcs (where two patches cross: crossing points in 2D, intersection curves in 3D).
/// Cheap to copy (shared, immutable).
template <int D>
class Complex {
 public:
  [[nodiscard]] std::size_t region_count() const;
  [[nodiscard]] std::size_t cell_count() const;
  [[nodiscard]] std::size_t patch_count() const;
  [[nodiscard]] std::size_t arc_count() const;
  [[nodiscard]] int max_winding_number() const;
  /// Winding number of each cell (>= 1), by cell id.
  [[nodiscard]] std::vector<int> cell_winding_numbers() const;
  /// Area (2D) or volume (3D) of each cell, by cell id, rounded from the exact value (3D: from
  /// doubles when built with exact_volumes = false).
  [[nodiscard]] std::vector<double> cell_measures() const;
  /// The exact area / volume of each cell as a rational "p/q" (empty strings when not exact).
  [[nodiscard]] std::vector<std::string> cell_measures_exact() const;
  /// Region of each cell, by cell id.
  [[nodiscard]] std::vector<int> cell_regions() const;
  /// Per patch: the region on its positive and on its negative side (winding drops by one
  /// across the patch in the direction of its normal).
  [[nodiscard]] std::vector<std::array<int, 2>> patch_regions() const;
  /// True when the input was entirely inside-out (clockwise) and was reversed.
  [[nodiscard]] bool reversed() const;

  std::shared_ptr<const detail::ComplexData<D>> data_;  ///< the library's complex
};

struct BuildOptions {
  /// 3D: exact rational volumes (slower on large inputs; 2D areas are always exact).
  bool exact_volumes = true;
  /// 3D: threads for the per-triangle triangulations (0 = all cores); the result is the same.
  unsigned threads = 0;
  /// 3D, `--repair-folds MAX`: move local-fold vertices by at most MAX (model units) instead of
  /// the local-fold verdict; unset: local folds throw NotImmersible.
  std::optional<double> repair_folds;
};

/// Builds the exact cell complex. Paper §4.1–4.3.
/// @throws Error InvalidInput (defects, non-generic contacts) or NotImmersible (a region of
///         negative winding number: the input inverts space).
Complex<2> build_complex(const Curves& curves, const BuildOptions& options = {});
Complex<3> build_complex(const Surface& surface, const BuildOptions& options = {});

// ---- immersions (paper §5-6) ---------------------------------------------------------------------

/// One immersion: the graph of cell copies. Node n is a copy of cell `node_cell[n]`; cell c has
/// as many nodes as its winding number. Two nodes are glued across a patch by an edge; every
/// patch is owned by exactly one node (Rules 1-7).
struct ImmersionGraph {
  std::vector<int> node_cell;                ///< per node: its cell
  std::vector<std::array<int, 3>> edges;     ///< (inner node, outer node, patch)
  std::vector<int> patch_owner;              ///< per patch: the node that owns it
  std::size_t components = 0;                ///< connected components of the immersed shape
};

struct SearchOptions {
  /// Stop after this many distinct immersions; 0 = every one (the program's --all).
  std::size_t max_immersions = 1;
  /// Budget on search states and wall time (0 = none), as --max-states / --time-limit.
  std::size_t max_states = 50'000'000;
  double time_limit_seconds = 0.0;
  /// 3D: cut self-connecting cells with helper boxes (paper §6.2), as the program does unless
  /// --no-helper-boxes.
  bool helper_boxes = true;
  /// 3D: threads for building the complex (0 = all cores).
  unsigned threads = 0;
  /// 3D: as BuildOptions::repair_folds; what was moved is in Immersions::notes.
  std::optional<double> repair_folds;
};

/// The immersions found, with the complex they refer to.
template <int D>
struct Immersions {
  std::vector<ImmersionGraph> graphs;  ///< pairwise non-isomorphic, in discovery order
  bool complete = false;               ///< every immersion was enumerated
  /// The complex the graphs refer to. 3D: built with the helper boxes, when some were needed
  /// (their triangles come after the input's; cell, patch and arc ids include them).
  Complex<D> complex;
  std::size_t helper_boxes = 0;        ///< 3D
  std::vector<std::string> notes;      ///< what was done (fold repair, helper boxes), as the program prints

  std::shared_ptr<const detail::ImmersionsData<D>> data_;  ///< what meshing needs
};

/// Builds the complex and searches its immersions (Algorithm 1); in 3D cuts self-connecting
/// cells with helper boxes first, as the program does (the complex is then rebuilt, which is why
/// the search starts from the input and not from a Complex). The complex is built without exact
/// volumes (the search reads none). Paper §5.2, §6.
/// @throws Error InvalidInput, or NotImmersible naming the rule, cells and patches in conflict
///         (also a self-connecting cell left, or an exhausted budget).
Immersions<2> find_immersions(const Curves& curves, const SearchOptions& options = {});
Immersions<3> find_immersions(const Surface& surface, const SearchOptions& options = {});

// ---- meshing (paper §7) --------------------------------------------------------------------------

enum class MeshMethod { Clip, Csg };

struct MeshOptions {
  /// Which immersion (index into Immersions::graphs).
  std::size_t immersion = 0;
  /// Background resolution: 2D target edges across the diagonal (default 24), 3D grid cubes
  /// along the longest side (default 16). Ignored with `background`.
  std::optional<int> resolution;
  /// A background mesh file instead (2D: Medit .mesh; 3D: .veg, .mesh, .node/.ele, .msh).
  std::optional<std::string> background;
  /// 3D: a graded background instead of the uniform grid (`mesh --surface-resolution M
  /// [--gap-resolution G]`, issue 17): the Kuhn grid refined by conforming bisection to cubes of
  /// side longest / M where it meets the input and longest / G where two separate pieces of the
  /// input come within about one element; `resolution` (default 8) is then the size far away.
  /// Excludes `background` and `conforming`; M >= resolution, G >= M.
  std::optional<int> surface_resolution;
  std::optional<int> gap_resolution;
  /// Elements never cut by the input: 2D constrained triangles; 3D TetGen tets whose boundary
  /// faces are the cut triangles (`mesh --conforming`). Excludes `background` and Csg.
  bool conforming = false;
  /// 3D conforming: target edge length (default: longest box side / resolution), radius-edge
  /// bound (>= 1), minimum dihedral angle in degrees aimed for (0: none), as the program's options.
  std::optional<double> edge_length;
  double radius_edge = 2.0;
  double min_dihedral = 0.0;
  MeshMethod method = MeshMethod::Clip;
  unsigned threads = 0;              ///< 3D: threads for the virtual tets (0 = all cores)
};

/// An unglued simplex mesh: triangles in 2D, tets in 3D, positively oriented.
template <int D>
struct SimplexMesh {
  std::vector<std::array<double, D>> vertices;    ///< #V x D
  std::vector<std::array<int, D + 1>> elements;   ///< #T x (D + 1)
  std::vector<int> node;                           ///< per element: the graph node that owns it
  /// Per input vertex (input order): the element holding it and D + 1 barycentric weights that
  /// reproduce it (the `.emb` file).
  std::vector<int> embedding_element;
  std::vector<std::array<double, D + 1>> embedding_weights;
  /// 3D: the translation applied to the input relative to a given background to make every
  /// contact generic ((0,0,0) when none was needed).
  std::array<double, D> input_shift{};
};

/// Meshes immersion `options.immersion`. Paper §7, §7.1.
/// @throws Error InvalidInput (unreadable background, background not covering the input,
///         non-generic contact) or Internal (options.immersion out of range is InvalidInput).
SimplexMesh<2> mesh_immersion(const Immersions<2>& immersions, const MeshOptions& options = {});
SimplexMesh<3> mesh_immersion(const Immersions<3>& immersions, const MeshOptions& options = {});

/// Writes a mesh chosen by the extension of `path` (atomically: complete or absent).
/// 2D: .mesh (Medit). 3D: .mesh, .vtu, .veg, .msh (Gmsh 4.1), .node (TetGen, with the .ele
/// beside it). @throws Error Internal when it cannot be written, InvalidInput for an unknown
/// extension.
void write_mesh(const SimplexMesh<2>& mesh, const std::string& path);
void write_mesh(const SimplexMesh<3>& mesh, const std::string& path);

}  // namespace immersion
