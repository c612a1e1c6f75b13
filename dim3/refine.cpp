// Exact self-intersection refinement of a closed triangle mesh (dim3/cut_mesh.h).
//
// 1. Candidate pairs: the triangles whose closed bounding boxes meet (dim3/triangle_pairs.h).
// 2. Every pair is classified with orientation predicates on the input doubles (CGAL Epick
//    predicates are exact on double input): no contact, a generic crossing (a segment whose two
//    ends are each an input edge crossing the other triangle's interior), or a defect: coplanar
//    overlap, a vertex on a triangle, an edge meeting an edge, an intersection curve through a
//    shared vertex. The pairs are classified on all threads and applied in pair order.
// 3. Per cut triangle, in a projection that keeps its orientation sign known: the crossings of its
//    intersection segments are the triple points (each found by all three of its triangles); the
//    triangle is then triangulated with its boundary points and the subdivided segments as
//    constraints (CGAL constrained Delaunay triangulation over Epeck, no constraint crossings;
//    the cut triangles on all threads). Three points on one input edge or one intersection
//    segment are collinear by construction: the triangulation's orientation test says so
//    without exact arithmetic (KnownLines).
// The exact constructions (edge-plane and plane-plane-plane intersections) are Epeck lazy
// numbers: interval arithmetic first, exact GMP rationals only when a predicate needs them.
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_face_base_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mpzf.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <limits>
#include <map>
#include <sstream>
#include <numeric>
#include <optional>
#include <unordered_map>

#include "core/parallel.h"
#include "dim3/cut_mesh.h"
#include "dim3/triangle_pairs.h"

namespace imm::dim3 {
namespace {

using IK = CGAL::Exact_predicates_inexact_constructions_kernel;
using IPoint = IK::Point_3;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr std::size_t kMaxDefectsPerKind = 25;

std::uint64_t pair_key(std::uint32_t a, std::uint32_t b) {
  return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
}

struct TripleKey {
  std::array<std::uint32_t, 3> t;
  bool operator==(const TripleKey&) const = default;
};
struct TripleHash {
  std::size_t operator()(const TripleKey& k) const {
    std::uint64_t h = k.t[0];
    h = h * 0x9E3779B97F4A7C15ull ^ k.t[1];
    h = h * 0x9E3779B97F4A7C15ull ^ k.t[2];
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

/// The generic intersection of two input triangles a < b: a segment between two edge-triangle
/// points. `positive_corner[s]` is a corner of triangles[s] strictly on the positive side of the
/// other triangle's plane.
struct Segment {
  std::array<std::uint32_t, 2> triangles;
  std::array<std::uint32_t, 2> ends;  // point ids
  std::array<std::uint8_t, 2> positive_corner;
};

/// Collects defects, at most kMaxDefectsPerKind messages per kind plus a count of the rest.
class DefectSink {
 public:
  void add(Defect d) {
    std::size_t& n = count_[d.kind];
    if (++n <= kMaxDefectsPerKind) report_.add(std::move(d));
  }
  [[nodiscard]] bool empty() const { return count_.empty(); }
  ValidationReport finish() {
    for (const auto& [kind, n] : count_) {
      if (n > kMaxDefectsPerKind) report_.unlisted += n - kMaxDefectsPerKind;
    }
    return std::move(report_);
  }
  /// Every defect found per kind, listed or not.
  [[nodiscard]] std::vector<std::pair<DefectKind, std::size_t>> counts() const { return {count_.begin(), count_.end()}; }

 private:
  std::map<DefectKind, std::size_t> count_;
  ValidationReport report_;
};

std::vector<double> coords(const Point3& p) { return {p[0], p[1], p[2]}; }

class Refiner {
 public:
  Refiner(const Surface& s, const LogCallback& progress, unsigned threads)
      : s_(s), progress_(progress), threads_(threads) {}

  RefineResult failed() {
    RefineResult r;
    r.counts = defects_.counts();
    r.report = defects_.finish();
    return r;
  }

  RefineResult run() {
    auto mesh = std::make_shared<CutMesh>();
    m_ = mesh.get();
    build_edges();
    m_->points.reserve(s_.vertex_count());
    for (const Point3& p : s_.vertices) {
      m_->points.emplace_back(p[0], p[1], p[2]);
      m_->origins.push_back({PointOrigin::Kind::InputVertex, {static_cast<std::uint32_t>(m_->origins.size()), 0, 0}});
    }
    ipoints_.reserve(s_.vertex_count());
    for (const Point3& p : s_.vertices) ipoints_.emplace_back(p[0], p[1], p[2]);

    const std::vector<std::array<std::uint32_t, 2>> candidates = candidate_pairs();
    log("intersect: " + std::to_string(candidates.size()) + " candidate triangle pairs");
    tri_segments_.assign(s_.triangle_count(), {});
    edge_points_.assign(m_->edges.size(), {});
    classify_all(candidates);
    if (!defects_.empty()) return failed();
    m_->intersecting_pairs = segments_.size();
    m_->edge_triangle_points = m_->points.size() - s_.vertex_count();
    log("intersect: " + std::to_string(segments_.size()) + " crossing pairs, " +
        std::to_string(m_->edge_triangle_points) + " intersection points");

    sort_edge_points();
    log("intersect: intersection points ordered along their edges");
    find_triple_points();
    log("intersect: " + std::to_string(triples_.size()) + " triple points");
    if (!defects_.empty()) return failed();
    m_->triple_points = triples_.size();
    assign_sheet_vertices();
    triangulate_all(threads_);
    if (!defects_.empty()) return failed();
    check_pieces();
    log("cut: " + std::to_string(m_->triangles.size()) + " sub-triangles, " + std::to_string(m_->pieces.size()) +
        " cut edges, " + std::to_string(m_->triple_points) + " triple points");
    return {ValidationReport{}, {}, std::move(mesh)};
  }

 private:
  // ---- input combinatorics ---------------------------------------------------------------

  void build_edges() {
    std::unordered_map<std::uint64_t, std::uint32_t> index;
    index.reserve(s_.triangle_count() * 2);
    m_->triangle_edges.resize(s_.triangle_count());
    for (std::uint32_t t = 0; t < s_.triangle_count(); ++t) {
      const Triangle& tri = s_.triangles[t];
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t u = tri[k], v = tri[(k + 1) % 3];
        auto [it, inserted] = index.try_emplace(pair_key(u, v), static_cast<std::uint32_t>(m_->edges.size()));
        if (inserted) m_->edges.push_back({std::min(u, v), std::max(u, v), {t, kNone}});
        else m_->edges[it->second].triangles[1] = t;
        m_->triangle_edges[t][k] = it->second;
      }
    }
    for (const InputEdge& e : m_->edges) {
      IMM_ASSERT(e.triangles[1] != kNone, "refine_surface needs a closed manifold input (validate_surface first)");
    }
  }

  std::vector<std::array<std::uint32_t, 2>> candidate_pairs() const {
    return overlapping_triangle_pairs(s_, threads_);  // sorted: deterministic ids below
  }

  // ---- pair classification (exact predicates on the input doubles) ----------------------

  const IPoint& ip(std::uint32_t t, int k) const { return ipoints_[s_.triangles[t][k]]; }
  IK::Triangle_3 itri(std::uint32_t t) const { return {ip(t, 0), ip(t, 1), ip(t, 2)}; }

  std::string describe_triangle(std::uint32_t t) const {
    std::ostringstream os;
    os << "triangle " << t << " (vertices " << s_.triangles[t][0] << ", " << s_.triangles[t][1] << ", "
       << s_.triangles[t][2] << ")";
    return os.str();
  }

  Defect make_defect(DefectKind kind, const std::string& message, std::vector<long> triangles,
                     std::vector<long> vertices) const {
    std::vector<std::vector<double>> pts;
    for (long v : vertices) pts.push_back(coords(s_.vertices[static_cast<std::size_t>(v)]));
    return Defect{kind, "intersect", message, std::move(triangles), std::move(vertices), std::move(pts)};
  }

  void defect(DefectKind kind, const std::string& message, std::vector<long> triangles, std::vector<long> vertices) {
    defects_.add(make_defect(kind, message, std::move(triangles), std::move(vertices)));
  }

  /// What one candidate pair contributes: found from exact predicates on the input doubles
  /// alone (no shared state is written, so pairs are classified on all threads), then applied
  /// in pair order on the calling thread (apply), so point ids and defects do not depend on the
  /// thread count.
  struct PairResult {
    bool crossing = false;
    std::array<std::array<std::uint32_t, 2>, 2> ends{};  // per end: (input edge, triangle it crosses)
    std::array<std::uint8_t, 2> positive_corner{0, 0};
    std::vector<Defect> defects;
    [[nodiscard]] bool empty() const { return !crossing && defects.empty(); }
    void defect(Defect d) { defects.push_back(std::move(d)); }
  };

  /// Classifies every candidate pair (in blocks, on all threads) and applies the results in
  /// pair order; then computes the new intersection points' exact coordinates on all threads.
  void classify_all(const std::vector<std::array<std::uint32_t, 2>>& candidates) {
    constexpr std::size_t kBlock = 2048;
    const std::size_t blocks = (candidates.size() + kBlock - 1) / kBlock;
    std::vector<std::vector<std::pair<std::uint32_t, PairResult>>> found(blocks);  // non-empty results only
    parallel_for(threads_, blocks, [&](std::size_t block, unsigned) {
      std::vector<std::pair<std::uint32_t, PairResult>> results;  // local: blocks' headers share cache lines
      for (std::size_t i = block * kBlock; i < std::min(candidates.size(), (block + 1) * kBlock); ++i) {
        PairResult r;
        classify(candidates[i][0], candidates[i][1], r);
        if (!r.empty()) results.emplace_back(static_cast<std::uint32_t>(i), std::move(r));
      }
      found[block] = std::move(results);
    }, 1);
    for (auto& list : found)
      for (auto& [i, r] : list) apply(candidates[i][0], candidates[i][1], r);
    if (!defects_.empty()) return;
    // The points were numbered in pair order above; their coordinates are independent (each an
    // Epeck point of its own exact rationals, so building them on several threads shares nothing).
    std::vector<std::optional<EK::Point_3>> exact(pending_points_.size());
    parallel_for(threads_, pending_points_.size(), [&](std::size_t k, unsigned) {
      std::array<Rational, 3> x = edge_triangle_coordinates(pending_points_[k][0], pending_points_[k][1]);
      exact[k].emplace(EK::FT(std::move(x[0])), EK::FT(std::move(x[1])), EK::FT(std::move(x[2])));
    });
    m_->points.reserve(m_->points.size() + exact.size());
    for (auto& p : exact) m_->points.push_back(std::move(*p));
    std::vector<std::array<std::uint32_t, 2>>().swap(pending_points_);
  }

  void apply(std::uint32_t a, std::uint32_t b, PairResult& r) {
    for (Defect& d : r.defects) defects_.add(std::move(d));
    if (!r.crossing) return;
    Segment seg{{a, b}, {edge_triangle_point(r.ends[0][0], r.ends[0][1]), edge_triangle_point(r.ends[1][0], r.ends[1][1])},
                r.positive_corner};
    const auto id = static_cast<std::uint32_t>(segments_.size());
    segments_.push_back(seg);
    tri_segments_[a].push_back(id);
    tri_segments_[b].push_back(id);
  }

  void classify(std::uint32_t a, std::uint32_t b, PairResult& r) const {
    const Triangle& ta = s_.triangles[a];
    const Triangle& tb = s_.triangles[b];
    int shared = 0;
    std::array<int, 3> match_a{-1, -1, -1};  // corner of b equal to corner k of a
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (ta[i] == tb[j]) {
          match_a[i] = j;
          ++shared;
        }
    if (shared == 3) return;  // a duplicate face: validate_surface reports it
    if (shared == 2) return classify_edge_neighbours(a, b, match_a, r);
    if (shared == 1) return classify_vertex_neighbours(a, b, match_a, r);
    classify_disjoint(a, b, r);
  }

  void classify_edge_neighbours(std::uint32_t a, std::uint32_t b, const std::array<int, 3>& match_a,
                                PairResult& r) const {
    int oa = 0;
    while (match_a[oa] >= 0) ++oa;
    const Triangle& tb = s_.triangles[b];
    int ob = 0;
    while (tb[ob] == s_.triangles[a][0] || tb[ob] == s_.triangles[a][1] || tb[ob] == s_.triangles[a][2]) ++ob;
    if (CGAL::orientation(ip(a, 0), ip(a, 1), ip(a, 2), ip(b, ob)) != CGAL::COPLANAR) return;
    const IPoint& u = ip(a, (oa + 1) % 3);
    const IPoint& v = ip(a, (oa + 2) % 3);
    if (CGAL::coplanar_orientation(u, v, ip(a, oa), ip(b, ob)) == CGAL::POSITIVE) {
      r.defect(make_defect(DefectKind::CoplanarOverlap,
             describe_triangle(a) + " and " + describe_triangle(b) + " share an edge and fold onto each other "
                 "(coplanar overlap)",
             {a, b}, {s_.triangles[a][oa], tb[ob]}));
    }
  }

  void classify_vertex_neighbours(std::uint32_t a, std::uint32_t b, const std::array<int, 3>& match_a,
                                  PairResult& r) const {
    int ia = 0;
    while (match_a[ia] < 0) ++ia;
    const int ib = match_a[ia];
    const IPoint &a1 = ip(a, (ia + 1) % 3), &a2 = ip(a, (ia + 2) % 3);
    const IPoint &b1 = ip(b, (ib + 1) % 3), &b2 = ip(b, (ib + 2) % 3);
    // The common case first, with two orientations: when b's far corners lie strictly on one
    // side of a's plane, b meets that plane (so a) only at v, and the two do not meet beyond v
    // (and vice versa).
    for (int side = 0; side < 2; ++side) {
      const std::uint32_t t = side == 0 ? a : b;
      const IPoint &f1 = side == 0 ? b1 : a1, &f2 = side == 0 ? b2 : a2;
      const CGAL::Orientation o1 = CGAL::orientation(ip(t, 0), ip(t, 1), ip(t, 2), f1);
      if (o1 != CGAL::COPLANAR && o1 == CGAL::orientation(ip(t, 0), ip(t, 1), ip(t, 2), f2)) return;
    }
    // Two triangles sharing only v meet beyond v iff the far edge of one meets the other.
    if (!CGAL::do_intersect(IK::Segment_3(a1, a2), itri(b)) && !CGAL::do_intersect(IK::Segment_3(b1, b2), itri(a))) {
      return;
    }
    const std::uint32_t v = s_.triangles[a][ia];
    // A robust crossing: the far edge of one triangle crosses the other's interior transversally.
    // Every small perturbation keeps it, so it is a local fold, not a contact.
    for (int side = 0; side < 2; ++side) {
      const std::uint32_t t = side == 0 ? a : b, u = side == 0 ? b : a;
      const int k = ((side == 0 ? ia : ib) + 1) % 3;  // edge k joins corners k and k + 1: the far edge
      const CGAL::Orientation op = CGAL::orientation(ip(u, 0), ip(u, 1), ip(u, 2), ip(t, k));
      const CGAL::Orientation oq = CGAL::orientation(ip(u, 0), ip(u, 1), ip(u, 2), ip(t, (k + 1) % 3));
      if (op == CGAL::COPLANAR || oq == CGAL::COPLANAR || op == oq || edge_crosses(t, k, u) != 1) continue;
      r.defect(local_fold(v, t, u, k));
      return;
    }
    const bool coplanar = CGAL::orientation(ip(a, 0), ip(a, 1), ip(a, 2), b1) == CGAL::COPLANAR &&
                          CGAL::orientation(ip(a, 0), ip(a, 1), ip(a, 2), b2) == CGAL::COPLANAR;
    if (coplanar) {
      r.defect(make_defect(DefectKind::CoplanarOverlap,
                           describe_triangle(a) + " and " + describe_triangle(b) + " share vertex " +
                               std::to_string(v) + " " + format_point(s_.vertices[v]) +
                               " and overlap in their common plane",
                           {a, b}, {v}));
    } else {
      r.defect(make_defect(DefectKind::TriplePoint,
                           describe_triangle(a) + " and " + describe_triangle(b) + " share vertex " +
                               std::to_string(v) + " " + format_point(s_.vertices[v]) +
                               " and intersect beyond it: an intersection curve passes through an input vertex "
                               "(non-generic)",
                           {a, b}, {v}));
    }
  }

  /// Triangles t and u of vertex v's star cross beyond v: edge k of t (the far edge) crosses u's
  /// interior. Reported with the crossing point (rounded) as the place to look.
  Defect local_fold(std::uint32_t v, std::uint32_t t, std::uint32_t u, int k) const {
    const Point3 &a = s_.vertices[s_.triangles[u][0]], &b = s_.vertices[s_.triangles[u][1]],
                 &c = s_.vertices[s_.triangles[u][2]];
    const Point3 &p = s_.vertices[s_.triangles[t][k]], &q = s_.vertices[s_.triangles[t][(k + 1) % 3]];
    const auto det = [&](const Point3& x) {
      const double u0 = b[0] - a[0], u1 = b[1] - a[1], u2 = b[2] - a[2];
      const double v0 = c[0] - a[0], v1 = c[1] - a[1], v2 = c[2] - a[2];
      const double w0 = x[0] - a[0], w1 = x[1] - a[1], w2 = x[2] - a[2];
      return u0 * (v1 * w2 - v2 * w1) - u1 * (v0 * w2 - v2 * w0) + u2 * (v0 * w1 - v1 * w0);
    };
    const double dp = det(p), dq = det(q), lambda = dp / (dp - dq);
    const Point3 x{p[0] + (q[0] - p[0]) * lambda, p[1] + (q[1] - p[1]) * lambda, p[2] + (q[2] - p[2]) * lambda};
    const std::uint32_t lo = std::min(t, u), hi = std::max(t, u);
    std::vector<std::vector<double>> pts{coords(s_.vertices[v]), coords(x)};
    return Defect{DefectKind::LocalFold, "intersect",
                        "vertex " + std::to_string(v) + " " + format_point(s_.vertices[v]) + ": " +
                            describe_triangle(lo) + " and " + describe_triangle(hi) +
                            " of its star cross each other beyond it (from the vertex to about " + format_point(x) +
                            "): a local fold. The surface is not embedded around the vertex, so it bounds no "
                            "immersed solid there, and no small perturbation removes the crossing",
                        {lo, hi},
                        {v},
                        std::move(pts)};
  }

  /// Edge k of triangle t crossing the interior of triangle u: 1 crossing, 0 missing, -1 touching
  /// u's boundary (non-generic). @pre its endpoints lie strictly on opposite sides of u's plane.
  int edge_crosses(std::uint32_t t, int k, std::uint32_t u) const {
    const IPoint &p = ip(t, k), &q = ip(t, (k + 1) % 3);
    const CGAL::Orientation s0 = CGAL::orientation(p, q, ip(u, 0), ip(u, 1));
    const CGAL::Orientation s1 = CGAL::orientation(p, q, ip(u, 1), ip(u, 2));
    const CGAL::Orientation s2 = CGAL::orientation(p, q, ip(u, 2), ip(u, 0));
    if (s0 == s1 && s1 == s2) return 1;  // all non-zero: a zero in all three is impossible (u is not degenerate)
    const bool pos = s0 == CGAL::POSITIVE || s1 == CGAL::POSITIVE || s2 == CGAL::POSITIVE;
    const bool neg = s0 == CGAL::NEGATIVE || s1 == CGAL::NEGATIVE || s2 == CGAL::NEGATIVE;
    return pos && neg ? 0 : -1;
  }

  void classify_disjoint(std::uint32_t a, std::uint32_t b, PairResult& r) const {
    std::array<CGAL::Orientation, 3> oa, ob;  // corners of a w.r.t. b's plane, and vice versa
    for (int k = 0; k < 3; ++k) {
      oa[k] = CGAL::orientation(ip(b, 0), ip(b, 1), ip(b, 2), ip(a, k));
      ob[k] = CGAL::orientation(ip(a, 0), ip(a, 1), ip(a, 2), ip(b, k));
    }
    auto one_side = [](const std::array<CGAL::Orientation, 3>& o) {
      return (o[0] == o[1] && o[1] == o[2] && o[0] != CGAL::COPLANAR);
    };
    if (one_side(oa) || one_side(ob)) return;
    if (oa[0] == CGAL::COPLANAR && oa[1] == CGAL::COPLANAR && oa[2] == CGAL::COPLANAR) {
      if (CGAL::do_intersect(itri(a), itri(b))) {
        r.defect(make_defect(DefectKind::CoplanarOverlap,
                             describe_triangle(a) + " and " + describe_triangle(b) + " are coplanar and overlap or touch",
                             {a, b}, {s_.triangles[a][0], s_.triangles[b][0]}));
      }
      return;
    }
    // Contacts that are not transversal crossings: a vertex in the other triangle's plane and
    // inside it, an edge lying in the other plane and meeting the triangle.
    for (int side = 0; side < 2; ++side) {
      const std::uint32_t t = side == 0 ? a : b, u = side == 0 ? b : a;
      const auto& o = side == 0 ? oa : ob;
      for (int k = 0; k < 3; ++k) {
        if (o[k] != CGAL::COPLANAR) continue;
        const std::uint32_t v = s_.triangles[t][k];
        if (CGAL::do_intersect(itri(u), ip(t, k))) {
          r.defect(make_defect(DefectKind::Touching,
                               "vertex " + std::to_string(v) + " " + format_point(s_.vertices[v]) + " of " +
                                   describe_triangle(t) + " lies on " + describe_triangle(u) +
                                   ": the surface touches itself there",
                               {t, u}, {v}));
          return;
        }
        const int k1 = (k + 1) % 3;
        if (o[k1] == CGAL::COPLANAR && CGAL::do_intersect(IK::Segment_3(ip(t, k), ip(t, k1)), itri(u))) {
          r.defect(make_defect(DefectKind::Touching,
                               "edge (" + std::to_string(v) + ", " + std::to_string(s_.triangles[t][k1]) + ") of " +
                                   describe_triangle(t) + " lies in the plane of " + describe_triangle(u) +
                                   " and meets it",
                               {t, u}, {v, s_.triangles[t][k1]}));
          return;
        }
      }
    }
    int found = 0;
    for (int side = 0; side < 2; ++side) {
      const std::uint32_t t = side == 0 ? a : b, u = side == 0 ? b : a;
      const auto& o = side == 0 ? oa : ob;
      for (int k = 0; k < 3; ++k) {
        const int k1 = (k + 1) % 3;
        if (o[k] == CGAL::COPLANAR || o[k1] == CGAL::COPLANAR || o[k] == o[k1]) continue;
        const int c = edge_crosses(t, k, u);
        if (c == 0) continue;
        if (c < 0) {
          const std::uint32_t v0 = s_.triangles[t][k], v1 = s_.triangles[t][k1];
          r.defect(make_defect(DefectKind::Touching,
                               "edge (" + std::to_string(v0) + ", " + std::to_string(v1) + ") of " +
                                   describe_triangle(t) + " passes through an edge or vertex of " +
                                   describe_triangle(u) + " instead of its interior (non-generic contact)",
                               {t, u}, {v0, v1}));
          return;
        }
        if (found < 2) r.ends[found] = {m_->triangle_edges[t][k], u};
        ++found;
      }
    }
    if (found == 0) return;
    IMM_ASSERT(found == 2, "a generic triangle-triangle crossing has exactly two ends, found " + std::to_string(found));
    r.crossing = true;
    for (int k = 0; k < 3; ++k) {
      if (oa[k] == CGAL::POSITIVE) r.positive_corner[0] = static_cast<std::uint8_t>(k);
      if (ob[k] == CGAL::POSITIVE) r.positive_corner[1] = static_cast<std::uint8_t>(k);
    }
  }

  /// The id of the crossing of input edge `edge` with triangle `tri`, numbered at its first
  /// use; its coordinates are computed later (classify_all, edge_triangle_coordinates).
  std::uint32_t edge_triangle_point(std::uint32_t edge, std::uint32_t tri) {
    auto [it, inserted] = edge_tri_index_.try_emplace((std::uint64_t{edge} << 32) | tri, 0);
    if (!inserted) return it->second;
    const std::uint32_t id = static_cast<std::uint32_t>(m_->origins.size());
    it->second = id;
    m_->origins.push_back({PointOrigin::Kind::EdgeTriangle, {edge, tri, 0}});
    pending_points_.push_back({edge, tri});
    edge_points_[edge].push_back(id);
    return id;
  }

  /// The crossing of input edge `edge` with triangle `tri` in exact rationals from the input
  /// doubles (not as a lazy construction): the point is then exact from the start, and the many
  /// predicates that later meet it exactly (points on triangle edges are collinear with the
  /// corners) cost no deferred evaluation.
  /// With d(x) = det(b - a, c - a, x - a): the crossing is p + (q - p) d(p) / (d(p) - d(q))
  /// = (q d(p) - p d(q)) / (d(p) - d(q)). Sums and products of doubles are exact in CGAL's dyadic
  /// Mpzf (no gcd per operation, unlike GMP rationals), so only the three final quotients are
  /// rationals: the same (canonical) rationals as evaluating the formula in rationals throughout.
  std::array<Rational, 3> edge_triangle_coordinates(std::uint32_t edge, std::uint32_t tri) const {
    using Z = CGAL::Mpzf;
    const InputEdge& e = m_->edges[edge];
    const Triangle& t = s_.triangles[tri];
    const auto exact = [&](std::uint32_t v) {
      const Point3& x = s_.vertices[v];
      return std::array<Z, 3>{Z(x[0]), Z(x[1]), Z(x[2])};
    };
    const auto a = exact(t[0]), b = exact(t[1]), c = exact(t[2]), p = exact(e.v0), q = exact(e.v1);
    const Z u0 = b[0] - a[0], u1 = b[1] - a[1], u2 = b[2] - a[2];
    const Z v0 = c[0] - a[0], v1 = c[1] - a[1], v2 = c[2] - a[2];
    const auto det = [&](const std::array<Z, 3>& x) {
      const Z w0 = x[0] - a[0], w1 = x[1] - a[1], w2 = x[2] - a[2];
      return Z(u0 * (v1 * w2 - v2 * w1) - u1 * (v0 * w2 - v2 * w0) + u2 * (v0 * w1 - v1 * w0));
    };
    const Z dp = det(p), dq = det(q);
    IMM_ASSERT(dp != dq, "edge-triangle crossing without an intersection point");
    const Rational denominator = static_cast<Rational>(Z(dp - dq));
    std::array<Rational, 3> out;
    for (int d = 0; d < 3; ++d) out[d] = static_cast<Rational>(Z(q[d] * dp - p[d] * dq)) / denominator;
    return out;
  }

  void sort_edge_points() {
    for (std::size_t e = 0; e < m_->edges.size(); ++e) {
      auto& list = edge_points_[e];
      if (list.size() < 2) continue;
      const EK::Point_3& from = m_->points[m_->edges[e].v0];
      std::sort(list.begin(), list.end(), [&](std::uint32_t p, std::uint32_t q) {
        return CGAL::compare_distance_to_point(from, m_->points[p], m_->points[q]) == CGAL::SMALLER;
      });
      for (std::size_t i = 1; i < list.size(); ++i) {
        if (CGAL::compare_distance_to_point(from, m_->points[list[i - 1]], m_->points[list[i]]) == CGAL::EQUAL) {
          const auto& o0 = m_->origins[list[i - 1]].ids;
          const auto& o1 = m_->origins[list[i]].ids;
          defect(DefectKind::TriplePoint,
                 "triangles " + std::to_string(o0[1]) + " and " + std::to_string(o1[1]) + " cross edge (" +
                     std::to_string(m_->edges[e].v0) + ", " + std::to_string(m_->edges[e].v1) +
                     ") at the same point: three sheets meet on an edge (non-generic)",
                 {o0[1], o1[1]}, {m_->edges[e].v0, m_->edges[e].v1});
        }
      }
    }
  }

  // ---- per-triangle planar work --------------------------------------------------------------

  /// The coordinate dropped by triangle t's projection (its normal's non-zero component), and
  /// whether the projection reverses orientation.
  struct Projection {
    int drop = 2;
    bool flipped = false;
  };

  Projection projection_of(std::uint32_t t) const {
    const Point3 &p = s_.vertices[s_.triangles[t][0]], &q = s_.vertices[s_.triangles[t][1]],
                 &r = s_.vertices[s_.triangles[t][2]];
    const double n[3] = {(q[1] - p[1]) * (r[2] - p[2]) - (q[2] - p[2]) * (r[1] - p[1]),
                         (q[2] - p[2]) * (r[0] - p[0]) - (q[0] - p[0]) * (r[2] - p[2]),
                         (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])};
    int order[3] = {0, 1, 2};
    std::sort(order, order + 3, [&](int i, int j) { return std::abs(n[i]) > std::abs(n[j]); });
    for (int drop : order) {  // the largest component first; the exact sign decides
      const int i = (drop + 1) % 3, j = (drop + 2) % 3;
      const CGAL::Orientation o = CGAL::orientation(IK::Point_2(p[i], p[j]), IK::Point_2(q[i], q[j]),
                                                    IK::Point_2(r[i], r[j]));
      if (o != CGAL::COLLINEAR) return {drop, o == CGAL::NEGATIVE};
    }
    IMM_ASSERT(false, "degenerate triangle " + std::to_string(t) + " reached the refinement");
    return {};
  }

  static EK::Point_2 project(const EK::Point_3& p, int drop) {
    switch (drop) {
      case 0: return {p.y(), p.z()};
      case 1: return {p.z(), p.x()};
      default: return {p.x(), p.y()};
    }
  }

  /// Per cut triangle: the points of each of its segments in order (ends included).
  void find_triple_points() {
    seg_points_.assign(segments_.size() * 2, {});
    for (std::uint32_t t = 0; t < s_.triangle_count(); ++t) {
      const auto& segs = tri_segments_[t];
      if (segs.empty()) continue;
      const Projection pr = projection_of(t);
      std::unordered_map<std::uint32_t, EK::Point_2> proj;
      auto P = [&](std::uint32_t id) -> const EK::Point_2& {
        auto it = proj.find(id);
        if (it == proj.end()) it = proj.emplace(id, project(m_->points[id], pr.drop)).first;
        return it->second;
      };
      std::vector<std::vector<std::uint32_t>> inner(segs.size());
      for (std::size_t i = 0; i < segs.size(); ++i) {
        const Segment& si = segments_[segs[i]];
        const CGAL::Bbox_2 bi = P(si.ends[0]).bbox() + P(si.ends[1]).bbox();
        for (std::size_t j = i + 1; j < segs.size(); ++j) {
          const Segment& sj = segments_[segs[j]];
          if (!CGAL::do_overlap(bi, P(sj.ends[0]).bbox() + P(sj.ends[1]).bbox())) continue;
          const bool shares = si.ends[0] == sj.ends[0] || si.ends[0] == sj.ends[1] || si.ends[1] == sj.ends[0] ||
                              si.ends[1] == sj.ends[1];
          if (shares) {
            // Consecutive pieces of one curve across an edge of the other sheet: they meet only
            // at the shared end unless they are collinear and overlap. (No predicate here sees the
            // shared point twice: such a predicate is exactly zero and would defeat the filter.)
            const std::uint32_t c = (si.ends[0] == sj.ends[0] || si.ends[0] == sj.ends[1]) ? si.ends[0] : si.ends[1];
            const std::uint32_t far_i = si.ends[0] == c ? si.ends[1] : si.ends[0];
            const std::uint32_t far_j = sj.ends[0] == c ? sj.ends[1] : sj.ends[0];
            if (CGAL::orientation(P(c), P(far_i), P(far_j)) == CGAL::COLLINEAR &&
                !CGAL::collinear_are_ordered_along_line(P(far_i), P(c), P(far_j))) {
              non_generic_curves(t, si, sj);
            }
            continue;
          }
          const EK::Point_2 &p = P(si.ends[0]), &q = P(si.ends[1]), &r = P(sj.ends[0]), &s = P(sj.ends[1]);
          const CGAL::Orientation o1 = CGAL::orientation(p, q, r), o2 = CGAL::orientation(p, q, s);
          const CGAL::Orientation o3 = CGAL::orientation(r, s, p), o4 = CGAL::orientation(r, s, q);
          if (o1 * o2 < 0 && o3 * o4 < 0) {
            const std::uint32_t other_i = si.triangles[0] == t ? si.triangles[1] : si.triangles[0];
            const std::uint32_t other_j = sj.triangles[0] == t ? sj.triangles[1] : sj.triangles[0];
            const std::uint32_t id = triple_point(t, other_i, other_j);
            inner[i].push_back(id);
            inner[j].push_back(id);
            continue;
          }
          if (o1 * o2 <= 0 && o3 * o4 <= 0) {
            // Touching or collinear: do they meet at all?
            if (CGAL::do_intersect(EK::Segment_2(p, q), EK::Segment_2(r, s))) non_generic_curves(t, si, sj);
          }
        }
      }
      for (std::size_t i = 0; i < segs.size(); ++i) {
        const Segment& si = segments_[segs[i]];
        std::vector<std::uint32_t> pts = std::move(inner[i]);
        const EK::Point_2& from = P(si.ends[0]);
        std::sort(pts.begin(), pts.end(), [&](std::uint32_t x, std::uint32_t y) {
          return CGAL::compare_distance_to_point(from, P(x), P(y)) == CGAL::SMALLER;
        });
        pts.insert(pts.begin(), si.ends[0]);
        pts.push_back(si.ends[1]);
        seg_points_[segs[i] * 2 + (si.triangles[0] == t ? 0 : 1)] = std::move(pts);
      }
    }
    for (const auto& [key, count] : triple_seen_) {
      IMM_ASSERT(count == 3, "triple point of triangles " + std::to_string(key.t[0]) + ", " + std::to_string(key.t[1]) +
                                 ", " + std::to_string(key.t[2]) + " found by " + std::to_string(count) +
                                 " of its 3 triangles");
    }
  }

  void non_generic_curves(std::uint32_t t, const Segment& si, const Segment& sj) {
    const std::uint32_t other_i = si.triangles[0] == t ? si.triangles[1] : si.triangles[0];
    const std::uint32_t other_j = sj.triangles[0] == t ? sj.triangles[1] : sj.triangles[0];
    defect(DefectKind::TriplePoint,
           "the intersection curves of " + describe_triangle(t) + " with triangles " + std::to_string(other_i) +
               " and " + std::to_string(other_j) + " touch or overlap instead of crossing (non-generic triple contact)",
           {t, other_i, other_j}, {s_.triangles[t][0]});
  }

  std::uint32_t triple_point(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    TripleKey key{{a, b, c}};
    std::sort(key.t.begin(), key.t.end());
    ++triple_seen_[key];
    auto [it, inserted] = triples_.try_emplace(key, 0);
    if (!inserted) return it->second;
    const std::uint32_t id = static_cast<std::uint32_t>(m_->points.size());
    it->second = id;
    auto plane = [&](std::uint32_t t) {
      const Triangle& tri = s_.triangles[t];
      return EK::Plane_3(m_->points[tri[0]], m_->points[tri[1]], m_->points[tri[2]]);
    };
    const auto hit = CGAL::intersection(plane(key.t[0]), plane(key.t[1]), plane(key.t[2]));
    const EK::Point_3* p = hit ? boost::get<EK::Point_3>(&*hit) : nullptr;
    IMM_ASSERT(p != nullptr, "three crossing triangles without a common point");
    m_->points.push_back(*p);
    // Evaluated exactly now, while one thread runs. A lazy point's approximation tightens when
    // its exact value is first computed, and CGAL's triangulations start each point location
    // with a walk on those approximations rounded to doubles (structural filtering): left lazy,
    // a triple point shared by several cut triangles would present different doubles to their
    // concurrent triangulations depending on which thread evaluated it first, and the CDTs would
    // be built along different walks (same faces, another order; another triangulation where
    // points are cocircular).
    CGAL::exact(m_->points.back());
    m_->origins.push_back({PointOrigin::Kind::TriplePoint, key.t});
    return id;
  }

  // ---- sheet vertices -------------------------------------------------------------------------

  void assign_sheet_vertices() {
    const std::size_t n = m_->points.size();
    sheet_base_.assign(n, 0);
    m_->vertex_point.clear();
    for (std::uint32_t p = 0; p < n; ++p) {
      sheet_base_[p] = static_cast<std::uint32_t>(m_->vertex_point.size());
      const int sheets = m_->origins[p].kind == PointOrigin::Kind::InputVertex    ? 1
                         : m_->origins[p].kind == PointOrigin::Kind::EdgeTriangle ? 2
                                                                                  : 3;
      for (int k = 0; k < sheets; ++k) m_->vertex_point.push_back(p);
    }
  }

  /// The vertex of point p on the sheet of input triangle t.
  std::uint32_t sheet_vertex(std::uint32_t p, std::uint32_t t) const {
    const PointOrigin& o = m_->origins[p];
    switch (o.kind) {
      case PointOrigin::Kind::InputVertex: return sheet_base_[p];
      case PointOrigin::Kind::EdgeTriangle: return sheet_base_[p] + (o.ids[1] == t ? 1 : 0);
      case PointOrigin::Kind::TriplePoint: return sheet_base_[p] + (o.ids[0] == t ? 0 : o.ids[1] == t ? 1 : 2);
    }
    return kNone;
  }

  // ---- triangulation -----------------------------------------------------------------------

  /// The lines of one cut triangle's arrangement that are known exactly: its input edges (a
  /// corner lies on two, a crossing point on the edge it crosses) and its intersection segments
  /// (their ends and the triple points on them; a triple point lies on two). Three points on one
  /// such line are collinear by construction, a fact the triangulation's orientation predicate
  /// would otherwise establish in exact rationals (the interval filter cannot decide an exact
  /// zero): points on the triangle's edges make most of its exact evaluations.
  class KnownLines {
   public:
    static std::uint64_t edge_line(std::uint32_t edge) { return edge; }
    static std::uint64_t segment_line(std::uint32_t segment) { return (std::uint64_t{1} << 32) | segment; }

    /// Records that point `id` lies on `line`.
    void add(std::uint32_t id, std::uint64_t line) {
      Entry& e = entry(id);
      if (std::find(e.lines.begin(), e.lines.begin() + e.count, line) != e.lines.begin() + e.count) return;
      IMM_ASSERT(e.count < e.lines.size(), "a cut point on more than four known lines");
      e.lines[e.count++] = line;
    }
    /// The projected point of `id`, as the triangulation holds it (the same lazy handle).
    void set_point(std::uint32_t id, const EK::Point_2& p) {
      Entry& e = entry(id);
      e.point = p;
      e.placed = true;
    }

    /// True when p, q and r (handles given to set_point) lie on one known line.
    [[nodiscard]] bool collinear(const EK::Point_2& p, const EK::Point_2& q, const EK::Point_2& r) const {
      const Entry *ep = find(p), *eq = find(q), *er = find(r);
      if (ep == nullptr || eq == nullptr || er == nullptr) return false;
      const auto on = [](const Entry& e, std::uint64_t line) {
        return std::find(e.lines.begin(), e.lines.begin() + e.count, line) != e.lines.begin() + e.count;
      };
      for (std::uint8_t i = 0; i < ep->count; ++i)
        if (on(*eq, ep->lines[i]) && on(*er, ep->lines[i])) return true;
      return false;
    }

   private:
    struct Entry {
      std::uint32_t id = 0;
      EK::Point_2 point;    // a default handle (shared by every default point) until placed
      bool placed = false;
      std::array<std::uint64_t, 4> lines{};
      std::uint8_t count = 0;
    };
    Entry& entry(std::uint32_t id) {
      for (Entry& e : entries_)
        if (e.id == id) return e;
      entries_.push_back({});
      entries_.back().id = id;
      return entries_.back();
    }
    const Entry* find(const EK::Point_2& p) const {
      for (const Entry& e : entries_)
        if (e.placed && static_cast<const CGAL::Handle&>(e.point).identical(p)) return &e;  // the same lazy point
      return nullptr;
    }
    std::vector<Entry> entries_;  // a cut triangle has a few dozen points at most: a linear scan
  };

  /// Epeck with an orientation predicate that answers COLLINEAR for three points on a known line
  /// (KnownLines) when the interval filter cannot decide, before evaluating exactly. The answer
  /// is the exact one either way, so the triangulation is the same, only cheaper.
  struct CdtTraits : EK {
    const KnownLines* known = nullptr;
    class Orientation_2 {
     public:
      explicit Orientation_2(const KnownLines* known) : known_(known) {}
      CGAL::Orientation operator()(const EK::Point_2& p, const EK::Point_2& q, const EK::Point_2& r) const {
        {
          const CGAL::Protect_FPU_rounding<true> rounding;
          const auto &ap = p.approx(), &aq = q.approx(), &ar = r.approx();
          const CGAL::Uncertain<CGAL::Orientation> o =
              CGAL::orientationC2(ap.x(), ap.y(), aq.x(), aq.y(), ar.x(), ar.y());
          if (CGAL::is_certain(o)) return CGAL::get_certain(o);
        }
        if (known_ != nullptr && known_->collinear(p, q, r)) return CGAL::COLLINEAR;
        return EK().orientation_2_object()(p, q, r);
      }

     private:
      const KnownLines* known_;
    };
    [[nodiscard]] Orientation_2 orientation_2_object() const { return Orientation_2(known); }
  };

  using Vb = CGAL::Triangulation_vertex_base_with_info_2<std::uint32_t, CdtTraits>;
  using Fb = CGAL::Constrained_triangulation_face_base_2<CdtTraits>;
  using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
  using CDT = CGAL::Constrained_Delaunay_triangulation_2<CdtTraits, Tds, CGAL::No_constraint_intersection_tag>;

  void add_boundary_edge(std::uint32_t p, std::uint32_t q, std::uint32_t sub) {
    auto [it, inserted] = boundary_.try_emplace(pair_key(p, q), sub);
    if (!inserted) {
      m_->uncut_adjacent.push_back({it->second, sub});
      boundary_.erase(it);
    }
  }

  /// The triangulation of one cut triangle, in local face numbers (computed in parallel, merged
  /// in triangle order so that the output does not depend on the thread count).
  struct LocalCut {
    std::vector<Triangle> faces;                              // point ids, oriented like the input
    std::vector<std::array<std::uint32_t, 2>> inner;          // faces sharing an uncut edge
    std::vector<std::array<std::uint32_t, 3>> boundary;       // (point, point, face) on input edges
    struct Piece {
      std::uint32_t segment, p, q, positive_face, negative_face;
    };
    std::vector<Piece> pieces;
    bool failed = false;
    std::string problem;
  };

  /// Puts the faces of a cut triangle in a canonical order: each face starts at its smallest
  /// point id (orientation kept) and the faces are sorted by their ids; the face numbers in the
  /// adjacency lists and pieces follow, and those lists are sorted too. The order the CDT's
  /// container hands out its faces, and the corner each starts at, are not reproducible when the
  /// triangulations run on several threads (measured: the quintuple torus swapped two faces of
  /// one triangle, one of them rotated, between runs), and every later stage, TetGen above all,
  /// depends on the order of the cut triangles.
  static void canonicalize(LocalCut& lc) {
    const std::size_t n = lc.faces.size();
    for (Triangle& f : lc.faces) std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
    std::vector<std::uint32_t> order(n), rank(n);
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) { return lc.faces[x] < lc.faces[y]; });
    std::vector<Triangle> faces(n);
    for (std::size_t i = 0; i < n; ++i) {
      rank[order[i]] = static_cast<std::uint32_t>(i);
      faces[i] = lc.faces[order[i]];
    }
    lc.faces = std::move(faces);
    for (auto& pair : lc.inner) {
      pair = {rank[pair[0]], rank[pair[1]]};
      if (pair[0] > pair[1]) std::swap(pair[0], pair[1]);
    }
    std::sort(lc.inner.begin(), lc.inner.end());
    for (auto& edge : lc.boundary) edge[2] = rank[edge[2]];
    std::sort(lc.boundary.begin(), lc.boundary.end());
    for (LocalCut::Piece& piece : lc.pieces) {
      piece.positive_face = rank[piece.positive_face];
      piece.negative_face = rank[piece.negative_face];
    }
  }

  void triangulate_all(unsigned threads) {
    std::vector<std::uint32_t> cut;
    for (std::uint32_t t = 0; t < s_.triangle_count(); ++t)
      if (!tri_segments_[t].empty()) cut.push_back(t);
    std::vector<LocalCut> local(cut.size());
    parallel_for(threads, cut.size(), [&](std::size_t i, unsigned) {
      local[i] = triangulate(cut[i]);
      if (!local[i].failed) canonicalize(local[i]);
    });
    m_->first_sub_triangle.assign(s_.triangle_count() + 1, 0);
    boundary_.reserve(s_.triangle_count());
    std::size_t next = 0;
    for (std::uint32_t t = 0; t < s_.triangle_count(); ++t) {
      const auto base = static_cast<std::uint32_t>(m_->triangles.size());
      m_->first_sub_triangle[t] = base;
      if (tri_segments_[t].empty()) {
        m_->triangles.push_back(s_.triangles[t]);
        m_->triangle_source.push_back(t);
        for (int k = 0; k < 3; ++k) add_boundary_edge(s_.triangles[t][k], s_.triangles[t][(k + 1) % 3], base);
        continue;
      }
      const LocalCut& lc = local[next++];
      if (lc.failed) {
        const Triangle& tri = s_.triangles[t];
        defect(DefectKind::TriplePoint, lc.problem + " on " + describe_triangle(t) + " (non-generic)", {t},
               {tri[0], tri[1], tri[2]});
        continue;
      }
      for (const Triangle& f : lc.faces) {
        m_->triangles.push_back({sheet_vertex(f[0], t), sheet_vertex(f[1], t), sheet_vertex(f[2], t)});
        m_->triangle_source.push_back(t);
      }
      for (const auto& [a, b] : lc.inner) m_->uncut_adjacent.push_back({base + a, base + b});
      for (const auto& [p, q, f] : lc.boundary) add_boundary_edge(p, q, base + f);
      for (const LocalCut::Piece& lp : lc.pieces) {
        const Segment& seg = segments_[lp.segment];
        const int sheet = seg.triangles[0] == t ? 0 : 1;
        CutPiece& piece = piece_for(lp.p, lp.q, seg);
        piece.side[sheet][0] = base + lp.positive_face;
        piece.side[sheet][1] = base + lp.negative_face;
        ++piece_sheets_[&piece - m_->pieces.data()];
      }
    }
    m_->first_sub_triangle[s_.triangle_count()] = static_cast<std::uint32_t>(m_->triangles.size());
    if (defects_.empty()) {
      IMM_ASSERT(boundary_.empty(), "sub-edges on input edges do not match between neighbouring triangles");
    }
  }

  /// Triangulates cut triangle t with its boundary points and its subdivided segments as
  /// constraints. Reads only shared immutable state (safe to run concurrently: CGAL 5.5's lazy
  /// exact numbers evaluate under std::call_once).
  /// The common case without a triangulation: one intersection segment crossing the triangle
  /// from one edge to another (two boundary points, no interior point). The chord cuts the
  /// triangle into a triangle and a convex quadrilateral, split along a diagonal; every face
  /// follows the boundary order, so it is oriented like the input triangle. Only the side of
  /// the chord the positive corner lies on needs a predicate (exact, filtered).
  /// @return nullopt when the triangle is not of that kind (the caller triangulates it).
  std::optional<LocalCut> single_chord(std::uint32_t t, const std::vector<std::uint32_t>& ring,
                                       const Projection& pr) const {
    const std::uint32_t s = tri_segments_[t].front();
    const Segment& seg = segments_[s];
    const int sheet = seg.triangles[0] == t ? 0 : 1;
    const auto& pts = seg_points_[s * 2 + sheet];
    if (pts.size() != 2) return std::nullopt;
    const auto at = [&](std::uint32_t id) {
      return static_cast<std::size_t>(std::find(ring.begin(), ring.end(), id) - ring.begin());
    };
    const std::size_t ip = at(pts[0]), iq = at(pts[1]);
    if (ip == ring.size() || iq == ring.size()) return std::nullopt;
    LocalCut out;
    // a: the ring from P forward to Q (closed by Q -> P); b: from Q forward to P (closed by P -> Q).
    const auto fan = [&](std::size_t from, std::size_t to) {
      std::vector<std::uint32_t> poly;
      for (std::size_t i = from;; i = (i + 1) % ring.size()) {
        poly.push_back(ring[i]);
        if (i == to) break;
      }
      const auto first = static_cast<std::uint32_t>(out.faces.size());
      for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
        const auto face = static_cast<std::uint32_t>(out.faces.size());
        out.faces.push_back({poly[0], poly[k], poly[k + 1]});
        if (k > 1) out.inner.push_back({face - 1, face});
      }
      // Boundary edges (every polygon edge but the closing chord) with their faces.
      for (std::size_t k = 0; k + 1 < poly.size(); ++k) {
        const std::uint32_t face = k == 0 ? first : first + static_cast<std::uint32_t>(std::max<std::size_t>(k, 1) - 1);
        out.boundary.push_back({poly[k], poly[k + 1], face});
      }
      return static_cast<std::uint32_t>(out.faces.size() - 1);  // the face holding the chord
    };
    const std::uint32_t right = fan(ip, iq);  // right of P -> Q
    const std::uint32_t left = fan(iq, ip);   // left of P -> Q
    const EK::Point_2 corner = project(m_->points[s_.triangles[t][seg.positive_corner[sheet]]], pr.drop);
    const bool left_in_projection =
        CGAL::orientation(project(m_->points[pts[0]], pr.drop), project(m_->points[pts[1]], pr.drop), corner) ==
        CGAL::LEFT_TURN;
    const bool left_is_positive = left_in_projection != pr.flipped;
    out.pieces.push_back({s, pts[0], pts[1], left_is_positive ? left : right, left_is_positive ? right : left});
    return out;
  }

  LocalCut triangulate(std::uint32_t t) const {
    LocalCut out;
    const Projection pr = projection_of(t);
    const Triangle& tri = s_.triangles[t];
    KnownLines known;
    CdtTraits traits;
    traits.known = &known;
    CDT cdt(traits);
    std::unordered_map<std::uint32_t, CDT::Vertex_handle> handle;
    CDT::Face_handle hint;
    bool coincident = false;
    auto insert = [&](std::uint32_t id) {
      if (handle.count(id)) return;
      const std::size_t before = cdt.number_of_vertices();
      const EK::Point_2 point = project(m_->points[id], pr.drop);
      known.set_point(id, point);
      CDT::Vertex_handle v = cdt.insert(point, hint);
      if (cdt.number_of_vertices() == before) coincident = true;
      v->info() = id;
      handle.emplace(id, v);
      hint = v->face();
    };
    // Boundary: corners and the crossing points on each edge, in order around the triangle.
    std::vector<std::uint32_t> ring;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t e = m_->triangle_edges[t][k];
      ring.push_back(tri[k]);
      const auto& list = edge_points_[e];
      if (tri[k] == m_->edges[e].v0) ring.insert(ring.end(), list.begin(), list.end());
      else ring.insert(ring.end(), list.rbegin(), list.rend());
    }
    if (tri_segments_[t].size() == 1 && ring.size() == 5) {
      if (auto fast = single_chord(t, ring, pr)) return std::move(*fast);
    }
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t e = m_->triangle_edges[t][k];
      known.add(tri[k], KnownLines::edge_line(e));
      known.add(tri[(k + 1) % 3], KnownLines::edge_line(e));
      for (std::uint32_t id : edge_points_[e]) known.add(id, KnownLines::edge_line(e));
    }
    for (std::uint32_t s : tri_segments_[t]) {
      for (std::uint32_t id : seg_points_[s * 2 + (segments_[s].triangles[0] == t ? 0 : 1)])
        known.add(id, KnownLines::segment_line(s));
    }
    for (std::uint32_t id : ring) insert(id);
    for (std::uint32_t s : tri_segments_[t]) {
      for (std::uint32_t id : seg_points_[s * 2 + (segments_[s].triangles[0] == t ? 0 : 1)]) insert(id);
    }
    if (coincident) {
      out.failed = true;
      out.problem = "two distinct intersection points coincide";
      return out;
    }
    try {
      for (std::size_t i = 0; i < ring.size(); ++i) {
        cdt.insert_constraint(handle[ring[i]], handle[ring[(i + 1) % ring.size()]]);
      }
      for (std::uint32_t s : tri_segments_[t]) {
        const auto& pts = seg_points_[s * 2 + (segments_[s].triangles[0] == t ? 0 : 1)];
        for (std::size_t i = 0; i + 1 < pts.size(); ++i) cdt.insert_constraint(handle[pts[i]], handle[pts[i + 1]]);
      }
    } catch (const std::exception&) {
      out.failed = true;
      out.problem = "the intersection curves meet in a way that is not a crossing";
      return out;
    }
    std::unordered_map<CDT::Face_handle, std::uint32_t> local;
    for (CDT::Face_handle f : cdt.finite_face_handles()) {
      local.emplace(f, static_cast<std::uint32_t>(out.faces.size()));
      Triangle st{f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()};
      if (pr.flipped) std::swap(st[1], st[2]);
      out.faces.push_back(st);
    }
    for (CDT::Face_handle f : cdt.finite_face_handles()) {
      const std::uint32_t lf = local[f];
      for (int i = 0; i < 3; ++i) {
        CDT::Face_handle g = f->neighbor(i);
        if (cdt.is_infinite(g)) {
          out.boundary.push_back({f->vertex(CDT::ccw(i))->info(), f->vertex(CDT::cw(i))->info(), lf});
        } else if (!f->is_constrained(i) && lf < local[g]) {
          out.inner.push_back({lf, local[g]});
        }
      }
    }
    // Cut pieces: the sub-triangles on both sides of every piece of every segment.
    for (std::uint32_t s : tri_segments_[t]) {
      const Segment& seg = segments_[s];
      const int sheet = seg.triangles[0] == t ? 0 : 1;
      const auto& pts = seg_points_[s * 2 + sheet];
      const EK::Point_2 corner = project(m_->points[tri[seg.positive_corner[sheet]]], pr.drop);
      const bool left_is_positive =
          CGAL::orientation(project(m_->points[seg.ends[0]], pr.drop), project(m_->points[seg.ends[1]], pr.drop),
                            corner) == CGAL::LEFT_TURN;
      for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
        CDT::Face_handle fr;
        int idx = 0;
        const bool is_edge = cdt.is_edge(handle[pts[i]], handle[pts[i + 1]], fr, idx);
        IMM_ASSERT(is_edge, "a constrained piece is missing from the triangulation");
        CDT::Face_handle left = fr, right = fr->neighbor(idx);
        if (fr->vertex(CDT::ccw(idx)) != handle[pts[i]]) std::swap(left, right);
        IMM_ASSERT(!cdt.is_infinite(left) && !cdt.is_infinite(right), "a cut piece on the triangle boundary");
        const std::uint32_t lp = local[left], rp = local[right];
        out.pieces.push_back({s, pts[i], pts[i + 1], left_is_positive ? lp : rp, left_is_positive ? rp : lp});
      }
    }
    return out;
  }

  CutPiece& piece_for(std::uint32_t p, std::uint32_t q, const Segment& seg) {
    auto [it, inserted] = piece_index_.try_emplace(pair_key(p, q), static_cast<std::uint32_t>(m_->pieces.size()));
    if (inserted) {
      CutPiece piece;
      piece.points = {std::min(p, q), std::max(p, q)};
      piece.triangles = seg.triangles;
      piece.side = {{{kNone, kNone}, {kNone, kNone}}};
      m_->pieces.push_back(piece);
      piece_sheets_.push_back(0);
    }
    CutPiece& piece = m_->pieces[it->second];
    IMM_ASSERT(piece.triangles == seg.triangles, "one cut edge claimed by two triangle pairs");
    return piece;
  }

  void check_pieces() const {
    for (std::size_t i = 0; i < m_->pieces.size(); ++i) {
      IMM_ASSERT(piece_sheets_[i] == 2, "cut edge " + std::to_string(i) + " seen by " + std::to_string(piece_sheets_[i]) +
                                            " of its two sheets");
    }
  }

  void log(const std::string& m) const {
    if (progress_) progress_(m);
  }

  const Surface& s_;
  const LogCallback& progress_;
  unsigned threads_ = 1;
  CutMesh* m_ = nullptr;
  std::vector<IPoint> ipoints_;
  DefectSink defects_;
  std::vector<Segment> segments_;
  std::vector<std::vector<std::uint32_t>> tri_segments_;
  std::vector<std::vector<std::uint32_t>> edge_points_;  // sorted from v0 to v1
  std::unordered_map<std::uint64_t, std::uint32_t> edge_tri_index_;
  std::vector<std::array<std::uint32_t, 2>> pending_points_;  // (edge, triangle) of points without coordinates
  std::unordered_map<TripleKey, std::uint32_t, TripleHash> triples_;
  std::unordered_map<TripleKey, int, TripleHash> triple_seen_;
  std::vector<std::vector<std::uint32_t>> seg_points_;  // per (segment, sheet): ordered points
  std::vector<std::uint32_t> sheet_base_;
  std::unordered_map<std::uint64_t, std::uint32_t> boundary_;
  std::unordered_map<std::uint64_t, std::uint32_t> piece_index_;
  std::vector<int> piece_sheets_;
};

}  // namespace

RefineResult refine_surface(const Surface& surface, const LogCallback& progress, unsigned threads) {
  return Refiner(surface, progress, resolve_threads(threads)).run();
}

Rational six_signed_volume(const EK::Point_3& a, const EK::Point_3& b, const EK::Point_3& c) {
  const auto& ea = CGAL::exact(a);
  const auto& eb = CGAL::exact(b);
  const auto& ec = CGAL::exact(c);
  const Rational ax(ea.x()), ay(ea.y()), az(ea.z());
  const Rational bx(eb.x()), by(eb.y()), bz(eb.z());
  const Rational cx(ec.x()), cy(ec.y()), cz(ec.z());
  return ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
}

}  // namespace imm::dim3
