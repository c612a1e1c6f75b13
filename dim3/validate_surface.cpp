// validate_surface (dim3/surface.h): the defects of a triangle mesh that need no intersection
// test. Linear apart from two sorts (duplicate vertices, duplicate faces): 300k triangles take a
// few tens of milliseconds.
//
// Topology is analysed on the *usable* triangles: indices in range, three distinct vertices, and
// not a repetition of an earlier triangle's vertex set. The others are reported once, as what they
// are, instead of also showing up as open or non-manifold edges.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <span>

#include "dim3/surface.h"

namespace imm::dim3 {
namespace {

using IK = CGAL::Exact_predicates_inexact_constructions_kernel;
constexpr const char* kValidateStage = "validate";
constexpr std::size_t kMaxDefectsPerKind = 20;
constexpr std::size_t kMaxListedIds = 12;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

/// Defects grouped by kind in a fixed order, at most kMaxDefectsPerKind per kind followed by one
/// "... and N more" (a broken million-triangle file must not produce a million lines).
class DefectCollector {
 public:
  void add(Defect d) {
    Bucket& b = buckets_[d.kind];
    if (++b.count <= kMaxDefectsPerKind) b.defects.push_back(std::move(d));
  }
  ValidationReport finish() {
    ValidationReport report;
    for (auto& [kind, bucket] : buckets_) {
      for (Defect& d : bucket.defects) report.add(std::move(d));
      if (bucket.count > kMaxDefectsPerKind) {
        report.add(Defect{kind,
                          kValidateStage,
                          "... and " + std::to_string(bucket.count - kMaxDefectsPerKind) +
                              " more " + to_string(kind) + " defects",
                          {},
                          {},
                          {}});
      }
    }
    return report;
  }

 private:
  struct Bucket {
    std::size_t count = 0;
    std::vector<Defect> defects;
  };
  std::map<DefectKind, Bucket> buckets_;  // DefectKind order: empty, non-finite, ..., duplicates
};

bool is_finite(const Point3& p) {
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

std::vector<double> coordinates(const Point3& p) { return {p[0], p[1], p[2]}; }

/// "3, 8, 12" (at most kMaxListedIds, then ", ... (N in all)").
template <class Ids>
std::string id_list(const Ids& ids) {
  std::string s;
  std::size_t shown = 0;
  for (const auto id : ids) {
    if (shown == kMaxListedIds) {
      s += ", ... (" + std::to_string(ids.size()) + " in all)";
      break;
    }
    s += (shown++ ? ", " : "") + std::to_string(id);
  }
  return s;
}

class Validator {
 public:
  explicit Validator(const Surface& s) : s_(s), nv_(s.vertices.size()), nt_(s.triangles.size()) {}

  ValidationReport run() {
    if (nt_ == 0) {
      out_.add(Defect{DefectKind::Empty,
                      kValidateStage,
                      "the surface has no triangle (" + std::to_string(nv_) + " vertices)",
                      {},
                      {},
                      {}});
      return out_.finish();
    }
    check_vertices();
    check_triangles();
    check_duplicate_vertices();
    check_duplicate_triangles();
    check_edges_and_fans();
    return out_.finish();
  }

 private:
  [[nodiscard]] std::string vertex_name(std::uint32_t v) const {
    return "vertex " + std::to_string(v) + " " + format_point(s_.vertices[v]);
  }
  /// "triangle 12 (vertices 3, 4, 5)", plus its file face when that differs.
  [[nodiscard]] std::string triangle_name(std::size_t t) const {
    const Triangle& tri = s_.triangles[t];
    std::string name = "triangle " + std::to_string(t) + " (vertices " + std::to_string(tri[0]) +
                       ", " + std::to_string(tri[1]) + ", " + std::to_string(tri[2]);
    if (s_.source_face.size() == nt_ && s_.source_face[t] != t)
      name += "; file face " + std::to_string(s_.source_face[t]);
    return name + ")";
  }
  [[nodiscard]] bool in_range(const Triangle& t) const {
    return t[0] < nv_ && t[1] < nv_ && t[2] < nv_;
  }
  /// Corners of an in-range triangle, for Defect::points.
  [[nodiscard]] std::vector<std::vector<double>> corner_points(const Triangle& t) const {
    return {coordinates(s_.vertices[t[0]]), coordinates(s_.vertices[t[1]]),
            coordinates(s_.vertices[t[2]])};
  }

  void check_vertices() {
    for (std::uint32_t v = 0; v < nv_; ++v) {
      if (is_finite(s_.vertices[v])) {
        // The exact steps take any double, but the rays that place nested surfaces are built in
        // doubles (a point beyond the box, twice its size away): beyond 1e300 they overflowed to
        // infinity and the exact conversion of it stopped the program (issue 13, found by the
        // fuzzer at -1e308).
        const Point3& p = s_.vertices[v];
        if (std::abs(p[0]) > kMaxCoordinate3 || std::abs(p[1]) > kMaxCoordinate3 || std::abs(p[2]) > kMaxCoordinate3) {
          out_.add(Defect{DefectKind::OutOfRange,
                          kValidateStage,
                          vertex_name(v) + " lies beyond the coordinate range of 3D inputs, |x|, |y|, |z| <= 1e300",
                          {},
                          {static_cast<long>(v)},
                          {coordinates(p)}});
        }
        continue;
      }
      out_.add(Defect{DefectKind::NonFinite,
                      kValidateStage,
                      vertex_name(v) + " has a non-finite coordinate",
                      {},
                      {static_cast<long>(v)},
                      {coordinates(s_.vertices[v])}});
    }
  }

  /// Index range, repeated corners, exactly collinear corners.
  void check_triangles() {
    usable_.assign(nt_, 1);
    for (std::size_t t = 0; t < nt_; ++t) {
      const Triangle& tri = s_.triangles[t];
      if (!in_range(tri)) {
        usable_[t] = 0;
        std::vector<long> bad;
        for (std::uint32_t v : tri) {
          if (v >= nv_) bad.push_back(static_cast<long>(v));
        }
        // No kind names a bad index exactly; OutOfRange ("out-of-range") reads right.
        out_.add(Defect{DefectKind::OutOfRange,
                        kValidateStage,
                        triangle_name(t) + " refers to vertex " + id_list(bad) +
                            ", but the surface has only " + std::to_string(nv_) + " vertices",
                        {static_cast<long>(t)},
                        {bad.begin(), bad.end()},
                        {}});
        continue;
      }
      const auto ids = std::vector<long>{tri[0], tri[1], tri[2]};
      if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) {
        usable_[t] = 0;
        out_.add(Defect{
            DefectKind::DegenerateFacet,
            kValidateStage,
            triangle_name(t) + " is degenerate: it repeats a vertex, at " +
                format_point(s_.vertices[tri[0] == tri[1] || tri[0] == tri[2] ? tri[0] : tri[1]]),
            {static_cast<long>(t)},
            ids,
            corner_points(tri)});
        continue;
      }
      const Point3& a = s_.vertices[tri[0]];
      const Point3& b = s_.vertices[tri[1]];
      const Point3& c = s_.vertices[tri[2]];
      if (!is_finite(a) || !is_finite(b) || !is_finite(c)) continue;  // reported with the vertex
      // Epick predicates are exact on double input (filtered, exact fallback).
      if (CGAL::collinear(IK::Point_3(a[0], a[1], a[2]), IK::Point_3(b[0], b[1], b[2]),
                          IK::Point_3(c[0], c[1], c[2]))) {
        out_.add(Defect{DefectKind::DegenerateFacet,
                        kValidateStage,
                        triangle_name(t) + " is degenerate: its corners " + format_point(a) + ", " +
                            format_point(b) + ", " + format_point(c) + " are collinear (zero area)",
                        {static_cast<long>(t)},
                        ids,
                        corner_points(tri)});
      }
    }
  }

  /// Two vertex ids at the same exact position, both used: welding them would change the
  /// topology, so the surface touches itself there.
  void check_duplicate_vertices() {
    std::vector<std::uint32_t> first_triangle(nv_, kNone);
    for (std::size_t t = 0; t < nt_; ++t) {
      if (!in_range(s_.triangles[t])) continue;
      for (std::uint32_t v : s_.triangles[t]) {
        if (first_triangle[v] == kNone) first_triangle[v] = static_cast<std::uint32_t>(t);
      }
    }
    struct Position {
      double x, y, z;
      std::uint32_t vertex;
      bool operator<(const Position& o) const {
        if (x != o.x) return x < o.x;
        if (y != o.y) return y < o.y;
        if (z != o.z) return z < o.z;
        return vertex < o.vertex;
      }
      [[nodiscard]] bool same_point(const Position& o) const {
        return x == o.x && y == o.y && z == o.z;
      }
    };
    std::vector<Position> used;  // finite: NaN would break the ordering (reported as non-finite)
    for (std::uint32_t v = 0; v < nv_; ++v) {
      const Point3& p = s_.vertices[v];
      if (first_triangle[v] != kNone && is_finite(p)) used.push_back({p[0], p[1], p[2], v});
    }
    std::sort(used.begin(), used.end());
    for (std::size_t i = 0; i < used.size();) {
      std::size_t j = i + 1;
      while (j < used.size() && used[j].same_point(used[i])) ++j;
      if (j - i > 1) {
        const Point3& p = s_.vertices[used[i].vertex];
        Defect d{DefectKind::DuplicateVertex, kValidateStage, "", {}, {}, {coordinates(p)}};
        std::string uses;
        for (std::size_t k = i; k < j; ++k) {
          const std::uint32_t v = used[k].vertex;
          d.vertices.push_back(v);
          d.facets.push_back(first_triangle[v]);
          if (k < i + kMaxListedIds) {
            uses += (k > i ? ", " : "") + std::to_string(v) + " in triangle " +
                    std::to_string(first_triangle[v]);
          }
        }
        d.message = "vertices " + id_list(d.vertices) + " are the same point " + format_point(p) +
                    " and are all used (" + uses +
                    "): the surface touches itself there (welding them would change its topology)";
        out_.add(std::move(d));
      }
      i = j;
    }
  }

  /// Triangles with the same vertex set; all but the first are left out of the topology checks.
  void check_duplicate_triangles() {
    struct Key {
      std::array<std::uint32_t, 3> sorted;
      std::uint32_t triangle;
      [[nodiscard]] bool same_face(const Key& o) const {
        return sorted[0] == o.sorted[0] && sorted[1] == o.sorted[1] && sorted[2] == o.sorted[2];
      }
      bool operator<(const Key& o) const {
        if (sorted[0] != o.sorted[0]) return sorted[0] < o.sorted[0];
        if (sorted[1] != o.sorted[1]) return sorted[1] < o.sorted[1];
        if (sorted[2] != o.sorted[2]) return sorted[2] < o.sorted[2];
        return triangle < o.triangle;
      }
    };
    std::vector<Key> keys;
    keys.reserve(nt_);
    for (std::size_t t = 0; t < nt_; ++t) {
      if (!usable_[t]) continue;
      Key k{s_.triangles[t], static_cast<std::uint32_t>(t)};
      std::sort(k.sorted.begin(), k.sorted.end());
      keys.push_back(k);
    }
    std::sort(keys.begin(), keys.end());
    for (std::size_t i = 0; i < keys.size();) {
      std::size_t j = i + 1;
      while (j < keys.size() && keys[j].same_face(keys[i])) ++j;
      if (j - i > 1) {
        const std::uint32_t first = keys[i].triangle;
        Defect d{DefectKind::DuplicateFacet,        kValidateStage, "", {}, {},
                 corner_points(s_.triangles[first])};
        bool opposite = false;
        for (std::size_t k = i; k < j; ++k) {
          d.facets.push_back(keys[k].triangle);
          if (k > i) usable_[keys[k].triangle] = 0;
          opposite =
              opposite || !same_orientation(s_.triangles[first], s_.triangles[keys[k].triangle]);
        }
        for (std::uint32_t v : keys[i].sorted) d.vertices.push_back(v);
        d.message = "triangles " + id_list(d.facets) + " are the same face: vertices " +
                    std::to_string(keys[i].sorted[0]) + ", " + std::to_string(keys[i].sorted[1]) +
                    ", " + std::to_string(keys[i].sorted[2]) + " at " +
                    format_point(s_.vertices[keys[i].sorted[0]]) + ", " +
                    format_point(s_.vertices[keys[i].sorted[1]]) + ", " +
                    format_point(s_.vertices[keys[i].sorted[2]]) +
                    (opposite ? " (with opposite orientations)" : "");
        out_.add(std::move(d));
      }
      i = j;
    }
  }

  static bool same_orientation(const Triangle& a, const Triangle& b) {
    for (int r = 0; r < 3; ++r) {
      if (a[0] == b[r] && a[1] == b[(r + 1) % 3]) return true;
    }
    return false;
  }

  /// Per vertex v, from its incident usable triangles:
  ///  - every undirected edge {v, w} with w > v: used once (open), twice in opposite directions
  ///    (fine), twice in the same direction (inconsistent orientation), more (non-manifold edge);
  ///  - the link of v (one edge a-b per triangle (v, a, b)) must be connected: one fan.
  void check_edges_and_fans() {
    // Incident usable triangles of every vertex (CSR).
    std::vector<std::uint32_t> start(nv_ + 1, 0);
    for (std::size_t t = 0; t < nt_; ++t) {
      if (!usable_[t]) continue;
      for (std::uint32_t v : s_.triangles[t]) ++start[v + 1];
    }
    std::partial_sum(start.begin(), start.end(), start.begin());
    incident_.assign(start[nv_], 0);
    {
      std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
      for (std::size_t t = 0; t < nt_; ++t) {
        if (!usable_[t]) continue;
        for (std::uint32_t v : s_.triangles[t])
          incident_[fill[v]++] = static_cast<std::uint32_t>(t);
      }
    }

    struct Use {
      std::uint32_t other;  ///< the edge's other vertex (> v)
      std::uint32_t triangle;
      bool forward;  ///< the triangle traverses v -> other
    };
    std::vector<Use> uses;
    local_.assign(nv_, kNone);  // neighbour -> index in the link of the current vertex
    std::vector<std::uint32_t> neighbours;
    for (std::uint32_t v = 0; v < nv_; ++v) {
      const std::uint32_t begin = start[v], end = start[v + 1];
      if (begin == end) continue;
      uses.clear();
      neighbours.clear();
      parent_.clear();
      auto local_id = [&](std::uint32_t w) {
        if (local_[w] == kNone) {
          local_[w] = static_cast<std::uint32_t>(neighbours.size());
          neighbours.push_back(w);
          parent_.push_back(local_[w]);
        }
        return local_[w];
      };
      for (std::uint32_t i = begin; i < end; ++i) {
        const std::uint32_t t = incident_[i];
        const Triangle& tri = s_.triangles[t];
        const int corner = tri[0] == v ? 0 : tri[1] == v ? 1 : 2;
        const std::uint32_t next = tri[(corner + 1) % 3], previous = tri[(corner + 2) % 3];
        if (next > v) uses.push_back({next, t, true});
        if (previous > v) uses.push_back({previous, t, false});
        const std::uint32_t a = find(local_id(next)), b = find(local_id(previous));
        if (a != b) parent_[a] = b;
      }
      check_fan(v, begin, end);
      for (std::uint32_t w : neighbours) local_[w] = kNone;

      std::sort(uses.begin(), uses.end(), [](const Use& a, const Use& b) {
        return a.other != b.other ? a.other < b.other : a.triangle < b.triangle;
      });
      for (std::size_t i = 0; i < uses.size();) {
        std::size_t j = i + 1;
        while (j < uses.size() && uses[j].other == uses[i].other) ++j;
        check_edge(v, uses[i].other, std::span<const Use>(uses.data() + i, j - i));
        i = j;
      }
    }
  }

  template <class Use>
  void check_edge(std::uint32_t v, std::uint32_t w, std::span<const Use> uses) {
    if (uses.size() == 2 && uses[0].forward != uses[1].forward) return;
    const std::string edge = "the edge between " + vertex_name(v) + " and " + vertex_name(w);
    Defect d{DefectKind::NotClosed,
             kValidateStage,
             "",
             {},
             {v, w},
             {coordinates(s_.vertices[v]), coordinates(s_.vertices[w])}};
    for (const Use& u : uses) d.facets.push_back(u.triangle);
    if (uses.size() == 1) {
      d.message = "open boundary: " + edge + " belongs only to " + triangle_name(uses[0].triangle);
    } else if (uses.size() == 2) {
      d.kind = DefectKind::InconsistentOrientation;
      const bool forward = uses[0].forward;
      d.message = triangle_name(uses[0].triangle) + " and " + triangle_name(uses[1].triangle) +
                  " both run along the edge from vertex " + std::to_string(forward ? v : w) + " " +
                  format_point(s_.vertices[forward ? v : w]) + " to vertex " +
                  std::to_string(forward ? w : v) + " " +
                  format_point(s_.vertices[forward ? w : v]) +
                  ": neighbouring triangles with opposite orientations";
    } else {
      d.kind = DefectKind::NonManifoldEdge;
      d.message = "non-manifold edge: " + edge + " is shared by " + std::to_string(uses.size()) +
                  " triangles (" + id_list(d.facets) +
                  "); an edge of a closed manifold has exactly 2";
    }
    out_.add(std::move(d));
  }

  /// The triangles around v form one fan iff the link (neighbours joined through triangles) is
  /// connected.
  void check_fan(std::uint32_t v, std::uint32_t begin, std::uint32_t end) {
    std::map<std::uint32_t, std::vector<std::uint32_t>> fans;  // link root -> triangles
    bool single = true;
    std::uint32_t root = kNone;
    for (std::uint32_t i = begin; i < end && single; ++i) {
      const std::uint32_t r = find(link_node(incident_[i], v));
      if (root == kNone) root = r;
      single = r == root;
    }
    if (single) return;
    for (std::uint32_t i = begin; i < end; ++i) {
      const std::uint32_t t = incident_[i];
      fans[find(link_node(t, v))].push_back(t);
    }
    Defect d{DefectKind::NonManifoldVertex, kValidateStage, "", {}, {v},
             {coordinates(s_.vertices[v])}};
    std::string groups;
    for (const auto& [r, triangles] : fans) {
      groups += (groups.empty() ? "" : " | ") + id_list(triangles);
      d.facets.insert(d.facets.end(), triangles.begin(), triangles.end());
    }
    d.message = "non-manifold " + vertex_name(v) + ": its " + std::to_string(end - begin) +
                " triangles form " + std::to_string(fans.size()) + " separate fans (triangles " +
                groups + ") instead of one; the surface pinches there";
    out_.add(std::move(d));
  }

  /// Union-find root in the link of the current vertex.
  std::uint32_t find(std::uint32_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  /// The link node of triangle t at v (its corner after v; the corner before v is in the same set).
  [[nodiscard]] std::uint32_t link_node(std::uint32_t t, std::uint32_t v) const {
    const Triangle& tri = s_.triangles[t];
    const int corner = tri[0] == v ? 0 : tri[1] == v ? 1 : 2;
    return local_[tri[(corner + 1) % 3]];
  }

  const Surface& s_;
  std::size_t nv_, nt_;
  std::vector<std::uint8_t> usable_;
  DefectCollector out_;
  // check_edges_and_fans: incident usable triangles per vertex (CSR), and the link of the
  // current vertex (neighbour -> link node, union-find over link nodes).
  std::vector<std::uint32_t> incident_;
  std::vector<std::uint32_t> local_;
  std::vector<std::uint32_t> parent_;
};

}  // namespace

ValidationReport validate_surface(const Surface& surface) { return Validator(surface).run(); }

}  // namespace imm::dim3
