// Background triangulations for 2D meshing (paper §7: "arbitrary tet meshes can be used, as long
// as the volume enclosed by the input is a subset of the volume covered"):
//  - generated: a CGAL constrained Delaunay triangulation of the input's bounding box, enlarged
//    by 5% of its diagonal on every side, seeded with a triangular lattice of spacing
//    0.95 * diagonal / resolution and refined by CGAL's Delaunay mesher (Shewchuk-style
//    refinement with clusters, not Shewchuk's Triangle program) to shape bound 0.125 and edge
//    length <= diagonal / resolution;
//  - conforming (MeshOptions::conforming): the same with every exact cut segment inserted as a
//    constraint, so that no triangle is crossed by the input;
//  - read from a Medit .mesh (Dimension 2).
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>

#include "core/medit.h"
#include "core/text_io.h"
#include "core/union_find.h"
#include "dim2/cut_curve.h"
#include "dim2/kernel.h"
#include "dim2/mesh2_detail.h"

namespace imm::dim2 {

namespace {

using Epick = CGAL::Exact_predicates_inexact_constructions_kernel;

/// Epeck whose circumcenters are rounded to doubles. The conforming mesher must construct points
/// on the constraints exactly (midpoints and cluster splits of exact cut segments, which may end
/// at rational crossing points), but its interior Steiner points only need to lie near the
/// circumcenter. Rounding them keeps every interior vertex a double: exact circumcenters of
/// circumcenters would make the coordinates' bit length grow with every refinement generation.
struct ConformingTraits : public Kernel {
  struct Construct_circumcenter_2 {
    using result_type = Point_2;
    Point_2 operator()(const Point_2& p, const Point_2& q, const Point_2& r) const {
      const Point_2 c = Kernel().construct_circumcenter_2_object()(p, q, r);
      // The interval approximation is enough: any nearby point is a valid refinement point.
      return Point_2(CGAL::to_double(c.x()), CGAL::to_double(c.y()));
    }
    Point_2 operator()(const Point_2& p, const Point_2& q) const {
      return Kernel().construct_midpoint_2_object()(p, q);
    }
  };
  Construct_circumcenter_2 construct_circumcenter_2_object() const { return {}; }
};

template <class Traits>
struct MesherTypes {
  using Vb = CGAL::Triangulation_vertex_base_with_info_2<int, Traits>;
  using Fb = CGAL::Delaunay_mesh_face_base_2<Traits>;
  using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
  using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Traits, Tds, CGAL::Exact_intersections_tag>;
  using Criteria = CGAL::Delaunay_mesh_size_criteria_2<Cdt>;
};

struct Box {
  double xmin, ymin, xmax, ymax;
};

/// The input's bounding box enlarged by 5% of its diagonal on every side, with the facts the
/// range check of generate_background needs.
struct InputExtent {
  Box enlarged;
  double diagonal = 0.0;
  double largest = 0.0;  ///< largest absolute input coordinate
};

InputExtent input_extent(const Complex2& complex) {
  Box box{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
          -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (const Curve& curve : complex.curves.curves) {
    for (const Point& p : curve.vertices) {
      box.xmin = std::min(box.xmin, p.x);
      box.ymin = std::min(box.ymin, p.y);
      box.xmax = std::max(box.xmax, p.x);
      box.ymax = std::max(box.ymax, p.y);
    }
  }
  InputExtent extent;
  extent.diagonal = std::hypot(box.xmax - box.xmin, box.ymax - box.ymin);
  extent.largest = std::max({std::abs(box.xmin), std::abs(box.ymin), std::abs(box.xmax), std::abs(box.ymax)});
  const double margin = 0.05 * extent.diagonal;
  extent.enlarged = {box.xmin - margin, box.ymin - margin, box.xmax + margin, box.ymax + margin};
  return extent;
}

/// Inserts the box as constraints (so that the mesher splits its sides), seeds a triangular
/// lattice of spacing ~ size_bound, and refines. The lattice gives the mesher nearly nothing to do
/// away from constraints: refinement from the bare box, one circumcenter at a time, costs
/// super-linear time in CGAL's priority queues (14 s instead of ~2 s for 10^6 triangles).
/// @param max_vertices  0: refine until done; otherwise stop once the triangulation has more
///   vertices (checked every 1,024 steps) and @return false. Step by step is the same sequence of
///   insertions as CGAL's refine_mesh (one step of the edge level while it has work, else one of
///   the face level).
template <class Cdt, class Criteria>
bool insert_box_and_refine(Cdt& cdt, const Box& box, double size_bound, std::size_t max_vertices = 0) {
  using P = typename Cdt::Point;
  const double width = box.xmax - box.xmin, height = box.ymax - box.ymin;
  const double spacing = 0.95 * size_bound;
  std::vector<P> seeds;
  const auto nx = static_cast<long>(std::ceil(width / spacing));
  const auto ny = static_cast<long>(std::ceil(height / spacing));
  std::vector<P> corners;
  for (long i = 0; i < nx; ++i) {
    const double x = box.xmin + width * static_cast<double>(i) / static_cast<double>(nx);
    corners.emplace_back(x, box.ymin);
  }
  for (long j = 0; j < ny; ++j)
    corners.emplace_back(box.xmax, box.ymin + height * static_cast<double>(j) / static_cast<double>(ny));
  for (long i = nx; i > 0; --i)
    corners.emplace_back(box.xmin + width * static_cast<double>(i) / static_cast<double>(nx), box.ymax);
  for (long j = ny; j > 0; --j)
    corners.emplace_back(box.xmin, box.ymin + height * static_cast<double>(j) / static_cast<double>(ny));
  // The box sides, as constraints split at their seeds (points exactly on the sides).
  for (std::size_t k = 0; k < corners.size(); ++k)
    cdt.insert_constraint(corners[k], corners[(k + 1) % corners.size()]);
  const double row = spacing * std::sqrt(3.0) / 2.0;
  const double margin = 0.5 * spacing;
  for (long j = 1;; ++j) {
    const double y = box.ymin + row * static_cast<double>(j);
    if (y > box.ymax - margin) break;
    const double shift = (j % 2 == 0) ? 0.0 : 0.5 * spacing;
    for (long i = 1;; ++i) {
      const double x = box.xmin + shift + spacing * static_cast<double>(i) - 0.5 * spacing;
      if (x > box.xmax - margin) break;
      if (x < box.xmin + margin) continue;
      seeds.emplace_back(x, y);
    }
  }
  cdt.insert(seeds.begin(), seeds.end());
  if (max_vertices == 0) {
    CGAL::refine_Delaunay_mesh_2(cdt, Criteria(0.125, size_bound));
    return true;
  }
  CGAL::Delaunay_mesher_2<Cdt, Criteria> mesher(cdt, Criteria(0.125, size_bound));
  mesher.init();
  for (std::size_t step = 1; mesher.try_one_step_refine_mesh(); ++step)
    if (step % 1024 == 0 && cdt.number_of_vertices() > max_vertices) return false;
  return true;
}

/// Numbers the vertices and lists the finite faces (counter-clockwise in CGAL).
template <class Cdt, class ToPoint>
void extract(Cdt& cdt, detail::Background& out, ToPoint&& store_vertex) {
  int next = 0;
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) {
    v->info() = next++;
    store_vertex(v->point());
  }
  out.triangles.reserve(cdt.number_of_faces());
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
    out.triangles.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
}

/// The largest generated 2D background (see generate_background).
constexpr double kMaxBackgroundTriangles = 4e6;
/// A conforming mesh stops refining beyond this many vertices per seed-lattice triangle plus
/// kConformingExtraVertices (see generate_background).
constexpr std::size_t kConformingVerticesPerSeed = 20;
constexpr std::size_t kConformingExtraVertices = 20000;

detail::Background generate_background(const Complex2& complex, const MeshOptions& options,
                                       ValidationReport& report) {
  IMM_ASSERT(options.resolution >= 1, "mesh resolution must be at least 1");
  const InputExtent extent = input_extent(complex);
  // The generated background is a double-precision Delaunay mesh: its predicates are exact, but
  // the mesher's constructions (squared lengths, circumcentres) overflow or underflow far from
  // unit scale and CGAL then fails inside the mesher. Refuse such inputs with a clear message;
  // the exact steps (complex, search, clipping against a given --background) have no such limit.
  constexpr double kMaxCoordinate = 1e75;
  constexpr double kMinDiagonal = 1e-60;
  if (!(extent.largest <= kMaxCoordinate) || !(extent.diagonal >= kMinDiagonal)) {
    std::ostringstream msg;
    msg << "cannot generate a background mesh: the input's largest coordinate is " << extent.largest
        << " and its bounding-box diagonal " << extent.diagonal << "; the double-precision mesher "
        << "needs coordinates up to " << kMaxCoordinate << " and a diagonal of at least "
        << kMinDiagonal << " (scale the input, or pass --background)";
    report.add({DefectKind::OutOfRange, "mesh", msg.str(), {}, {}, {}});
    return {};
  }
  const Box& box = extent.enlarged;
  const double size_bound = extent.diagonal / options.resolution;
  // The mesher's size: the seed lattice alone has area / (sqrt(3)/4 (0.95 h)^2) triangles (about
  // 1.7 resolution^2 for a square input). Refused before any allocation above kMaxTriangles:
  // resolution 3,000 (15 million triangles) took 39 s and 3.2 GB, 10,000 ran out of memory.
  double seed_estimate = 0.0;  // triangles of the seed lattice
  {
    const double spacing = 0.95 * size_bound;
    const double area = (box.xmax - box.xmin) * (box.ymax - box.ymin);
    const double estimate = area / (std::sqrt(3.0) / 4.0 * spacing * spacing);
    seed_estimate = estimate;
    if (!(estimate <= kMaxBackgroundTriangles)) {
      std::ostringstream msg;
      msg << "resolution " << options.resolution << " would generate about "
          << static_cast<long long>(std::min(estimate, 1e18)) << " background triangles; at most "
          << static_cast<long long>(kMaxBackgroundTriangles) << " are generated (about resolution "
          << static_cast<long long>(options.resolution * std::sqrt(kMaxBackgroundTriangles / estimate))
          << " for this input; or pass --background)";
      report.add({DefectKind::OutOfRange, "mesh", msg.str(), {}, {}, {}});
      return {};
    }
  }
  detail::Background out;
  if (!options.conforming) {
    using Types = MesherTypes<Epick>;
    typename Types::Cdt cdt;
    insert_box_and_refine<typename Types::Cdt, typename Types::Criteria>(cdt, box, size_bound);
    extract(cdt, out, [&](const Epick::Point_2& p) { out.vertices.push_back({p.x(), p.y()}); });
    return out;
  }
  using Types = MesherTypes<ConformingTraits>;
  typename Types::Cdt cdt;
  IMM_ASSERT(complex.exact != nullptr, "complex without exact geometry");
  for (const CutSegment& s : complex.exact->segments) cdt.insert_constraint(s.source, s.target);
  // Refinement grades down to the input's smallest feature: two constraints 1e-12 apart along a
  // whole side (the thin gap a contact's perturbation leaves between touching curves, or a
  // near contact) would need ~1e12 triangles. Stop long before memory runs out and say why.
  const std::size_t cap = kConformingVerticesPerSeed * static_cast<std::size_t>(seed_estimate) + kConformingExtraVertices;
  if (!insert_box_and_refine<typename Types::Cdt, typename Types::Criteria>(cdt, box, size_bound, cap)) {
    std::ostringstream msg;
    msg << "the conforming mesh refines past " << cap << " vertices (resolution " << options.resolution
        << " asks for about " << static_cast<long long>(seed_estimate)
        << " triangles): the input has features far smaller than the mesh size, such as curves that "
           "touch exactly (the perturbation resolving the contacts leaves gaps of about 2^-40 of the "
           "scale) or nearly"
        << "; mesh on a background instead (without --conforming)";
    report.add({DefectKind::OutOfRange, "mesh", msg.str(), {}, {}, {}});
    return {};
  }
  extract(cdt, out, [&](const Point_2& p) {
    out.vertices.push_back(to_double(p));
    out.exact_vertices.push_back({to_rational(p.x()), to_rational(p.y())});
  });
  return out;
}

Defect make_defect(DefectKind kind, std::string message) {
  Defect d;
  d.kind = kind;
  d.stage = "read-background";
  d.message = std::move(message);
  return d;
}

/// Pieces of a read background (triangles joined across shared edges) that overlap: two meshes
/// in one file, an unglued output (its copies overlap by design) reused as a background.
/// Triangles on the same side of a shared edge (a fold) are refused where the edges are paired
/// (dim2/virtual_triangles.cpp); here, two pieces overlap iff a triangle of one and a triangle
/// of the other have intersecting interiors (the overlap is open), decided exactly for the pairs
/// whose boxes meet; pieces that only touch are fine. The first pair in (triangle, triangle)
/// order is reported. One piece (most files): nothing more than the pairing. NOT detected: one
/// piece overlapping itself away from its shared edges (a strip wound round onto itself, a
/// vertex star wound twice around).
void check_pieces(const TriangleMesh& mesh, ValidationReport& report) {
  const auto& triangles = mesh.triangles;
  struct EdgeRef {
    int a, b;  // a < b
    std::uint32_t triangle;
    auto operator<=>(const EdgeRef&) const = default;
  };
  std::vector<EdgeRef> edges;
  edges.reserve(3 * triangles.size());
  for (std::uint32_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int u = triangles[t][k], v = triangles[t][(k + 1) % 3];
      edges.push_back({std::min(u, v), std::max(u, v), t});
    }
  std::sort(edges.begin(), edges.end());
  UnionFind pieces(triangles.size());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j].a == edges[i].a && edges[j].b == edges[i].b) ++j;
    if (j - i > 2) return;  // an edge shared by more triangles: reported where edges are paired
    if (j - i == 2) pieces.unite(edges[i].triangle, edges[i + 1].triangle);
    i = j;
  }
  std::vector<std::uint32_t> piece(triangles.size());
  bool several = false;
  for (std::uint32_t t = 0; t < triangles.size(); ++t) {
    piece[t] = pieces.find(t);
    several = several || piece[t] != piece[0];
  }
  if (!several) return;
  const auto point = [&](int v) { return Epick::Point_2(mesh.vertices[v].x, mesh.vertices[v].y); };
  // Exact (Epick's predicates on the doubles): the triangles are counter-clockwise (read_medit_2d),
  // so an edge line of one with the other wholly on its right or on it separates them.
  const auto separated = [&](std::uint32_t t, std::uint32_t u) {
    for (int k = 0; k < 3; ++k) {
      bool all = true;
      for (int m = 0; m < 3 && all; ++m)
        all = CGAL::orientation(point(triangles[t][k]), point(triangles[t][(k + 1) % 3]), point(triangles[u][m])) !=
              CGAL::LEFT_TURN;
      if (all) return true;
    }
    return false;
  };
  // The pairs of different pieces whose boxes meet (CGAL's box intersection, as the 3D check),
  // tested exactly in (triangle, triangle) order: the first overlapping pair is reported.
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 2, std::uint32_t>;
  std::vector<Box> boxes;
  boxes.reserve(triangles.size());
  for (std::uint32_t t = 0; t < triangles.size(); ++t) {
    CGAL::Bbox_2 box;
    for (int k = 0; k < 3; ++k) {
      const Point& p = mesh.vertices[triangles[t][k]];
      box += CGAL::Bbox_2(p.x, p.y, p.x, p.y);
    }
    boxes.emplace_back(box, t);
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& a, const Box& b) {
    if (piece[a.info()] != piece[b.info()]) pairs.emplace_back(std::min(a.info(), b.info()), std::max(a.info(), b.info()));
  });
  std::sort(pairs.begin(), pairs.end());
  std::optional<std::pair<std::uint32_t, std::uint32_t>> first;
  for (const auto& [t, u] : pairs)
    if (!separated(t, u) && !separated(u, t)) {
      first = std::pair(t, u);
      break;
    }
  if (!first) return;
  const auto [t, u] = *first;
  const Point& p = mesh.vertices[triangles[t][0]];
  Defect d = make_defect(DefectKind::InconsistentOrientation,
                         "background triangles overlap: triangles " + std::to_string(t) + " and " + std::to_string(u) +
                             ", in different pieces of the background (triangles joined across edges), overlap near " +
                             format_point(p) +
                             ": the background would be meshed twice there (an unglued output has overlapping copies "
                             "by design and cannot be a background: pass the glued mesh, or none)");
  d.facets = {static_cast<long>(t), static_cast<long>(u)};
  d.points = {{p.x, p.y}};
  report.add(std::move(d));
}

}  // namespace

TriangleMesh read_medit_2d(const std::string& path, ValidationReport& report) {
  TriangleMesh mesh;
  auto fail = [&](const std::string& why) {
    report.add(make_defect(DefectKind::Unreadable, "background mesh: " + why));
    return TriangleMesh{};
  };
  std::string error;
  const std::optional<std::string> text = text::read_file(path, error);
  if (!text) return fail(error);
  MeditMesh<2> medit;
  if (error = parse_medit<2>(*text, path, medit); !error.empty()) return fail(error);
  long far = 0;  // vertices beyond the range (the first 10 are listed)
  for (std::size_t i = 0; i < medit.vertices.size(); ++i) {
    const auto [x, y] = medit.vertices[i];
    mesh.vertices.push_back({x, y});
    if (!std::isfinite(x) || !std::isfinite(y)) {
      Defect d = make_defect(DefectKind::NonFinite,
                             "background vertex " + std::to_string(i) + " is not finite");
      d.vertices = {static_cast<long>(i)};
      report.add(std::move(d));
    } else if (!(std::abs(x) <= kMaxCoordinate2 && std::abs(y) <= kMaxCoordinate2) && ++far <= 10) {
      Defect d = make_defect(DefectKind::OutOfRange, "background vertex " + std::to_string(i) + " " +
                                                         format_point(mesh.vertices.back()) +
                                                         " lies beyond the 2D coordinate range |x|, |y| <= 1e75");
      d.vertices = {static_cast<long>(i)};
      report.add(std::move(d));
    }
  }
  const auto n = static_cast<long long>(mesh.vertices.size());
  for (std::size_t i = 0; i < medit.elements.size(); ++i) {
    std::array<int, 3> tri{};
    for (int k = 0; k < 3; ++k) {
      const long long v = medit.elements[i][k];
      if (v < 0 || v >= n) {
        return fail(text::at(path, medit.element_line[i]) + "triangle " + std::to_string(i + 1) +
                    " has vertex index " + std::to_string(v + 1) + " out of 1.." +
                    std::to_string(n));
      }
      tri[k] = static_cast<int>(v);
    }
    mesh.triangles.push_back(tri);
    mesh.reference.push_back(medit.reference[i]);
  }
  if (mesh.triangles.empty()) {
    report.add(make_defect(DefectKind::Empty, "background mesh '" + path + "' has no triangles"));
    return mesh;
  }
  if (!report.ok()) return mesh;
  // Orientation by the exact predicate: clockwise triangles are turned, flat ones are defects.
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    auto& t = mesh.triangles[i];
    const auto point = [&](int k) {
      return Epick::Point_2(mesh.vertices[t[k]].x, mesh.vertices[t[k]].y);
    };
    const CGAL::Orientation o = CGAL::orientation(point(0), point(1), point(2));
    if (o == CGAL::COLLINEAR) {
      Defect d = make_defect(DefectKind::DegenerateFacet,
                             "background triangle " + std::to_string(i) + " has zero area");
      d.facets = {static_cast<long>(i)};
      d.vertices = {t[0], t[1], t[2]};
      report.add(std::move(d));
    } else if (o == CGAL::CLOCKWISE) {
      std::swap(t[1], t[2]);
    }
  }
  return mesh;
}

std::string format_medit_2d(const TriangleMesh& mesh) {
  std::vector<std::array<double, 2>> vertices;
  vertices.reserve(mesh.vertices.size());
  for (const Point& p : mesh.vertices) vertices.push_back({p.x, p.y});
  return format_medit<2>(vertices, mesh.triangles, mesh.reference);
}

namespace detail {

Background make_background(const Complex2& complex, const MeshOptions& options,
                           ValidationReport& report) {
  if (options.background_path) {
    TriangleMesh mesh = read_medit_2d(*options.background_path, report);
    Background out;
    if (!report.ok()) return out;
    check_pieces(mesh, report);
    if (!report.ok()) return out;
    out.vertices = std::move(mesh.vertices);
    out.triangles = std::move(mesh.triangles);
    return out;
  }
  if (options.progress) options.progress("meshing: background triangulation");
  return generate_background(complex, options, report);
}

}  // namespace detail

}  // namespace imm::dim2
