// Virtual tets by exact CSG: the baseline the paper compares its clipping with (Li & Barbič 2018
// §7, after Sifakis et al. 2007). It fills the same detail::LocalRegions as dim3/virtual_tets.cpp
// and exists to check it (tests/dim3/csg_test.cpp) and to time the two against each other.
//
// For each background tet T whose box meets cut triangles:
//  1. every cut triangle x that meets the open tet gets a point p_x strictly inside x ∩ T (the
//     mean of the vertices of that convex polygon: x's corners in T, x's edges through T's faces,
//     T's edges through x, all exact Epeck constructions);
//  2. N = Nef_polyhedron_3(closed T) minus the union of those triangles as 2D Nef polyhedra. The
//     volumes of N other than the outer volume are exactly the connected components of
//     (open T minus the input): the local regions of T. For speed the triangles go in as a few
//     open surfaces (one Nef construction each, see group_triangles) united first and subtracted
//     once: booleans dominate the cost, and this takes about 4x fewer than one per triangle;
//  3. N.locate(p_x) is a halffacet of N; a Nef halffacet's incident volume lies on the positive
//     side of its plane, so the volumes on x's inner (negative) and outer side follow from the
//     sign of the dot product of the two normals. They give the regions (patch sides), fusions,
//     embedded pieces and input-vertex locations;
//  4. the halffacets of N between a local region and the outer volume are the parts of T's
//     faces; each is stored projected to a coordinate plane with a point strictly inside it.
// Across a shared face, a part of one tet and a part of the other overlap with positive area iff
// the interior point of one lies strictly inside the other (both tets cut the face by the same
// traces, so the parts coincide; the test is made both ways). Regions of local regions without
// an input facet follow by union-find over the adjacencies, as in dim3/virtual_tets.cpp; a
// component without any is located by an exact segment to a cut triangle.
//
// Tets run on threads in blocks, merged in tet order as in dim3/virtual_tets.cpp, so both methods
// are timed on the same number of threads and the result does not depend on it.
//
// Nothing here is rounded except the barycentric weights of the output; no epsilon is used.
// Non-generic contacts (an input vertex on a tet face, an input edge meeting a tet edge, a tet
// vertex or edge on the input) are detected exactly and reported as Touching defects.
#include <CGAL/Box_intersection_d/Box_with_info_d.h>
#include <CGAL/Nef_polyhedron_3.h>
#include <CGAL/Polygon_2_algorithms.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <chrono>
#include <exception>
#include <map>
#include <set>
#include <optional>
#include <unordered_map>

#include "core/parallel.h"
#include "core/union_find.h"
#include "core/unglue.h"
#include "dim3/cut_mesh.h"
#include "dim3/mesh3_detail.h"

namespace imm::dim3::detail {

namespace {

using Point = EK::Point_3;
using Point2 = EK::Point_2;
using Nef = CGAL::Nef_polyhedron_3<EK>;
using Mesh = CGAL::Surface_mesh<Point>;
constexpr std::uint32_t kNone = LocalRegions::kNone;

/// Face f of a tet is opposite vertex f; vertex f lies on the positive side of (a, b, c).
constexpr int kFace[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};
constexpr int kEdge[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

/// One part of a tet face: a halffacet of the tet's Nef polyhedron between a local region and
/// the outside, projected to the coordinate plane that drops `axis`.
struct FacePart {
  std::uint32_t lr = 0;                   ///< local region (index within the tet)
  std::vector<std::vector<Point2>> cycles;  ///< outer cycle first, then holes; empty: whole face
  Point2 inside;                          ///< strictly inside the part
};

/// Removes the vertices where a cycle goes straight on (Nef cycles keep them where another
/// feature ends on the edge); the cycle bounds the same set.
void drop_straight_vertices(std::vector<Point2>& c) {
  for (bool changed = true; changed && c.size() > 3;) {
    changed = false;
    for (std::size_t i = 0; i < c.size() && c.size() > 3; ++i) {
      const std::size_t n = c.size();
      if (CGAL::collinear(c[(i + n - 1) % n], c[i], c[(i + 1) % n])) {
        c.erase(c.begin() + static_cast<std::ptrdiff_t>(i));
        changed = true;
      }
    }
  }
}

/// A point strictly inside a polygon with holes (O'Rourke's diagonal argument): the
/// lexicographically smallest vertex v is convex, with neighbours a, b; if no other vertex lies
/// in the closed triangle (a, v, b), its centroid is inside; otherwise the vertex q in it farthest
/// from line ab sees v along an interior diagonal, and the midpoint of v and q is inside. Moves
/// the cycle holding v (the outer one) to the front.
Point2 interior_point(std::vector<std::vector<Point2>>& cycles) {
  std::size_t ci = 0, vi = 0;
  for (std::size_t c = 0; c < cycles.size(); ++c)
    for (std::size_t i = 0; i < cycles[c].size(); ++i)
      if (CGAL::compare_xy(cycles[c][i], cycles[ci][vi]) == CGAL::SMALLER) {
        ci = c;
        vi = i;
      }
  std::swap(cycles[0], cycles[ci]);
  const std::vector<Point2>& outer = cycles[0];
  const std::size_t n = outer.size();
  const Point2& a = outer[(vi + n - 1) % n];
  const Point2& v = outer[vi];
  const Point2& b = outer[(vi + 1) % n];
  const EK::Triangle_2 wedge(a, v, b);
  IMM_ASSERT(!wedge.is_degenerate(), "a straight vertex left in a face part");
  std::optional<Point2> best;
  EK::FT best_area(0);
  for (std::size_t c = 0; c < cycles.size(); ++c)
    for (std::size_t i = 0; i < cycles[c].size(); ++i) {
      if (c == 0 && (i == vi || i == (vi + 1) % n || i == (vi + n - 1) % n)) continue;
      const Point2& q = cycles[c][i];
      if (wedge.bounded_side(q) == CGAL::ON_UNBOUNDED_SIDE) continue;
      const EK::FT area = CGAL::abs(CGAL::area(a, b, q));
      if (!best || area > best_area) {
        best = q;
        best_area = area;
      }
    }
  if (!best) return CGAL::centroid(a, v, b);
  return CGAL::midpoint(v, *best);
}

/// +1 strictly inside the part, -1 strictly outside, 0 on its boundary.
int part_side(const FacePart& part, const Point2& p) {
  const auto side = [&](const std::vector<Point2>& c) { return CGAL::bounded_side_2(c.begin(), c.end(), p, EK()); };
  const CGAL::Bounded_side outer = side(part.cycles[0]);
  if (outer != CGAL::ON_BOUNDED_SIDE) return outer == CGAL::ON_BOUNDARY ? 0 : -1;
  for (std::size_t h = 1; h < part.cycles.size(); ++h) {
    const CGAL::Bounded_side s = side(part.cycles[h]);
    if (s == CGAL::ON_BOUNDARY) return 0;
    if (s == CGAL::ON_BOUNDED_SIDE) return -1;
  }
  return 1;
}

/// What one tet contributes, with its local regions numbered from 0; merged in tet order.
struct TetOut {
  std::vector<RegionId> regions;
  std::vector<LocalRegions::Fusion> fusions;
  std::vector<LocalRegions::Embedded> embedded;
  std::vector<std::pair<std::uint32_t, LocalRegions::VertexLocation>> vertices;  ///< input vertex, location
  std::vector<std::uint32_t> met;                ///< cut triangles that meet the open tet
  std::array<std::vector<FacePart>, 4> parts;    ///< per face of the tet
  std::optional<Defect> touching;                ///< a non-generic contact (the tet is then incomplete)
  std::exception_ptr error;                      ///< thrown while processing the tet; rethrown in tet order
  /// CPU seconds in the tet, set only when cut triangles meet it (all of its work is then exact);
  /// they include seconds_booleans.
  double seconds = 0.0;
  double seconds_booleans = 0.0;                 ///< CPU seconds in Nef constructions and booleans
};

class CsgTets {
 public:
  CsgTets(const Complex& complex, const TetMesh& background, bool record, unsigned threads, const LogCallback& progress,
          ValidationReport& report, bool& non_generic)
      : c_(complex), m_(*complex.exact), bg_(background), record_(record), threads_(threads), progress_(progress),
        report_(report), non_generic_(non_generic) {}

  LocalRegions run() {
    non_generic_ = false;
    points_.reserve(bg_.vertices.size());
    for (const Point3& p : bg_.vertices) points_.emplace_back(p[0], p[1], p[2]);
    find_candidates();
    out_.vertices.resize(c_.surface.vertex_count());
    out_.first.reserve(bg_.tets.size() + 1);
    parts_.resize(4 * bg_.tets.size());
    triangle_met_.assign(m_.triangles.size(), 0);
    std::vector<std::size_t> cand_first(bg_.tets.size() + 1, 0);
    for (const auto& c : candidates_) ++cand_first[c.first + 1];
    for (std::size_t t = 0; t < bg_.tets.size(); ++t) cand_first[t + 1] += cand_first[t];
    // Tets are independent: blocks of them run on the threads (one tet at a time: a cut tet costs
    // milliseconds) and are merged in tet order, so the result does not depend on the thread count.
    constexpr std::size_t kBlock = 128;
    std::vector<TetOut> block(kBlock);
    const auto start = std::chrono::steady_clock::now();
    auto last_report = start;
    for (std::size_t first = 0; first < bg_.tets.size(); first += kBlock) {
      const std::size_t count = std::min(kBlock, bg_.tets.size() - first);
      parallel_for(
          threads_, count,
          [&](std::size_t i, unsigned) {
            const auto t = static_cast<std::uint32_t>(first + i);
            block[i] = TetOut();
            try {
              const double tet_start = thread_cpu_seconds();
              process_tet(t, cand_first[t], cand_first[t + 1], block[i]);
              if (!block[i].met.empty()) block[i].seconds = thread_cpu_seconds() - tet_start;
            } catch (...) {
              block[i].error = std::current_exception();  // rethrown by merge, so the first tet's wins
            }
          },
          /*grain=*/1);
      for (std::size_t i = 0; i < count; ++i) {
        merge(static_cast<std::uint32_t>(first + i), block[i]);
        if (non_generic_) return std::move(out_);
      }
      const auto now = std::chrono::steady_clock::now();
      if (progress_ && now - last_report > std::chrono::seconds(5)) {
        last_report = now;
        progress_("CSG booleans: " + std::to_string(first + count) + " of " + std::to_string(bg_.tets.size()) +
                  " tets (" + std::to_string(out_.cut_elements) + " cut) after " +
                  std::to_string(std::chrono::duration_cast<std::chrono::seconds>(now - start).count()) + " s");
      }
    }
    out_.finish();
    connect_faces();
    if (!report_.ok()) return std::move(out_);
    resolve_regions();
    check_coverage();
    return std::move(out_);
  }

 private:
  [[nodiscard]] const Point& corner(std::uint32_t x, int k) const {
    return m_.points[m_.vertex_point[m_.triangles[x][k]]];
  }
  [[nodiscard]] const Point& tet_point(std::uint32_t t, int k) const {
    return points_[static_cast<std::size_t>(bg_.tets[t][k])];
  }
  [[nodiscard]] PatchId patch(std::uint32_t x) const { return c_.cut_triangle_patch[x]; }
  [[nodiscard]] RegionId side_region(std::uint32_t x, bool inner) const {
    const PatchSides& s = c_.complex.sides(patch(x));
    return inner ? s.negative : s.positive;
  }

  /// (tet, cut triangle) pairs with overlapping boxes (CGAL box_intersection_d), sorted.
  void find_candidates() {
    using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::uint32_t>;
    std::vector<Box> tets, triangles;
    tets.reserve(bg_.tets.size());
    for (std::uint32_t t = 0; t < bg_.tets.size(); ++t) {
      CGAL::Bbox_3 b;
      for (int k = 0; k < 4; ++k) b += tet_point(t, k).bbox();
      tets.emplace_back(b, t);
    }
    triangles.reserve(m_.triangles.size());
    for (std::uint32_t x = 0; x < m_.triangles.size(); ++x)
      triangles.emplace_back(corner(x, 0).bbox() + corner(x, 1).bbox() + corner(x, 2).bbox(), x);
    CGAL::box_intersection_d(tets.begin(), tets.end(), triangles.begin(), triangles.end(),
                             [&](const Box& t, const Box& x) { candidates_.emplace_back(t.info(), x.info()); });
    std::sort(candidates_.begin(), candidates_.end());
    out_.candidate_pairs = candidates_.size();
  }

  /// Records, once per tet, a non-generic contact of tet t with cut triangle x at `where`.
  void touching(TetOut& out, std::uint32_t t, std::uint32_t x, const Point& where, const std::string& what) const {
    if (out.touching) return;
    const Point3 p{CGAL::to_double(where.x()), CGAL::to_double(where.y()), CGAL::to_double(where.z())};
    Defect d;
    d.kind = DefectKind::Touching;
    d.stage = "mesh";
    d.message = "background tet " + std::to_string(t) + " meets the input non-generically at " + format_point(p) +
                ": " + what + " (input triangle " + std::to_string(m_.triangle_source[x]) +
                "); move or perturb the background mesh";
    d.facets = {static_cast<long>(m_.triangle_source[x])};
    d.points = {{p[0], p[1], p[2]}};
    out.touching = std::move(d);
  }

  /// A point strictly inside (cut triangle x) ∩ (open tet t), or nullopt when they do not meet;
  /// a non-generic contact is recorded in `out` (and returns nullopt).
  std::optional<Point> section_point(TetOut& out, std::uint32_t t, std::uint32_t x) const {
    std::vector<Point> vertices;
    const auto add = [&](const Point& p, const char* what) {
      if (std::find(vertices.begin(), vertices.end(), p) != vertices.end()) {
        touching(out, t, x, p, what);
        return false;
      }
      vertices.push_back(p);
      return true;
    };
    for (int k = 0; k < 3; ++k) {
      int inside = 0, on = 0;
      for (int f = 0; f < 4; ++f) {
        const CGAL::Orientation s =
            CGAL::orientation(tet_point(t, kFace[f][0]), tet_point(t, kFace[f][1]), tet_point(t, kFace[f][2]), corner(x, k));
        inside += s == CGAL::POSITIVE;
        on += s == CGAL::ZERO;
      }
      if (inside + on == 4 && on > 0) {
        touching(out, t, x, corner(x, k), "a vertex of the input lies on the boundary of the tet");
        return std::nullopt;
      }
      if (inside == 4 && !add(corner(x, k), "")) return std::nullopt;
    }
    for (int k = 0; k < 3; ++k) {
      const EK::Segment_3 edge(corner(x, k), corner(x, (k + 1) % 3));
      for (int f = 0; f < 4; ++f) {
        const EK::Triangle_3 face(tet_point(t, kFace[f][0]), tet_point(t, kFace[f][1]), tet_point(t, kFace[f][2]));
        const auto hit = CGAL::intersection(edge, face);
        if (!hit) continue;
        if (const Point* p = boost::get<Point>(&*hit)) {
          if (!add(*p, "an input edge meets an edge of the tet")) return std::nullopt;
        } else {
          touching(out, t, x, edge.source(), "an input edge lies in a face of the tet");
          return std::nullopt;
        }
      }
    }
    const EK::Triangle_3 triangle(corner(x, 0), corner(x, 1), corner(x, 2));
    for (const auto& e : kEdge) {
      const EK::Segment_3 edge(tet_point(t, e[0]), tet_point(t, e[1]));
      const auto hit = CGAL::intersection(edge, triangle);
      if (!hit) continue;
      if (const Point* p = boost::get<Point>(&*hit)) {
        if (!add(*p, "an edge of the tet meets the input at an edge or a vertex")) return std::nullopt;
      } else {
        touching(out, t, x, edge.source(), "an edge of the tet lies in the input");
        return std::nullopt;
      }
    }
    if (vertices.empty()) return std::nullopt;
    if (vertices.size() < 3) {
      touching(out, t, x, vertices.front(), "the input touches the tet");
      return std::nullopt;
    }
    EK::FT sx(0), sy(0), sz(0);
    for (const Point& p : vertices) {
      sx += p.x();
      sy += p.y();
      sz += p.z();
    }
    const EK::FT n(static_cast<int>(vertices.size()));
    return Point(sx / n, sy / n, sz / n);
  }

  /// Cut triangles gathered into open surfaces, each a 2D Nef polyhedron built at once: one
  /// boolean per group instead of one per triangle. A group is a Surface_mesh over sheet vertices;
  /// a triangle joins the first group where it keeps the mesh manifold and where none of its
  /// geometric points already stands for another sheet (two sheets crossing must not share a
  /// group: their copies of a point would be two Nef vertices at one place).
  struct TriangleGroup {
    Mesh mesh;
    std::unordered_map<std::uint32_t, Mesh::Vertex_index> vertex;  ///< sheet vertex -> mesh vertex
    std::unordered_map<std::uint32_t, std::uint32_t> sheet_vertex;  ///< geometric point -> sheet vertex
  };
  std::vector<TriangleGroup> group_triangles(const std::vector<std::pair<std::uint32_t, Point>>& met) const {
    std::vector<TriangleGroup> groups;
    for (const auto& [x, p] : met) {
      const Triangle& tri = m_.triangles[x];
      bool placed = false;
      for (std::size_t g = 0; g <= groups.size() && !placed; ++g) {
        if (g == groups.size()) groups.emplace_back();
        TriangleGroup& group = groups[g];
        bool conflict = false;
        for (int k = 0; k < 3 && !conflict; ++k) {
          const auto it = group.sheet_vertex.find(m_.vertex_point[tri[k]]);
          conflict = it != group.sheet_vertex.end() && it->second != tri[k];
        }
        if (conflict) continue;
        // Every vertex already in the mesh must get the new face next to one of its faces (an
        // edge in common): a vertex with two separate fans crashes the Nef constructor.
        std::array<std::optional<Mesh::Vertex_index>, 3> old;
        for (int k = 0; k < 3; ++k)
          if (const auto it = group.vertex.find(tri[k]); it != group.vertex.end()) old[k] = it->second;
        for (int k = 0; k < 3 && !conflict; ++k) {
          if (!old[k]) continue;
          const auto joined = [&](int j) {
            return old[j] && (group.mesh.halfedge(*old[k], *old[j]) != Mesh::null_halfedge() ||
                              group.mesh.halfedge(*old[j], *old[k]) != Mesh::null_halfedge());
          };
          conflict = !joined((k + 1) % 3) && !joined((k + 2) % 3);
        }
        if (conflict) continue;
        std::array<Mesh::Vertex_index, 3> v;
        std::vector<std::uint32_t> added;
        for (int k = 0; k < 3; ++k) {
          if (old[k]) {
            v[k] = *old[k];
          } else {
            v[k] = group.mesh.add_vertex(corner(x, k));
            added.push_back(tri[k]);
          }
        }
        if (group.mesh.add_face(v[0], v[1], v[2]) == Mesh::null_face()) {
          for (int k = 0; k < 3; ++k)
            if (std::find(added.begin(), added.end(), tri[k]) != added.end()) group.mesh.remove_vertex(v[k]);
          continue;
        }
        for (int k = 0; k < 3; ++k) {
          group.vertex.emplace(tri[k], v[k]);
          group.sheet_vertex.emplace(m_.vertex_point[tri[k]], tri[k]);
        }
        placed = true;
      }
      IMM_ASSERT(placed, "a cut triangle fits no group");
    }
    return groups;
  }

  /// The coordinate dropped to project face `key` (the largest normal component; the same for
  /// both tets of the face).
  [[nodiscard]] int face_axis(const std::array<int, 3>& key) const {
    const EK::Vector_3 n = CGAL::cross_product(points_[static_cast<std::size_t>(key[1])] - points_[static_cast<std::size_t>(key[0])],
                                               points_[static_cast<std::size_t>(key[2])] - points_[static_cast<std::size_t>(key[0])]);
    int axis = 0;
    double best = -1.0;
    for (int d = 0; d < 3; ++d) {
      const double v = std::abs(CGAL::to_double(n[d]));
      if (v > best) {
        best = v;
        axis = d;
      }
    }
    return axis;
  }
  [[nodiscard]] std::array<int, 3> face_key(std::uint32_t t, int f) const {
    std::array<int, 3> key = {bg_.tets[t][kFace[f][0]], bg_.tets[t][kFace[f][1]], bg_.tets[t][kFace[f][2]]};
    std::sort(key.begin(), key.end());
    return key;
  }

  /// The local regions of tet t, with candidate cut triangles candidates_[begin, end), into `out`.
  void process_tet(std::uint32_t t, std::size_t begin, std::size_t end, TetOut& out) const {
    const auto single = [&] {
      out.regions.emplace_back();
      for (std::vector<FacePart>& parts : out.parts) parts.push_back(FacePart{});
    };
    std::vector<std::pair<std::uint32_t, Point>> met;  // (cut triangle, point inside it in the tet)
    for (std::size_t c = begin; c < end; ++c) {
      const std::uint32_t x = candidates_[c].second;
      const std::optional<Point> p = section_point(out, t, x);
      if (out.touching) return;
      if (p) met.emplace_back(x, *p);
    }
    if (met.empty()) {
      single();
      return;
    }

    // The CSG: the closed tet minus every triangle that meets it.
    const double booleans_start = thread_cpu_seconds();
    Mesh tet;
    std::array<Mesh::Vertex_index, 4> v;
    for (int k = 0; k < 4; ++k) v[k] = tet.add_vertex(tet_point(t, k));
    for (const auto& f : kFace) tet.add_face(v[f[0]], v[f[2]], v[f[1]]);  // outward
    Nef nef(tet);
    {
      std::optional<Nef> cut;
      for (TriangleGroup& group : group_triangles(met)) {
        group.mesh.collect_garbage();
        if (cut) *cut += Nef(group.mesh); else cut.emplace(group.mesh);
      }
      nef -= *cut;
    }
    out.seconds_booleans = thread_cpu_seconds() - booleans_start;

    // Local regions: the bounded volumes.
    std::unordered_map<const void*, std::uint32_t> lr_of;
    for (auto vol = nef.volumes_begin(); vol != nef.volumes_end(); ++vol) {
      if (!vol->mark()) continue;
      lr_of.emplace(&*vol, static_cast<std::uint32_t>(lr_of.size()));
    }
    IMM_ASSERT(!lr_of.empty(), "a cut tet without a bounded volume");
    const auto lr = [&](Nef::Volume_const_handle vol) {
      const auto it = lr_of.find(&*vol);
      IMM_ASSERT(it != lr_of.end(), "a cut triangle facet next to the outside of its tet");
      return it->second;
    };
    std::vector<RegionId> regions(lr_of.size());
    std::vector<LocalRegions::Fusion> fusions;
    for (const auto& [x, p] : met) {
      out.met.push_back(x);
      Nef::Halffacet_const_handle facet;
      const bool on_facet = CGAL::assign(facet, nef.locate(p));
      IMM_ASSERT(on_facet, "a point inside a cut triangle is not on a facet");
      const EK::Vector_3 normal =
          CGAL::cross_product(corner(x, 1) - corner(x, 0), corner(x, 2) - corner(x, 0));
      // The incident volume of a Nef halffacet lies on the positive side of its plane.
      const bool along = CGAL::is_positive(facet->plane().orthogonal_vector() * normal);
      const std::uint32_t outer = lr(along ? facet->incident_volume() : facet->twin()->incident_volume());
      const std::uint32_t inner = lr(along ? facet->twin()->incident_volume() : facet->incident_volume());
      LocalRegions::set_region(regions, outer, side_region(x, false));
      LocalRegions::set_region(regions, inner, side_region(x, true));
      if (inner != outer) fusions.push_back({inner, outer, patch(x)});
      if (record_) {
        out.embedded.push_back({inner, x, true});
        out.embedded.push_back({outer, x, false});
      }
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t point = m_.vertex_point[m_.triangles[x][k]];
        if (point >= c_.surface.vertex_count() ||
            std::any_of(out.vertices.begin(), out.vertices.end(), [&](const auto& v) { return v.first == point; }))
          continue;
        bool inside = true;
        for (int f = 0; f < 4 && inside; ++f)
          inside = CGAL::orientation(tet_point(t, kFace[f][0]), tet_point(t, kFace[f][1]), tet_point(t, kFace[f][2]),
                                     corner(x, k)) == CGAL::POSITIVE;
        if (!inside) continue;
        const Point3& q = c_.surface.vertices[point];
        out.vertices.emplace_back(point, LocalRegions::VertexLocation{inner, patch(x), tet_barycentric(bg_, t, q)});
      }
    }
    out.regions = regions;
    LocalRegions::normalise(fusions);
    out.fusions = std::move(fusions);

    // Face parts: halffacets from a local region to the outside.
    std::array<int, 4> axis{};
    for (int f = 0; f < 4; ++f) axis[f] = face_axis(face_key(t, f));
    for (auto h = nef.halffacets_begin(); h != nef.halffacets_end(); ++h) {
      if (!h->incident_volume()->mark() || h->twin()->incident_volume()->mark()) continue;
      std::vector<std::vector<Point>> cycles;
      for (auto fc = h->facet_cycles_begin(); fc != h->facet_cycles_end(); ++fc) {
        Nef::SHalfedge_const_handle se(fc);
        IMM_ASSERT(se != Nef::SHalfedge_const_handle(), "an isolated loop on a tet face");
        Nef::SHalfedge_around_facet_const_circulator it(se), stop(it);
        cycles.emplace_back();
        CGAL_For_all(it, stop) cycles.back().push_back(it->source()->center_vertex()->point());
      }
      int face = -1;
      for (int f = 0; f < 4 && face < 0; ++f) {
        bool on = true;
        for (const Point& p : cycles.front())
          on = on && CGAL::coplanar(tet_point(t, kFace[f][0]), tet_point(t, kFace[f][1]), tet_point(t, kFace[f][2]), p);
        if (on) face = f;
      }
      IMM_ASSERT(face >= 0, "a tet boundary facet on no face of the tet");
      IMM_ASSERT(h->plane().oriented_side(tet_point(t, face)) == CGAL::ON_POSITIVE_SIDE,
                 "Nef halffacet orientation convention changed");
      FacePart part;
      part.lr = lr(h->incident_volume());
      const int a = (axis[face] + 1) % 3, b = (axis[face] + 2) % 3;
      for (const auto& cycle : cycles) {
        part.cycles.emplace_back();
        for (const Point& p : cycle) part.cycles.back().emplace_back(p[a], p[b]);
        drop_straight_vertices(part.cycles.back());
      }
      part.inside = interior_point(part.cycles);
      out.parts[static_cast<std::size_t>(face)].push_back(std::move(part));
    }
    for (const std::vector<FacePart>& parts : out.parts) IMM_ASSERT(!parts.empty(), "a tet face without parts");
  }

  /// Appends tet t's result (numbered from out_.region.size()); a non-generic contact is reported
  /// instead and stops the run.
  void merge(std::uint32_t t, TetOut& tet) {
    if (tet.touching) {
      report_.add(std::move(*tet.touching));
      non_generic_ = true;
      return;
    }
    if (tet.error) std::rethrow_exception(tet.error);
    const std::uint32_t base = out_.append_element(t, tet.regions, tet.fusions);
    out_.polygons += tet.met.size();
    out_.seconds_exact += tet.seconds;
    out_.seconds_booleans += tet.seconds_booleans;
    for (std::uint32_t x : tet.met) triangle_met_[x] = 1;
    for (const LocalRegions::Embedded& e : tet.embedded)
      out_.embedded.push_back({base + e.local_region, e.cut_triangle, e.inner});
    for (auto& [point, location] : tet.vertices) {
      if (out_.vertices[point].local_region != kNone) continue;
      location.local_region += base;
      out_.vertices[point] = location;
    }
    for (int f = 0; f < 4; ++f) parts_[4 * t + static_cast<std::size_t>(f)] = std::move(tet.parts[static_cast<std::size_t>(f)]);
  }


  // ---- faces ----------------------------------------------------------------------------------

  void connect_faces() {
    std::map<std::array<int, 3>, std::vector<std::pair<std::uint32_t, int>>> faces;
    std::set<std::pair<std::uint32_t, std::uint32_t>> same_vertices;
    for (std::uint32_t t = 0; t < bg_.tets.size(); ++t)
      for (int f = 0; f < 4; ++f) faces[face_key(t, f)].emplace_back(t, f);
    for (const auto& [key, sides] : faces) {
      if (sides.size() > 2) {
        Defect d;
        d.kind = DefectKind::NonManifoldEdge;
        d.stage = "background";
        d.message = "background face (" + std::to_string(key[0]) + ", " + std::to_string(key[1]) + ", " +
                    std::to_string(key[2]) + ") is shared by " + std::to_string(sides.size()) + " tets";
        d.vertices = {key[0], key[1], key[2]};
        report_.add(std::move(d));
        continue;
      }
      if (sides.size() == 1) {
        boundary_.push_back(sides.front());
        continue;
      }
      const auto [t1, f1] = sides[0];
      const auto [t2, f2] = sides[1];
      std::array<int, 4> v1 = bg_.tets[t1], v2 = bg_.tets[t2];
      std::sort(v1.begin(), v1.end());
      std::sort(v2.begin(), v2.end());
      if (v1 == v2) {
        // One tet twice: an adjacency's face is the three vertices its two tets share
        // (LocalRegions::face); refused as in dim3/virtual_tets.cpp, once per pair.
        if (same_vertices.insert({t1, t2}).second) report_.add(same_vertices_defect(t1, t2, bg_.tets[t1]));
        continue;
      }
      const std::vector<FacePart>& a = parts_[4 * t1 + static_cast<std::size_t>(f1)];
      const std::vector<FacePart>& b = parts_[4 * t2 + static_cast<std::size_t>(f2)];
      const std::uint32_t base1 = out_.first[t1], base2 = out_.first[t2];
      const auto add = [&](std::uint32_t x, std::uint32_t y) { out_.adjacencies.push_back({base1 + x, base2 + y, PatchId()}); };
      if (a.size() == 1 || b.size() == 1) {
        // One side is a single part covering the face: it overlaps every part of the other.
        for (const FacePart& x : a)
          for (const FacePart& y : b) add(x.lr, y.lr);
        continue;
      }
      // Positive-area overlap: a point strictly inside one part lies strictly inside the other.
      const auto holder = [&](const std::vector<FacePart>& in, const Point2& p) {
        for (const FacePart& q : in) {
          const int s = part_side(q, p);
          if (s > 0) return q.lr;
          IMM_ASSERT(s < 0, "the two tets of a face cut it differently");
        }
        IMM_ASSERT(false, "a face part of one tet in no part of the other");
        return kNone;
      };
      for (const FacePart& x : a) add(x.lr, holder(b, x.inside));
      for (const FacePart& y : b) add(holder(a, y.inside), y.lr);
    }
    LocalRegions::normalise(out_.adjacencies);
  }

  // ---- regions --------------------------------------------------------------------------------

  void resolve_regions() {
    out_.resolve_regions([&](std::uint32_t lr) { return locate(out_.element[lr]); }, threads_);
  }


  /// The region holding the centroid q of tet t (a tet the input does not meet): the side facing
  /// q of the first cut triangle crossed by the segment from q to the centroid of a cut triangle,
  /// for the first target whose segment crosses every triangle cleanly (not at an edge, not in
  /// its plane, no two at once).
  RegionId locate(std::uint32_t t) const {
    const Point q = CGAL::centroid(tet_point(t, 0), tet_point(t, 1), tet_point(t, 2), tet_point(t, 3));
    for (std::uint32_t aim = 0; aim < m_.triangles.size(); ++aim) {
      const Point m = CGAL::centroid(corner(aim, 0), corner(aim, 1), corner(aim, 2));
      std::optional<EK::FT> best;
      std::pair<std::uint32_t, bool> hit{0, false};
      bool clean = true;
      for (std::uint32_t y = 0; y < m_.triangles.size() && clean; ++y) {
        const Point& a = corner(y, 0);
        const Point& b = corner(y, 1);
        const Point& c = corner(y, 2);
        const CGAL::Orientation oq = CGAL::orientation(a, b, c, q);
        const CGAL::Orientation om = m_.triangle_source[y] == m_.triangle_source[aim] ? CGAL::ZERO
                                                                                       : CGAL::orientation(a, b, c, m);
        if (oq == CGAL::ZERO) {
          clean = !CGAL::do_intersect(EK::Segment_3(q, m), EK::Triangle_3(a, b, c));
          continue;
        }
        if (oq == om) continue;
        const CGAL::Orientation e0 = CGAL::orientation(q, m, a, b);
        const CGAL::Orientation e1 = CGAL::orientation(q, m, b, c);
        const CGAL::Orientation e2 = CGAL::orientation(q, m, c, a);
        const bool pos = e0 == CGAL::POSITIVE || e1 == CGAL::POSITIVE || e2 == CGAL::POSITIVE;
        const bool neg = e0 == CGAL::NEGATIVE || e1 == CGAL::NEGATIVE || e2 == CGAL::NEGATIVE;
        if (pos && neg) continue;
        if (e0 == CGAL::ZERO || e1 == CGAL::ZERO || e2 == CGAL::ZERO) {
          clean = false;
          continue;
        }
        EK::FT lambda(1);
        if (om != CGAL::ZERO) {
          const EK::FT vq = CGAL::determinant(b - a, c - a, q - a);
          const EK::FT vm = CGAL::determinant(b - a, c - a, m - a);
          lambda = vq / (vq - vm);
        }
        if (!best || lambda < *best) {
          best = lambda;
          hit = {y, oq == CGAL::NEGATIVE};
        } else if (lambda == *best) {
          clean = false;
        }
      }
      if (clean && best) return side_region(hit.first, hit.second);
    }
    IMM_ASSERT(false, "exact point location found no clean segment");
    return RegionId();
  }

  // ---- coverage -------------------------------------------------------------------------------

  void not_covered(std::string message, const Point3& p) {
    Defect d;
    d.kind = DefectKind::NotCovered;
    d.stage = "mesh";
    d.message = std::move(message);
    d.points.push_back({p[0], p[1], p[2]});
    report_.add(std::move(d));
  }

  void check_coverage() {
    for (const auto& [t, f] : boundary_) {
      const std::vector<FacePart>& parts = parts_[4 * t + static_cast<std::size_t>(f)];
      const Point3& p = bg_.vertices[static_cast<std::size_t>(bg_.tets[t][kFace[f][0]])];
      if (parts.size() > 1) {
        not_covered("the input crosses the boundary of the background mesh at boundary tet " + std::to_string(t) +
                        " near " + format_point(p),
                    p);
        return;
      }
      const int w = c_.complex.winding_number(out_.region[out_.first[t] + parts.front().lr]);
      if (w != 0) {
        not_covered("the background mesh ends inside a cell (winding number " + std::to_string(w) +
                        ") at boundary tet " + std::to_string(t) + " near " + format_point(p),
                    p);
        return;
      }
    }
    for (std::uint32_t x = 0; x < m_.triangles.size(); ++x) {
      if (triangle_met_[x]) continue;
      const Point& a = corner(x, 0);
      const Point3 p{CGAL::to_double(a.x()), CGAL::to_double(a.y()), CGAL::to_double(a.z())};
      not_covered("the background mesh does not cover input triangle " + std::to_string(m_.triangle_source[x]) +
                      " near " + format_point(p),
                  p);
      return;
    }
  }

  const Complex& c_;
  const CutMesh& m_;
  const TetMesh& bg_;
  const bool record_;
  const unsigned threads_;
  const LogCallback& progress_;
  ValidationReport& report_;
  bool& non_generic_;

  std::vector<Point> points_;  ///< background vertices
  std::vector<std::pair<std::uint32_t, std::uint32_t>> candidates_;
  std::vector<std::vector<FacePart>> parts_;  ///< per (tet, face)
  std::vector<char> triangle_met_;
  std::vector<std::pair<std::uint32_t, int>> boundary_;
  LocalRegions out_;
};

}  // namespace

LocalRegions compute_local_regions_csg(const Complex& complex, const TetMesh& background, bool record_embedded,
                                       unsigned threads, const LogCallback& progress, ValidationReport& report,
                                       bool& non_generic) {
  IMM_ASSERT(complex.exact != nullptr, "complex without exact geometry");
  return CsgTets(complex, background, record_embedded, resolve_threads(threads), progress, report, non_generic).run();
}

}  // namespace imm::dim3::detail
