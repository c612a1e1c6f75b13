// The public API (api/immersion/immersion.h) over the libraries: converts arrays, calls
// dim2/dim3/core, and turns their reports into immersion::Error with the program's messages.
// No algorithm here: each function is the library call the program makes for the same command.
#include "immersion/immersion.h"

#include <cmath>
#include <limits>
#include <utility>

#include "core/atomic_file.h"
#include "core/exit_codes.h"
#include "core/graph_search.h"
#include "core/parallel.h"
#include "core/text_io.h"
#include "core/verdicts.h"
#include "dim2/complex2.h"
#include "dim2/curves.h"
#include "dim2/mesh2.h"
#include "dim3/complex3.h"
#include "dim3/conforming_mesh3.h"
#include "dim3/mesh3.h"
#include "dim3/self_connecting.h"
#include "dim3/surface.h"
#include "dim3/tet_mesh.h"

#ifndef IMM_VERSION
#define IMM_VERSION "0.0.0"
#endif

namespace immersion {

namespace detail {
template <>
struct ComplexData<2> {
  std::shared_ptr<const imm::dim2::Complex2> complex;
  bool exact_measures = true;  ///< 2D areas are always exact
};
template <>
struct ComplexData<3> {
  std::shared_ptr<const imm::dim3::Complex> complex;
  bool exact_measures = true;  ///< BuildOptions::exact_volumes
};
template <>
struct ImmersionsData<2> {
  std::string name;
  imm::SearchResult search;
};
template <>
struct ImmersionsData<3> {
  std::string name;
  imm::dim3::Surface input;  ///< the user's surface (the conforming mesher's default edge length)
  imm::dim3::Immersed immersed;
};
}  // namespace detail

namespace {

using imm::ImmersionStatus;
using imm::SearchResult;
using imm::ValidationReport;

/// At most this many defect lines in a message (the program's cap; every defect is in the report).
constexpr std::size_t kMaxDefectLines = 50;

[[noreturn]] void throw_defects(const std::string& name, const ValidationReport& report,
                                const std::string& note = "") {
  throw Error(ErrorKind::InvalidInput,
              imm::invalid_input_message(name, report, kMaxDefectLines) + (note.empty() ? "" : "\nnote: " + note));
}

[[noreturn]] void throw_no_immersion(const std::string& name, const SearchResult& r, const std::string& hint = "") {
  throw Error(ErrorKind::NotImmersible, imm::no_immersion_message(name, r, imm::kLibraryOptions) + hint);
}

[[noreturn]] void throw_inversion(const std::string& name, const std::string& reason) {
  throw Error(ErrorKind::NotImmersible, imm::not_immersible_message(name, reason));
}

/// The option values the program refuses on its command line (exit 64) are InvalidInput here:
/// NaN or negative budgets were taken silently.
void check_repair_folds(const std::optional<double>& max) {
  if (max && !(*max > 0 && std::isfinite(*max)))
    throw Error(ErrorKind::InvalidInput, "repair_folds must be a positive number");
}

imm::SearchOptions search_options(const SearchOptions& o) {
  if (!(o.time_limit_seconds >= 0 && std::isfinite(o.time_limit_seconds)))
    throw Error(ErrorKind::InvalidInput, "time_limit_seconds must be a finite number >= 0 (0: no limit)");
  check_repair_folds(o.repair_folds);
  imm::SearchOptions s;
  s.max_immersions = o.max_immersions;
  s.max_states = o.max_states;
  s.time_limit_seconds = o.time_limit_seconds;
  return s;
}

/// Runs f, turning a library bug (InvariantError) or any other exception into Error Internal.
template <class F>
auto guarded(F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(ErrorKind::Internal, std::string("internal error: ") + e.what());
  }
}

imm::dim2::CurveSet to_curve_set(const Curves& in) {
  imm::dim2::CurveSet out;
  out.curves.reserve(in.curves.size());
  for (const auto& curve : in.curves) {
    imm::dim2::Curve c;
    c.vertices.reserve(curve.size());
    for (const auto& p : curve) c.vertices.push_back({p[0], p[1]});
    out.curves.push_back(std::move(c));
  }
  return out;
}

/// The surface as the libraries take it; an index out of range is a defect like the readers'.
imm::dim3::Surface to_surface(const Surface& in) {
  imm::dim3::Surface out;
  out.vertices = in.vertices;
  out.triangles.reserve(in.triangles.size());
  ValidationReport report;
  for (std::size_t t = 0; t < in.triangles.size(); ++t) {
    imm::dim3::Triangle tri{};
    for (int k = 0; k < 3; ++k) {
      const int v = in.triangles[t][k];
      if (v < 0 || static_cast<std::size_t>(v) >= in.vertices.size()) {
        report.add(imm::Defect{imm::DefectKind::OutOfRange, "input",
                               "triangle " + std::to_string(t) + " refers to vertex " +
                                   std::to_string(v) + ", but there are " +
                                   std::to_string(in.vertices.size()) + " vertices",
                               {static_cast<long>(t)}, {static_cast<long>(v)}, {}});
      }
      tri[k] = static_cast<std::uint32_t>(v);
    }
    out.triangles.push_back(tri);
    out.source_face.push_back(static_cast<std::uint32_t>(t));
  }
  if (!report.ok()) throw_defects(in.name, report);
  return out;
}

Complex<2> wrap(std::shared_ptr<const imm::dim2::Complex2> c) {
  Complex<2> out;
  out.data_ = std::make_shared<detail::ComplexData<2>>(detail::ComplexData<2>{std::move(c), true});
  return out;
}

Complex<3> wrap(std::shared_ptr<const imm::dim3::Complex> c) {
  const bool exact = c->exact_volumes;
  Complex<3> out;
  out.data_ = std::make_shared<detail::ComplexData<3>>(detail::ComplexData<3>{std::move(c), exact});
  return out;
}

ImmersionGraph graph_of(const imm::Immersion& im) {
  ImmersionGraph g;
  for (std::size_t n = 0; n < im.layout.node_count(); ++n)
    g.node_cell.push_back(im.layout.cell(imm::NodeId(static_cast<int>(n))).value());
  for (const imm::ImmersionEdge& e : im.edges)
    g.edges.push_back({e.inner.value(), e.outer.value(), e.patch.value()});
  for (std::size_t p = 0; p < im.owner.size(); ++p)
    g.patch_owner.push_back(im.owner[imm::PatchId(static_cast<int>(p))].value());
  g.components = im.components().size();
  return g;
}

}  // namespace

// The header is self-contained (no core/ include), so its exit codes are checked here against
// the program's (core/exit_codes.h).
static_assert(exit_code_of(ErrorKind::InvalidInput) == imm::kExitInvalidInput);
static_assert(exit_code_of(ErrorKind::NotImmersible) == imm::kExitNotImmersible);
static_assert(exit_code_of(ErrorKind::Internal) == imm::kExitInternalError);

std::string version() { return IMM_VERSION; }

// ---- Complex ---------------------------------------------------------------------------------------

template <int D>
const imm::CellComplex<D>& cell_complex(const Complex<D>& c) {
  if (!c.data_ || !c.data_->complex) throw Error(ErrorKind::Internal, "empty immersion::Complex");
  return c.data_->complex->complex;
}

template <int D>
std::size_t Complex<D>::region_count() const { return cell_complex(*this).region_count(); }
template <int D>
std::size_t Complex<D>::cell_count() const { return cell_complex(*this).cell_count(); }
template <int D>
std::size_t Complex<D>::patch_count() const { return cell_complex(*this).patch_count(); }
template <int D>
std::size_t Complex<D>::arc_count() const { return cell_complex(*this).arc_count(); }
template <int D>
int Complex<D>::max_winding_number() const { return cell_complex(*this).max_winding_number(); }
template <int D>
bool Complex<D>::reversed() const {
  cell_complex(*this);
  return data_->complex->reversed;
}
template <int D>
std::vector<int> Complex<D>::cell_winding_numbers() const {
  const auto& c = cell_complex(*this);
  std::vector<int> out;
  for (imm::CellId cell : imm::ids<imm::CellId>(c.cell_count())) out.push_back(c.winding_number(cell));
  return out;
}
template <int D>
std::vector<double> Complex<D>::cell_measures() const {
  const auto& c = cell_complex(*this);
  std::vector<double> out;
  for (imm::CellId cell : imm::ids<imm::CellId>(c.cell_count()))
    out.push_back(imm::to_double(c.measure(c.region_of(cell))));
  return out;
}
template <int D>
std::vector<std::string> Complex<D>::cell_measures_exact() const {
  const auto& c = cell_complex(*this);
  const bool exact = data_->exact_measures;
  std::vector<std::string> out;
  for (imm::CellId cell : imm::ids<imm::CellId>(c.cell_count()))
    out.push_back(exact ? imm::to_string(c.measure(c.region_of(cell))) : std::string());
  return out;
}
template <int D>
std::vector<int> Complex<D>::cell_regions() const {
  const auto& c = cell_complex(*this);
  std::vector<int> out;
  for (imm::CellId cell : imm::ids<imm::CellId>(c.cell_count())) out.push_back(c.region_of(cell).value());
  return out;
}
template <int D>
std::vector<std::array<int, 2>> Complex<D>::patch_regions() const {
  const auto& c = cell_complex(*this);
  std::vector<std::array<int, 2>> out;
  for (imm::PatchId p : imm::ids<imm::PatchId>(c.patch_count()))
    out.push_back({c.sides(p).positive.value(), c.sides(p).negative.value()});
  return out;
}

template class Complex<2>;
template class Complex<3>;

// ---- reading ---------------------------------------------------------------------------------------

Curves read_curves(const std::string& path) {
  return guarded([&] {
    imm::dim2::ReadResult read = imm::dim2::read_curves(path);
    if (!read.report.ok()) throw_defects(path, read.report);
    Curves out;
    out.name = path;
    for (const imm::dim2::Curve& c : read.curves.curves) {
      auto& curve = out.curves.emplace_back();
      for (const imm::dim2::Point& p : c.vertices) curve.push_back({p.x, p.y});
    }
    return out;
  });
}

Surface read_surface(const std::string& path) {
  return guarded([&] {
    imm::dim3::SurfaceReadResult read = imm::dim3::read_surface(path);
    if (!read.report.ok()) throw_defects(path, read.report);
    Surface out;
    out.name = path;
    out.vertices = std::move(read.surface.vertices);
    out.triangles.reserve(read.surface.triangles.size());
    for (const imm::dim3::Triangle& t : read.surface.triangles)
      out.triangles.push_back({static_cast<int>(t[0]), static_cast<int>(t[1]), static_cast<int>(t[2])});
    return out;
  });
}

// ---- building ----------------------------------------------------------------------------------

namespace {

/// build_complex for curves, shared by build_complex and find_immersions (prepare_curves).
std::shared_ptr<const imm::dim2::Complex2> built_curves(const Curves& curves) {
  imm::dim2::BuildResult built = imm::dim2::build_complex(to_curve_set(curves));
  if (!built.report.ok()) throw_defects(curves.name, built.report);
  if (built.inversion) throw_inversion(curves.name, built.inversion->message);
  if (!built.complex) throw Error(ErrorKind::Internal, "build_complex returned no complex");
  return built.complex;
}

/// The bounds the program's command line enforces, for the library's options (a resolution of
/// 0 failed an internal invariant, one of 10^6 an allocation check, and threads = 10^9 allocated
/// per-thread scratch until the process was killed).
void check_threads(unsigned threads) {
  if (threads > imm::kMaxThreads)
    throw Error(ErrorKind::InvalidInput, "threads: at most " + std::to_string(imm::kMaxThreads) + " (0 = all cores), got " +
                                             std::to_string(threads));
}

void check_resolution(const std::optional<int>& resolution, int max) {
  if (resolution && !(*resolution >= 1 && *resolution <= max))
    throw Error(ErrorKind::InvalidInput, "resolution expects 1.." + std::to_string(max) + ", got " + std::to_string(*resolution));
}

}  // namespace

Complex<2> build_complex(const Curves& curves, const BuildOptions&) {
  return guarded([&] { return wrap(built_curves(curves)); });
}

Complex<3> build_complex(const Surface& surface, const BuildOptions& options) {
  return guarded([&] {
    check_threads(options.threads);
    imm::dim3::BuildOptions o;
    o.exact_volumes = options.exact_volumes;
    o.threads = options.threads;
    check_repair_folds(options.repair_folds);
    o.repair_folds = options.repair_folds;
    imm::dim3::BuildResult built = imm::dim3::build_complex(to_surface(surface), o);
    if (!built.report.ok()) throw_defects(surface.name, built.report);
    if (!built.folds.ok())
      throw Error(ErrorKind::NotImmersible,
                  imm::local_folds_message(surface.name, built.folds) +
                      (built.repair ? "\nnote: " + imm::dim3::fold_repair_note(*built.repair, options.repair_folds.value_or(0.0)) : ""));
    if (built.inversion) throw_inversion(surface.name, built.inversion->message);
    if (!built.complex) throw Error(ErrorKind::Internal, "build_complex returned no complex");
    return wrap(std::shared_ptr<const imm::dim3::Complex>(built.complex));
  });
}

// ---- searching ---------------------------------------------------------------------------------

Immersions<2> find_immersions(const Curves& curves, const SearchOptions& options) {
  return guarded([&] {
    Immersions<2> out;
    out.complex = wrap(built_curves(curves));
    auto data = std::make_shared<detail::ImmersionsData<2>>();
    data->name = curves.name;
    data->search = imm::find_immersions(out.complex.data_->complex->complex, search_options(options));
    if (data->search.status != ImmersionStatus::Immersible) throw_no_immersion(curves.name, data->search);
    for (const imm::Immersion& im : data->search.immersions) out.graphs.push_back(graph_of(im));
    out.complete = data->search.complete;
    out.data_ = std::move(data);
    return out;
  });
}

Immersions<3> find_immersions(const Surface& surface, const SearchOptions& options) {
  return guarded([&] {
    check_threads(options.threads);
    imm::dim3::ImmerseOptions o;
    o.build.exact_volumes = false;  // the search reads no volume (as the program)
    o.build.threads = options.threads;
    o.build.repair_folds = options.repair_folds;
    o.search = search_options(options);
    if (!options.helper_boxes) o.max_boxes = 0;
    auto data = std::make_shared<detail::ImmersionsData<3>>();
    data->name = surface.name;
    data->input = to_surface(surface);
    data->immersed = imm::dim3::immerse_surface(data->input, o);
    const imm::dim3::Immersed& im = data->immersed;
    Immersions<3> out;
    if (im.repair) out.notes.push_back(imm::dim3::fold_repair_note(*im.repair, options.repair_folds.value_or(0.0)));
    out.notes.insert(out.notes.end(), im.notes.begin(), im.notes.end());
    out.helper_boxes = im.helper_boxes.size();
    if (!im.build.folds.ok())
      throw Error(ErrorKind::NotImmersible,
                  imm::local_folds_message(surface.name, im.build.folds) +
                      (im.repair ? "\nnote: " + imm::dim3::fold_repair_note(*im.repair, options.repair_folds.value_or(0.0)) : ""));
    if (!im.build.report.ok()) throw_defects(surface.name, im.build.report, imm::dim3::helper_box_defect_note(im));
    if (im.build.inversion) throw_inversion(surface.name, im.build.inversion->message);
    if (!im.build.complex) throw Error(ErrorKind::Internal, "immerse_surface returned no complex");
    if (im.search.status != ImmersionStatus::Immersible)
      throw_no_immersion(surface.name, im.search, imm::dim3::helper_box_hint(im, options.helper_boxes));
    out.complex = wrap(std::shared_ptr<const imm::dim3::Complex>(im.build.complex));
    for (const imm::Immersion& g : im.search.immersions) out.graphs.push_back(graph_of(g));
    out.complete = im.search.complete;
    out.data_ = std::move(data);
    return out;
  });
}

// ---- meshing -------------------------------------------------------------------------------------

namespace {

template <int D>
void check_immersion_index(const Immersions<D>& found, const MeshOptions& options, const std::string& name) {
  if (!found.data_) throw Error(ErrorKind::Internal, "empty immersion::Immersions");
  if (options.immersion >= found.graphs.size()) {
    throw Error(ErrorKind::InvalidInput,
                imm::immersion_index_message(options.immersion, name, found.graphs.size(), found.complete,
                                              imm::kLibraryOptions));
  }
}

imm::MeshMethod method_of(MeshMethod m) {
  return m == MeshMethod::Csg ? imm::MeshMethod::Csg : imm::MeshMethod::Clip;
}

}  // namespace

SimplexMesh<2> mesh_immersion(const Immersions<2>& found, const MeshOptions& options) {
  return guarded([&] {
    const std::string name = found.data_ ? found.data_->name : std::string();
    check_immersion_index(found, options, name);
    check_resolution(options.resolution, std::numeric_limits<int>::max());
    // The 3D-only options are refused, not ignored, as the program refuses their flags for curves.
    const MeshOptions defaults;
    const std::pair<bool, const char*> only_3d[] = {
        {options.surface_resolution.has_value(), "surface_resolution"},
        {options.gap_resolution.has_value(), "gap_resolution"},
        {options.edge_length.has_value(), "edge_length"},
        {options.radius_edge != defaults.radius_edge, "radius_edge"},
        {options.min_dihedral != defaults.min_dihedral, "min_dihedral"}};
    for (const auto& [given, option] : only_3d)
      if (given) throw Error(ErrorKind::InvalidInput, std::string(option) + " is for 3D surfaces only");
    imm::dim2::MeshOptions o;
    if (options.resolution) o.resolution = *options.resolution;
    o.background_path = options.background;
    o.conforming = options.conforming;
    o.method = method_of(options.method);
    const imm::dim2::MeshResult m = imm::dim2::mesh_immersion(
        *found.complex.data_->complex, found.data_->search.immersions[options.immersion], o);
    if (!m.report.ok()) {
      throw Error(ErrorKind::InvalidInput, imm::cannot_mesh_message(name, m.report, kMaxDefectLines));
    }
    SimplexMesh<2> out;
    out.vertices.reserve(m.mesh.vertices.size());
    for (const imm::dim2::Point& p : m.mesh.vertices) out.vertices.push_back({p.x, p.y});
    out.elements = m.mesh.triangles;
    out.node = m.mesh.reference;
    for (const imm::dim2::EmbeddedVertex& e : m.embedding) {
      out.embedding_element.push_back(e.element);
      out.embedding_weights.push_back(e.weights);
    }
    return out;
  });
}

namespace {

/// The 3D conforming mesh (TetGen), with the program's option checks and messages.
SimplexMesh<3> mesh_conforming3(const Immersions<3>& found, const MeshOptions& options, int resolution,
                                const std::string& name) {
  if (options.background || options.method == MeshMethod::Csg)
    throw Error(ErrorKind::InvalidInput, "a conforming mesh takes no background and no CSG method");
  if (!(options.radius_edge >= 1.0 && std::isfinite(options.radius_edge)))
    throw Error(ErrorKind::InvalidInput, "radius_edge expects a number >= 1");
  if (!(options.min_dihedral >= 0.0 && options.min_dihedral <= 30.0))
    throw Error(ErrorKind::InvalidInput, "min_dihedral expects degrees in [0, 30]");
  const imm::dim3::Immersed& im = found.data_->immersed;
  imm::dim3::ConformingOptions c;
  c.edge_length = options.edge_length ? *options.edge_length
                                      : imm::dim3::conforming_edge_length(found.data_->input, resolution);
  if (!(c.edge_length > 0 && std::isfinite(c.edge_length)))
    throw Error(ErrorKind::InvalidInput, "edge_length must be a positive number (the input's box is flat or not finite)");
  c.radius_edge = options.radius_edge;
  c.min_dihedral = options.min_dihedral;
  imm::dim3::ConformingResult m = imm::dim3::mesh_conforming(*im.build.complex, im.search.immersions[options.immersion],
                                                             c, im.input_vertices, im.input_triangles);
  if (!m.report.ok())
    throw Error(ErrorKind::InvalidInput, imm::cannot_mesh_message(name, m.report, 20, "conformingly"));
  SimplexMesh<3> out;
  out.vertices = std::move(m.mesh.vertices);
  out.elements.assign(m.mesh.tets.begin(), m.mesh.tets.end());
  out.node = std::move(m.mesh.reference);
  for (const auto& e : m.embedding) {
    out.embedding_element.push_back(e.element);
    out.embedding_weights.push_back(e.weights);
  }
  return out;
}

}  // namespace

SimplexMesh<3> mesh_immersion(const Immersions<3>& found, const MeshOptions& options) {
  return guarded([&] {
    const std::string name = found.data_ ? found.data_->name : std::string();
    check_immersion_index(found, options, name);
    check_resolution(options.resolution, imm::dim3::kMaxGridResolution);
    check_threads(options.threads);
    imm::dim3::MeshOptions o;
    if (options.resolution) o.resolution = *options.resolution;
    o.background_path = options.background;
    o.method = method_of(options.method);
    o.threads = options.threads;
    if (options.gap_resolution && !options.surface_resolution)
      throw Error(ErrorKind::InvalidInput, "gap_resolution needs surface_resolution");
    if (options.surface_resolution) {
      if (options.background || options.conforming)
        throw Error(ErrorKind::InvalidInput, "surface_resolution (a graded background) excludes background and conforming");
      imm::dim3::GradedOptions graded;
      graded.far_resolution = options.resolution.value_or(8);
      graded.surface_resolution = *options.surface_resolution;
      graded.gap_resolution = options.gap_resolution.value_or(0);
      if (std::string error =
              imm::dim3::graded_order_error(graded, {"resolution", "surface_resolution", "gap_resolution"});
          !error.empty())
        throw Error(ErrorKind::InvalidInput, "graded background: " + error);
      o.graded = graded;
    }
    const imm::dim3::Immersed& im = found.data_->immersed;
    if (options.conforming) return mesh_conforming3(found, options, o.resolution, name);
    imm::dim3::MeshResult m = imm::dim3::mesh_immersion(
        *im.build.complex, im.search.immersions[options.immersion], o, im.input_vertices, im.input_triangles);
    if (!m.report.ok()) {
      throw Error(ErrorKind::InvalidInput, imm::cannot_mesh_message(name, m.report, 20));
    }
    SimplexMesh<3> out;
    out.vertices = std::move(m.mesh.vertices);
    out.elements.reserve(m.mesh.tets.size());
    for (const imm::dim3::Tet& t : m.mesh.tets) out.elements.push_back(t);
    out.node = std::move(m.mesh.reference);
    for (const imm::dim3::EmbeddedVertex3& e : m.embedding) {
      out.embedding_element.push_back(e.element);
      out.embedding_weights.push_back(e.weights);
    }
    out.input_shift = m.stats.input_shift;
    return out;
  });
}

// ---- writing -------------------------------------------------------------------------------------

namespace {

/// Writes atomically, creating missing parent directories as the program does.
void write_or_throw(const std::string& path, const std::string& content) {
  if (const imm::WriteStatus dir = imm::ensure_parent_directory(path); !dir.ok())
    throw Error(ErrorKind::Internal, dir.error);
  const imm::WriteStatus status = imm::write_file_atomic(path, content);
  if (!status.ok()) throw Error(ErrorKind::Internal, status.error);
}

}  // namespace

/// A mesh filled by the caller is checked before it is written: indices out of range were written
/// as they were (a corrupt file), and fewer nodes than elements read past the end.
template <int D>
void check_mesh(const SimplexMesh<D>& mesh, const std::string& path) {
  const std::size_t n = mesh.vertices.size();
  for (std::size_t v = 0; v < n; ++v)
    for (double x : mesh.vertices[v])
      if (!std::isfinite(x))
        throw Error(ErrorKind::InvalidInput, path + ": vertex " + std::to_string(v) + " has a non-finite coordinate");
  for (std::size_t e = 0; e < mesh.elements.size(); ++e)
    for (auto i : mesh.elements[e])
      if (i < 0 || static_cast<std::size_t>(i) >= n)
        throw Error(ErrorKind::InvalidInput, path + ": element " + std::to_string(e) + " refers to vertex " +
                                                 std::to_string(i) + ", but the mesh has " + std::to_string(n) + " vertices");
  if (mesh.node.size() != mesh.elements.size())
    throw Error(ErrorKind::InvalidInput, path + ": " + std::to_string(mesh.elements.size()) + " elements but " +
                                             std::to_string(mesh.node.size()) + " node references");
}

void write_mesh(const SimplexMesh<2>& mesh, const std::string& path) {
  guarded([&] {
    check_mesh(mesh, path);
    if (imm::text::lower_extension(path) != ".mesh")
      throw Error(ErrorKind::InvalidInput, path + ": a triangle mesh is written as .mesh");
    imm::dim2::TriangleMesh m;
    for (const auto& p : mesh.vertices) m.vertices.push_back({p[0], p[1]});
    m.triangles = mesh.elements;
    m.reference = mesh.node;
    write_or_throw(path, imm::dim2::format_medit_2d(m));
  });
}

void write_mesh(const SimplexMesh<3>& mesh, const std::string& path) {
  guarded([&] {
    check_mesh(mesh, path);
    imm::dim3::TetMesh m;
    m.vertices = mesh.vertices;
    m.tets.assign(mesh.elements.begin(), mesh.elements.end());
    m.reference = mesh.node;
    const std::string ext = imm::text::lower_extension(path);
    if (ext == ".mesh") return write_or_throw(path, imm::dim3::format_medit_3d(m));
    if (ext == ".vtu") return write_or_throw(path, imm::dim3::format_vtu(m));
    if (ext == ".veg") return write_or_throw(path, imm::dim3::format_veg(m));
    if (ext == ".msh") return write_or_throw(path, imm::dim3::format_gmsh(m));
    if (ext == ".node" || ext == ".ele") {
      const imm::dim3::TetGenTexts texts = imm::dim3::format_tetgen(m);
      const auto [node, ele] = imm::dim3::tetgen_paths(path);
      write_or_throw(node, texts.node);
      return write_or_throw(ele, texts.ele);
    }
    throw Error(ErrorKind::InvalidInput,
                path + ": a tet mesh is written as .mesh, .vtu, .veg, .msh or .node/.ele");
  });
}

}  // namespace immersion
