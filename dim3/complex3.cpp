// The 3D cell complex from the exact cut mesh (dim3/complex3.h): patches, arcs with their cyclic
// junction order, regions with winding numbers (nesting decided by exact ray casting), exact
// volumes and the genus of every region's boundary.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mpzf.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <sstream>

#include "core/exact_sum.h"
#include "core/union_find.h"
#include "dim3/complex3.h"
#include "dim3/cut_mesh.h"

namespace imm::dim3 {
namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

/// Exact 6 x signed volume of (origin, a, b, c) for double corners, in CGAL's dyadic Mpzf
/// (exact for +, -, x of doubles and much cheaper than GMP rationals).
CGAL::Mpzf six_volume_dyadic(const Point3& a, const Point3& b, const Point3& c) {
  const CGAL::Mpzf ax(a[0]), ay(a[1]), az(a[2]), bx(b[0]), by(b[1]), bz(b[2]), cx(c[0]), cy(c[1]), cz(c[2]);
  return ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
}

Rational to_rational(const CGAL::Mpzf& x) { return static_cast<mpq_class>(x); }

template <class Id>
Id as(std::uint32_t v) {
  return Id(static_cast<std::size_t>(v));
}

Point3 rounded(const EK::Point_3& p) {
  return {CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())};
}

/// The arcs of the cut mesh: maximal chains of cut pieces through points where exactly two
/// sheets meet, ending at triple points, or closed loops.
struct ArcChain {
  std::vector<std::uint32_t> pieces;
  std::vector<std::uint32_t> points;  // pieces.size() + 1 points; closed loops repeat the first
};

std::vector<ArcChain> chain_arcs(const CutMesh& m) {
  std::vector<std::vector<std::uint32_t>> incident(m.points.size());
  for (std::uint32_t i = 0; i < m.pieces.size(); ++i) {
    incident[m.pieces[i].points[0]].push_back(i);
    incident[m.pieces[i].points[1]].push_back(i);
  }
  for (std::uint32_t p = 0; p < m.points.size(); ++p) {
    const std::size_t want = m.origins[p].kind == PointOrigin::Kind::TriplePoint ? 6
                             : m.origins[p].kind == PointOrigin::Kind::EdgeTriangle ? 2
                                                                                   : 0;
    IMM_ASSERT(incident[p].size() == want, "cut point " + std::to_string(p) + " has " +
                                                 std::to_string(incident[p].size()) + " cut edges, expected " +
                                                 std::to_string(want));
  }
  std::vector<char> used(m.pieces.size(), 0);
  std::vector<ArcChain> arcs;
  auto walk = [&](std::uint32_t start_point, std::uint32_t first_piece) {
    ArcChain arc;
    arc.points.push_back(start_point);
    std::uint32_t p = start_point, e = first_piece;
    while (true) {
      used[e] = 1;
      arc.pieces.push_back(e);
      p = m.pieces[e].points[0] == p ? m.pieces[e].points[1] : m.pieces[e].points[0];
      arc.points.push_back(p);
      if (incident[p].size() != 2 || p == start_point) break;
      e = incident[p][0] == e ? incident[p][1] : incident[p][0];
      if (used[e]) break;
    }
    arcs.push_back(std::move(arc));
  };
  for (std::uint32_t p = 0; p < m.points.size(); ++p) {
    if (incident[p].size() != 6) continue;
    for (std::uint32_t e : incident[p])
      if (!used[e]) walk(p, e);
  }
  for (std::uint32_t e = 0; e < m.pieces.size(); ++e)
    if (!used[e]) walk(m.pieces[e].points[0], e);  // closed loops without triple points
  return arcs;
}

/// A segment from `from` through `through` to beyond `box`, intersected with the input triangles
/// in `triangles`. Exact: the classification uses Epick predicates on the input doubles (the
/// segment's ends are doubles too), the few hits are ordered with Epeck constructions.
struct RayHit {
  std::uint32_t sub_triangle = 0;
  bool from_positive_side = false;
};
struct RayResult {
  enum class Kind { Degenerate, Miss, Hit } kind = Kind::Degenerate;
  RayHit hit;
};

class RayCaster {
 public:
  using IK = CGAL::Exact_predicates_inexact_constructions_kernel;

  RayCaster(const Surface& s, const CutMesh& m) : s_(s), m_(m) {}

  RayResult cast(const Point3& from_d, const Point3& through, const Box3& box,
                 const std::vector<std::uint32_t>& triangles) const {
    // Far enough along the ray to leave the box.
    double span = 0.0, dir = 0.0;
    for (int d = 0; d < 3; ++d) {
      span = std::max({span, std::abs(box.hi[d] - from_d[d]), std::abs(box.lo[d] - from_d[d])});
      dir = std::max(dir, std::abs(through[d] - from_d[d]));
    }
    if (!(dir > 0.0)) return {};
    const double lambda = 2.0 * span / dir + 2.0;
    const IK::Point_3 from(from_d[0], from_d[1], from_d[2]);
    const IK::Point_3 far(from_d[0] + lambda * (through[0] - from_d[0]), from_d[1] + lambda * (through[1] - from_d[1]),
                          from_d[2] + lambda * (through[2] - from_d[2]));
    std::vector<std::pair<std::uint32_t, bool>> hits;  // (triangle, from on its positive side)
    for (std::uint32_t x : triangles) {
      const IK::Point_3 a = P(x, 0), b = P(x, 1), c = P(x, 2);
      const CGAL::Orientation s0 = CGAL::orientation(a, b, c, from), s1 = CGAL::orientation(a, b, c, far);
      if (s0 == CGAL::COPLANAR || s1 == CGAL::COPLANAR) {
        if (CGAL::do_intersect(IK::Segment_3(from, far), IK::Triangle_3(a, b, c))) return {};
        continue;
      }
      if (s0 == s1) continue;
      const CGAL::Orientation o0 = CGAL::orientation(from, far, a, b);
      const CGAL::Orientation o1 = CGAL::orientation(from, far, b, c);
      const CGAL::Orientation o2 = CGAL::orientation(from, far, c, a);
      const bool pos = o0 == CGAL::POSITIVE || o1 == CGAL::POSITIVE || o2 == CGAL::POSITIVE;
      const bool neg = o0 == CGAL::NEGATIVE || o1 == CGAL::NEGATIVE || o2 == CGAL::NEGATIVE;
      if (pos && neg) continue;
      if (o0 == CGAL::COLLINEAR || o1 == CGAL::COLLINEAR || o2 == CGAL::COLLINEAR) return {};  // edge or vertex
      hits.push_back({x, s0 == CGAL::POSITIVE});
    }
    if (hits.empty()) return {RayResult::Kind::Miss, {}};
    const EK::Point_3 efrom(from_d[0], from_d[1], from_d[2]);
    const EK::Line_3 line(efrom, EK::Point_3(far.x(), far.y(), far.z()));
    auto hit_point = [&](std::uint32_t x) {
      const auto r = CGAL::intersection(line, EK::Plane_3(m_.points[s_.triangles[x][0]], m_.points[s_.triangles[x][1]],
                                                          m_.points[s_.triangles[x][2]]));
      return *boost::get<EK::Point_3>(&*r);
    };
    std::size_t best = 0;
    EK::Point_3 best_point = hit_point(hits[0].first);
    bool tie = false;
    for (std::size_t i = 1; i < hits.size(); ++i) {
      const EK::Point_3 p = hit_point(hits[i].first);
      const CGAL::Comparison_result cmp = CGAL::compare_distance_to_point(efrom, p, best_point);
      if (cmp == CGAL::SMALLER) {
        best = i;
        best_point = p;
        tie = false;
      } else if (cmp == CGAL::EQUAL) {
        tie = true;  // on an intersection curve: try another ray
      }
    }
    if (tie) return {};
    const std::uint32_t x = hits[best].first;
    for (std::uint32_t t = m_.first_sub_triangle[x]; t < m_.first_sub_triangle[x + 1]; ++t) {
      const EK::Point_3& a = m_.points[m_.vertex_point[m_.triangles[t][0]]];
      const EK::Point_3& b = m_.points[m_.vertex_point[m_.triangles[t][1]]];
      const EK::Point_3& c = m_.points[m_.vertex_point[m_.triangles[t][2]]];
      if (CGAL::coplanar_orientation(a, b, c, best_point) == CGAL::POSITIVE &&
          CGAL::coplanar_orientation(b, c, a, best_point) == CGAL::POSITIVE &&
          CGAL::coplanar_orientation(c, a, b, best_point) == CGAL::POSITIVE) {
        return {RayResult::Kind::Hit, {t, hits[best].second}};
      }
    }
    return {};  // on a sub-triangle edge: try another ray
  }

 private:
  IK::Point_3 P(std::uint32_t t, int k) const {
    const Point3& p = s_.vertices[s_.triangles[t][k]];
    return {p[0], p[1], p[2]};
  }
  const Surface& s_;
  const CutMesh& m_;
};

class ComplexBuilder {
 public:
  ComplexBuilder(const Surface& s, const CutMesh& m, const BuildOptions& o) : s_(s), m_(m), options_(o) {}

  /// @return false when a region has a negative winding number (result.inversion is set then).
  void build(Complex& out, std::optional<Inversion>& inversion, bool& all_nonpositive) {
    find_patches();
    arcs_ = chain_arcs(m_);
    glue_wedges();
    find_groups();
    relative_windings();
    place_groups();
    assign_regions();
    log("complex: " + std::to_string(patch_count_) + " patches, " + std::to_string(arcs_.size()) + " arcs, " +
        std::to_string(region_winding_.size()) + " regions in " + std::to_string(group_count_) + " group(s)");
    all_nonpositive = true;
    bool any_negative = false;
    for (RegionId r : ids<RegionId>(region_winding_.size())) {
      if (region_winding_[r] > 0) all_nonpositive = false;
      if (region_winding_[r] < 0 && !any_negative) {
        any_negative = true;
        inversion = describe_inversion(r);
      }
    }
    if (any_negative) return;
    emit(out);
  }

 private:
  // ---- patches: sub-triangles connected across uncut edges --------------------------------

  void find_patches() {
    const std::size_t n = m_.triangles.size();
    UnionFind uf(n);
    for (const auto& [a, b] : m_.uncut_adjacent) uf.unite(a, b);
    patch_of_.assign(n, kNone);
    std::vector<std::uint32_t> root_patch(n, kNone);
    for (std::uint32_t t = 0; t < n; ++t) {
      std::uint32_t& p = root_patch[uf.find(t)];
      if (p == kNone) p = patch_count_++;
      patch_of_[t] = p;
    }
  }

  std::uint32_t side_node(std::uint32_t patch, bool negative) const { return 2 * patch + (negative ? 1 : 0); }

  // ---- arcs: the four junctions in cyclic order and the wedges between them -----------------
  //
  // At a cut piece of sheets A and B, look along d = n_A x n_B. In the plane orthogonal to d the
  // four half-sheets alternate; counter-clockwise about d they are
  //     A+ (A's half on B's positive side), B- (B's half on A's negative side), A-, B+,
  // which one checks with n_A = x, n_B = y, d = z: A+ = +y, B- = -x, A- = -y, B+ = +x.
  // Wedge k lies between junction k and k+1: w0 = (A-side, B+side), w1 = (A-, B-),
  // w2 = (A+, B-), w3 = (A+, B+), where "A-side" is the negative side of A's plane.

  void glue_wedges() {
    sides_ = UnionFind(2 * patch_count_);
    junctions_.resize(arcs_.size());
    for (std::size_t i = 0; i < arcs_.size(); ++i) {
      const CutPiece& piece = m_.pieces[arcs_[i].pieces.front()];
      const std::uint32_t a_pos = patch_of_[piece.side[0][0]], a_neg = patch_of_[piece.side[0][1]];
      const std::uint32_t b_pos = patch_of_[piece.side[1][0]], b_neg = patch_of_[piece.side[1][1]];
      junctions_[i] = {a_pos, b_neg, a_neg, b_pos};
      // wedge node pairs: w0 = A+ negative side | B- positive side, etc.
      wedge_nodes_.push_back({side_node(a_pos, true), side_node(b_neg, false)});
      wedge_nodes_.push_back({side_node(b_neg, true), side_node(a_neg, true)});
      wedge_nodes_.push_back({side_node(a_neg, false), side_node(b_pos, true)});
      wedge_nodes_.push_back({side_node(b_pos, false), side_node(a_pos, false)});
      for (std::size_t k = wedge_nodes_.size() - 4; k < wedge_nodes_.size(); ++k)
        sides_.unite(wedge_nodes_[k][0], wedge_nodes_[k][1]);
    }
  }

  // ---- groups: sheets connected through arcs --------------------------------------------------

  void find_groups() {
    UnionFind uf(patch_count_);
    for (const auto& j : junctions_) {
      uf.unite(j[0], j[1]);
      uf.unite(j[0], j[2]);
      uf.unite(j[0], j[3]);
    }
    group_of_patch_.assign(patch_count_, kNone);
    std::vector<std::uint32_t> root_group(patch_count_, kNone);
    for (std::uint32_t p = 0; p < patch_count_; ++p) {
      std::uint32_t& g = root_group[uf.find(p)];
      if (g == kNone) g = group_count_++;
      group_of_patch_[p] = g;
    }
    group_triangles_.assign(group_count_, {});
    group_box_.assign(group_count_, Box3{});
    std::vector<char> seen(group_count_, 0);
    for (std::uint32_t t = 0; t < s_.triangle_count(); ++t) {
      const std::uint32_t g = group_of_patch_[patch_of_[m_.first_sub_triangle[t]]];
      group_triangles_[g].push_back(t);
      for (std::uint32_t v : s_.triangles[t]) {
        const Point3& p = s_.vertices[v];
        Box3& b = group_box_[g];
        if (!seen[g]) {
          b.lo = b.hi = p;
          seen[g] = 1;
        }
        for (int d = 0; d < 3; ++d) {
          b.lo[d] = std::min(b.lo[d], p[d]);
          b.hi[d] = std::max(b.hi[d], p[d]);
        }
      }
    }
  }

  // ---- winding numbers within each group ------------------------------------------------------

  void relative_windings() {
    // Classes of patch sides: the regions of each group's own arrangement (the boundary of a
    // complementary domain of a connected set in R^3 is connected, so one class = one region).
    const std::size_t nodes = 2 * patch_count_;
    class_of_node_.assign(nodes, kNone);
    std::vector<std::uint32_t> root_class(nodes, kNone);
    for (std::uint32_t v = 0; v < nodes; ++v) {
      std::uint32_t& c = root_class[sides_.find(v)];
      if (c == kNone) {
        c = static_cast<std::uint32_t>(class_group_.size());
        class_group_.push_back(group_of_patch_[v / 2]);
      }
      class_of_node_[v] = c;
    }
    // relative winding: +1 across every patch against its normal; BFS per group.
    const std::size_t classes = class_group_.size();
    std::vector<std::vector<std::pair<std::uint32_t, int>>> adj(classes);
    for (std::uint32_t p = 0; p < patch_count_; ++p) {
      const std::uint32_t pos = class_of_node_[side_node(p, false)], neg = class_of_node_[side_node(p, true)];
      adj[pos].push_back({neg, +1});
      adj[neg].push_back({pos, -1});
    }
    relative_.assign(classes, std::numeric_limits<int>::min());
    for (std::uint32_t c = 0; c < classes; ++c) {
      if (relative_[c] != std::numeric_limits<int>::min()) continue;
      relative_[c] = 0;
      std::vector<std::uint32_t> stack{c};
      while (!stack.empty()) {
        const std::uint32_t x = stack.back();
        stack.pop_back();
        for (const auto& [y, d] : adj[x]) {
          if (relative_[y] == std::numeric_limits<int>::min()) {
            relative_[y] = relative_[x] + d;
            stack.push_back(y);
          } else {
            IMM_ASSERT(relative_[y] == relative_[x] + d, "inconsistent winding numbers around a region");
          }
        }
      }
    }
  }

  // ---- each group's outside, and nesting between groups (exact ray casting) -------------------

  /// A ray from `from` through (roughly) the centroid of a triangle of group g, different for
  /// each attempt.
  RayResult cast_to_group(const Point3& from, std::uint32_t g, std::uint32_t attempt) const {
    const auto& tris = group_triangles_[g];
    const std::uint32_t t = tris[(static_cast<std::uint64_t>(attempt) * 7919u + tris.size() / 2) % tris.size()];
    Point3 through{0, 0, 0};
    const double w[3] = {0.31 + 0.01 * (attempt % 7), 0.37, 0.32 - 0.01 * (attempt % 7)};
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) through[d] += w[k] * s_.vertices[s_.triangles[t][k]][d];
    return RayCaster(s_, m_).cast(from, through, group_box_[g], tris);
  }

  std::uint32_t class_hit(const RayHit& h) const {
    return class_of_node_[side_node(patch_of_[h.sub_triangle], !h.from_positive_side)];
  }

  void place_groups() {
    outer_class_.assign(group_count_, kNone);
    for (std::uint32_t g = 0; g < group_count_; ++g) {
      const Box3& b = group_box_[g];
      const double dx = b.hi[0] - b.lo[0] + 1.0, dy = b.hi[1] - b.lo[1], dz = b.hi[2] - b.lo[2];
      const Point3 from{b.lo[0] - 0.5 * dx - 1.0, b.lo[1] + 0.3711 * dy, b.lo[2] + 0.6173 * dz};
      for (std::uint32_t attempt = 0; attempt < 64 && outer_class_[g] == kNone; ++attempt) {
        const RayResult r = cast_to_group(from, g, attempt);
        if (r.kind == RayResult::Kind::Hit) outer_class_[g] = class_hit(r.hit);
      }
      IMM_ASSERT(outer_class_[g] != kNone, "no generic ray found to the outside of a surface group");
    }
    // container_[g]: the class of another group whose bounded region holds group g, or kNone.
    std::vector<std::vector<std::uint32_t>> candidates(group_count_);
    for (std::uint32_t g = 0; g < group_count_ && group_count_ > 1; ++g) {
      const Point3& v = s_.vertices[s_.triangles[group_triangles_[g].front()][0]];
      for (std::uint32_t h = 0; h < group_count_; ++h) {
        if (h == g) continue;
        const Box3& b = group_box_[h];
        if (v[0] < b.lo[0] || v[0] > b.hi[0] || v[1] < b.lo[1] || v[1] > b.hi[1] || v[2] < b.lo[2] || v[2] > b.hi[2])
          continue;
        std::uint32_t cls = kNone;
        bool outside = false;
        for (std::uint32_t attempt = 0; attempt < 64 && cls == kNone && !outside; ++attempt) {
          const RayResult r = cast_to_group(v, h, attempt);
          if (r.kind == RayResult::Kind::Hit) cls = class_hit(r.hit);
          outside = r.kind == RayResult::Kind::Miss;  // a ray leaving h's box without a hit
        }
        IMM_ASSERT(cls != kNone || outside, "no generic ray found between two surface groups");
        if (cls != kNone && cls != outer_class_[h]) candidates[g].push_back(cls);
      }
    }
    // The tightest container is the candidate whose own group is nested deepest.
    container_.assign(group_count_, kNone);
    for (std::uint32_t g = 0; g < group_count_; ++g) {
      std::size_t best_depth = 0;
      for (std::uint32_t cls : candidates[g]) {
        const std::size_t depth = candidates[class_group_[cls]].size() + 1;
        if (depth > best_depth) {
          best_depth = depth;
          container_[g] = cls;
        }
      }
      depth_.push_back(candidates[g].size());
    }
  }

  // ---- regions: classes merged across nesting, absolute winding numbers ----------------------

  void assign_regions() {
    const std::size_t classes = class_group_.size();
    std::vector<std::vector<std::uint32_t>> group_classes(group_count_);
    for (std::uint32_t c = 0; c < classes; ++c) group_classes[class_group_[c]].push_back(c);
    // Groups by increasing nesting depth: a container's regions exist before its contents'.
    std::vector<std::uint32_t> order(group_count_);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return depth_[a] < depth_[b]; });
    region_of_class_.assign(classes, kNone);
    region_winding_.push_back(0);  // region 0: the unbounded one
    for (std::uint32_t g : order) {
      const std::uint32_t outer = outer_class_[g];
      int offset = -relative_[outer];
      if (container_[g] == kNone) {
        region_of_class_[outer] = 0;
      } else {
        const std::uint32_t r = region_of_class_[container_[g]];
        IMM_ASSERT(r != kNone, "a container region was not placed before its contents");
        region_of_class_[outer] = r;
        offset += region_winding_[as<RegionId>(r)];
      }
      for (std::uint32_t c : group_classes[g]) {
        if (c == outer) continue;
        region_of_class_[c] = static_cast<std::uint32_t>(region_winding_.size());
        region_winding_.push_back(relative_[c] + offset);
      }
    }
  }

  Inversion describe_inversion(RegionId r) const {
    Inversion inv;
    inv.region = r;
    inv.winding_number = region_winding_[r];
    for (std::uint32_t t = 0; t < m_.triangles.size() && inv.triangles.size() < 8; ++t) {
      const std::uint32_t p = patch_of_[t];
      if (region_of_class_[class_of_node_[side_node(p, false)]] == static_cast<std::uint32_t>(r.value()) ||
          region_of_class_[class_of_node_[side_node(p, true)]] == static_cast<std::uint32_t>(r.value())) {
        const long src = m_.triangle_source[t];
        if (inv.triangles.empty() || inv.triangles.back() != src) inv.triangles.push_back(src);
      }
    }
    std::ostringstream os;
    os << "a region has winding number " << inv.winding_number
       << ": the surface folds or turns inside out there (paper §3: no inversions); it is bounded by triangles";
    for (long t : inv.triangles) os << ' ' << t;
    inv.message = os.str();
    return inv;
  }

  // ---- output ------------------------------------------------------------------------------

  /// A sheet vertex in doubles (exact for input vertices, rounded for constructed points).
  Point3 approx_point(std::uint32_t sheet_vertex) const {
    const std::uint32_t p = m_.vertex_point[sheet_vertex];
    return p < s_.vertex_count() ? s_.vertices[p] : rounded(m_.points[p]);
  }

  std::uint32_t region_of_side(std::uint32_t patch, bool negative) const {
    return region_of_class_[class_of_node_[side_node(patch, negative)]];
  }

  void emit(Complex& out) {
    const std::size_t regions = region_winding_.size();
    // Volumes: sum over boundary sub-triangles of the signed cone volumes from the origin
    // (negative side = inside: +, positive side = outside: -). Exactly: sub-triangles with only
    // input corners in exact dyadic arithmetic, the others in GMP rationals of the constructed
    // points; or in doubles when exact volumes were not asked for.
    std::vector<std::vector<Rational>> terms(regions);
    std::vector<CGAL::Mpzf> dyadic(regions, CGAL::Mpzf(0));
    std::vector<double> approx(regions, 0.0);
    const std::uint32_t input_vertices = static_cast<std::uint32_t>(s_.vertex_count());
    // Doubles overflow for coordinates beyond about 5e102 (a cube of them passes DBL_MAX): then
    // the volumes are computed exactly after all, never converted from an infinity.
    bool exact_volumes = options_.exact_volumes;
    if (!exact_volumes) {
      for (std::uint32_t t = 0; t < m_.triangles.size() && !exact_volumes; ++t) {
        const Triangle& st = m_.triangles[t];
        const std::uint32_t neg = region_of_side(patch_of_[t], true), pos = region_of_side(patch_of_[t], false);
        const Point3 a = approx_point(st[0]), b = approx_point(st[1]), c = approx_point(st[2]);
        const double v = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                         a[2] * (b[0] * c[1] - b[1] * c[0]);
        approx[neg] += v;
        approx[pos] -= v;
        exact_volumes = !std::isfinite(approx[neg]) || !std::isfinite(approx[pos]);
      }
      if (exact_volumes) log("complex: volumes overflow doubles; computed exactly");
    }
    for (std::uint32_t t = 0; t < m_.triangles.size() && exact_volumes; ++t) {
      const Triangle& st = m_.triangles[t];
      const std::uint32_t neg = region_of_side(patch_of_[t], true), pos = region_of_side(patch_of_[t], false);
      if (st[0] < input_vertices && st[1] < input_vertices && st[2] < input_vertices) {
        const CGAL::Mpzf v = six_volume_dyadic(s_.vertices[st[0]], s_.vertices[st[1]], s_.vertices[st[2]]);
        dyadic[neg] += v;
        dyadic[pos] -= v;
      } else {
        const Rational v = six_signed_volume(m_.points[m_.vertex_point[st[0]]], m_.points[m_.vertex_point[st[1]]],
                                             m_.points[m_.vertex_point[st[2]]]);
        terms[neg].push_back(v);
        terms[pos].push_back(-v);
      }
    }
    log(std::string("complex: volumes ") + (exact_volumes ? "(exact)" : "(doubles)"));
    std::vector<int> genus = region_genus();
    log("complex: genus of every region boundary");

    CellComplex<3>& cc = out.complex;
    for (std::uint32_t r = 0; r < regions; ++r) {
      Rational volume(0);
      if (r != 0 && exact_volumes) {
        terms[r].push_back(to_rational(dyadic[r]));
        volume = tree_sum(std::move(terms[r])) / 6;
      } else if (r != 0) {
        volume = Rational(approx[r] / 6);
      }
      cc.add_region(region_winding_[as<RegionId>(r)], volume, genus[r] == 0);
    }
    for (std::uint32_t p = 0; p < patch_count_; ++p) {
      cc.add_patch(PatchSides{as<RegionId>(region_of_side(p, false)), as<RegionId>(region_of_side(p, true))});
    }
    for (std::size_t i = 0; i < arcs_.size(); ++i) {
      ArcJunctions aj;
      for (int k = 0; k < 4; ++k) {
        aj.patch[k] = as<PatchId>(junctions_[i][k]);
        const auto& w = wedge_nodes_[4 * i + k];
        aj.wedge[k] = as<RegionId>(region_of_class_[class_of_node_[w[0]]]);
      }
      cc.add_arc(aj);
    }
    cc.finalize();

    // Geometry in doubles, for output and display.
    out.points.reserve(m_.points.size());
    out.points = s_.vertices;  // input vertices are exact doubles already
    for (std::size_t p = s_.vertex_count(); p < m_.points.size(); ++p) out.points.push_back(rounded(m_.points[p]));
    out.cut_point = m_.vertex_point;
    out.cut_vertices.reserve(m_.vertex_point.size());
    for (std::uint32_t p : m_.vertex_point) out.cut_vertices.push_back(out.points[p]);
    out.cut_triangles = m_.triangles;
    out.cut_triangle_source = m_.triangle_source;
    out.cut_triangle_patch.reserve(m_.triangles.size());
    out.patch_triangle_count = IdMap<PatchId, std::size_t>(patch_count_, 0);
    for (std::uint32_t t = 0; t < m_.triangles.size(); ++t) {
      out.cut_triangle_patch.push_back(as<PatchId>(patch_of_[t]));
      ++out.patch_triangle_count[as<PatchId>(patch_of_[t])];
    }
    for (const ArcChain& a : arcs_) out.arc_points.push_back(a.points);
    std::vector<char> seen(regions, 0);
    out.region_box = IdMap<RegionId, Box3>(regions, Box3{});
    for (std::uint32_t t = 0; t < m_.triangles.size(); ++t) {
      for (bool negative : {false, true}) {
        const std::uint32_t r = region_of_side(patch_of_[t], negative);
        Box3& b = out.region_box[as<RegionId>(r)];
        for (std::uint32_t v : m_.triangles[t]) {
          const Point3& p = out.cut_vertices[v];
          if (!seen[r]) {
            b.lo = b.hi = p;
            seen[r] = 1;
          }
          for (int d = 0; d < 3; ++d) {
            b.lo[d] = std::min(b.lo[d], p[d]);
            b.hi[d] = std::max(b.hi[d], p[d]);
          }
        }
      }
    }
    out.region_genus = IdMap<RegionId, int>(genus.size(), 0);
    for (std::uint32_t r = 0; r < genus.size(); ++r) out.region_genus[as<RegionId>(r)] = genus[r];
    out.intersecting_pairs = m_.intersecting_pairs;
    out.intersection_points = m_.edge_triangle_points;
    out.triple_points = m_.triple_points;
    out.cut_edges = m_.pieces.size();
    out.groups = group_count_;
    out.exact_volumes = exact_volumes;
  }

  /// Total genus of each region's boundary surface, made manifold by splitting it along the arcs
  /// (a region occupying two wedges of an arc gets two edges there) and at pinch vertices:
  /// per boundary component chi = 2 - 2 genus, so genus = (2 components - chi) / 2.
  std::vector<int> region_genus() const {
    const std::size_t regions = region_winding_.size();
    const std::size_t n = m_.triangles.size();
    // face node: (sub-triangle, side); corner node: (face node, corner)
    auto face = [](std::uint32_t t, bool negative) { return 2 * t + (negative ? 1u : 0u); };
    UnionFind faces(2 * n), corners(6 * n);
    std::vector<long> edge_count(regions, 0);
    auto corner_of = [&](std::uint32_t t, std::uint32_t point) {
      for (int k = 0; k < 3; ++k)
        if (m_.vertex_point[m_.triangles[t][k]] == point) return k;
      IMM_ASSERT(false, "corner not found");
      return 0;
    };
    auto glue = [&](std::uint32_t t1, bool n1, std::uint32_t t2, bool n2, std::uint32_t p, std::uint32_t q) {
      faces.unite(face(t1, n1), face(t2, n2));
      corners.unite(3 * face(t1, n1) + corner_of(t1, p), 3 * face(t2, n2) + corner_of(t2, p));
      corners.unite(3 * face(t1, n1) + corner_of(t1, q), 3 * face(t2, n2) + corner_of(t2, q));
      ++edge_count[region_of_side(patch_of_[t1], n1)];
    };
    for (const auto& [a, b] : m_.uncut_adjacent) {
      // the two shared points
      std::uint32_t shared[2], k = 0;
      for (std::uint32_t u : m_.triangles[a])
        for (std::uint32_t v : m_.triangles[b])
          if (u == v && k < 2) shared[k++] = m_.vertex_point[u];
      IMM_ASSERT(k == 2, "adjacent sub-triangles share " + std::to_string(k) + " vertices");
      for (bool negative : {false, true}) glue(a, negative, b, negative, shared[0], shared[1]);
    }
    // Around a cut piece the four wedges each join two sub-triangle sides (see glue_wedges).
    for (const CutPiece& piece : m_.pieces) {
      const std::uint32_t ap = piece.side[0][0], an = piece.side[0][1], bp = piece.side[1][0], bn = piece.side[1][1];
      const std::uint32_t p = piece.points[0], q = piece.points[1];
      glue(ap, true, bn, false, p, q);
      glue(bn, true, an, true, p, q);
      glue(an, false, bp, true, p, q);
      glue(bp, false, ap, false, p, q);
    }
    std::vector<long> chi(regions, 0), components(regions, 0);
    for (std::uint32_t t = 0; t < n; ++t) {
      for (bool negative : {false, true}) {
        const std::uint32_t r = region_of_side(patch_of_[t], negative);
        const std::uint32_t f = face(t, negative);
        chi[r] += 1;  // a face
        if (faces.find(f) == f) ++components[r];
        for (int k = 0; k < 3; ++k)
          if (corners.find(3 * f + k) == 3 * f + k) ++chi[r];  // a vertex (one representative corner)
      }
    }
    std::vector<int> genus(regions, 0);
    for (std::size_t r = 0; r < regions; ++r) {
      chi[r] -= edge_count[r];
      const long twice = 2 * components[r] - chi[r];
      IMM_ASSERT(twice >= 0 && twice % 2 == 0, "region boundary with odd Euler characteristic");
      genus[r] = static_cast<int>(twice / 2);
    }
    return genus;
  }

  void log(const std::string& m) const {
    if (options_.progress) options_.progress(m);
  }

  const Surface& s_;
  const CutMesh& m_;
  const BuildOptions& options_;
  std::vector<std::uint32_t> patch_of_;
  std::uint32_t patch_count_ = 0;
  std::vector<ArcChain> arcs_;
  std::vector<std::array<std::uint32_t, 4>> junctions_;
  std::vector<std::array<std::uint32_t, 2>> wedge_nodes_;  // 4 per arc
  UnionFind sides_;
  std::vector<std::uint32_t> group_of_patch_;
  std::uint32_t group_count_ = 0;
  std::vector<std::vector<std::uint32_t>> group_triangles_;
  std::vector<Box3> group_box_;
  std::vector<std::uint32_t> class_of_node_;
  std::vector<std::uint32_t> class_group_;
  std::vector<int> relative_;
  std::vector<std::uint32_t> outer_class_;
  std::vector<std::uint32_t> container_;
  std::vector<std::size_t> depth_;
  std::vector<std::uint32_t> region_of_class_;
  IdMap<RegionId, int> region_winding_;
};

std::size_t count_components(const Surface& s) {
  UnionFind uf(s.vertex_count());
  std::vector<char> used(s.vertex_count(), 0);
  for (const Triangle& t : s.triangles) {
    uf.unite(t[0], t[1]);
    uf.unite(t[0], t[2]);
    used[t[0]] = used[t[1]] = used[t[2]] = 1;
  }
  std::size_t n = 0;
  for (std::uint32_t v = 0; v < s.vertex_count(); ++v) n += used[v] && uf.find(v) == v;
  return n;
}

Surface flipped(const Surface& s) {
  Surface f = s;
  for (Triangle& t : f.triangles) std::swap(t[1], t[2]);
  return f;
}

}  // namespace

namespace {

/// The defects of one kind (listed ones) split from the rest.
ValidationReport take_kind(ValidationReport& report, DefectKind kind) {
  ValidationReport taken, rest;
  for (Defect& d : report.defects) (d.kind == kind ? taken : rest).add(std::move(d));
  rest.unlisted = report.unlisted;
  report = std::move(rest);
  return taken;
}

bool has_kind(const std::vector<std::pair<DefectKind, std::size_t>>& counts, DefectKind kind) {
  return std::any_of(counts.begin(), counts.end(), [&](const auto& c) { return c.first == kind && c.second > 0; });
}

void add_counts(std::vector<std::pair<DefectKind, std::size_t>>& into, const ValidationReport& report) {
  for (const Defect& d : report.defects) {
    auto it = std::find_if(into.begin(), into.end(), [&](const auto& c) { return c.first == d.kind; });
    if (it == into.end()) into.emplace_back(d.kind, 1);
    else ++it->second;
  }
}

/// The contact-resolving perturbation of a surface (core/perturbation.h): inward is against the
/// area-weighted normal of each vertex star (outward for a counter-clockwise-from-outside input;
/// reversed when the whole input is inside-out), keys mix each vertex's coordinates with its
/// neighbours' (independent of the vertex order, but for identical copies).
PerturbationSummary perturb_surface(Surface& s, const PerturbationAttempt& attempt) {
  const std::size_t n = s.vertex_count();
  std::vector<std::array<double, 3>> inward(n, {0, 0, 0});
  std::vector<std::uint64_t> own(n), link(n, 0), keys(n);
  for (std::size_t v = 0; v < n; ++v) own[v] = point_key(s.vertices[v]);
  for (const Triangle& t : s.triangles) {
    const Point3 &a = s.vertices[t[0]], &b = s.vertices[t[1]], &c = s.vertices[t[2]];
    const std::array<double, 3> u{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const std::array<double, 3> normal{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    for (int k = 0; k < 3; ++k) {
      for (int d = 0; d < 3; ++d) inward[t[k]][d] -= normal[d];
      link[t[k]] += mix64(own[t[(k + 1) % 3]]) + mix64(own[t[(k + 2) % 3]] ^ 0xA5A5A5A5ull);
    }
  }
  const double sign = signed_volume(s) < 0.0 ? -1.0 : 1.0;
  for (std::size_t v = 0; v < n; ++v) keys[v] = mix64(own[v] ^ mix64(link[v]));
  distinguish_equal_keys(keys);  // identical copies of a part get different offsets (they cross)
  for (std::size_t v = 0; v < n; ++v) {
    const double len = std::sqrt(inward[v][0] * inward[v][0] + inward[v][1] * inward[v][1] + inward[v][2] * inward[v][2]);
    for (int d = 0; d < 3; ++d) inward[v][d] = len > 0.0 && std::isfinite(len) ? sign * inward[v][d] / len : 0.0;
  }
  return perturb_points(s.vertices, inward, keys, attempt);
}

/// Only coincident vertices (two ids, one exact position): a contact, not a broken file. The
/// validator lists every kind it finds at least once, so the listed kinds are all the kinds.
bool only_coincident_vertices(const ValidationReport& report) {
  return !report.ok() && std::all_of(report.defects.begin(), report.defects.end(),
                                     [](const Defect& d) { return d.kind == DefectKind::DuplicateVertex; });
}

}  // namespace

namespace {

BuildResult build_once(const Surface& surface, const BuildOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  BuildResult result;
  const auto finish = [&]() -> BuildResult {
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return std::move(result);
  };
  result.report = validate_surface(surface);
  if (!result.report.ok() && (options.strict || !only_coincident_vertices(result.report))) return finish();

  // The generic path: the input itself, refined once (a generic input is never perturbed).
  const Surface* base = &surface;  // the perturbed copy (in result.contacts) when contacts were resolved
  RefineResult refined;
  if (result.report.ok()) refined = refine_surface(surface, options.progress, options.threads);
  if (!result.report.ok() || !refined.report.ok()) {
    Contacts contacts;
    contacts.found = std::move(result.report);
    add_counts(contacts.counts, contacts.found);
    result.report = {};
    if (has_kind(refined.counts, DefectKind::LocalFold)) {
      // A robust crossing inside a vertex star: no perturbation removes it (exit 3).
      result.folds = take_kind(refined.report, DefectKind::LocalFold);
      for (const auto& c : refined.counts)
        if (c.first == DefectKind::LocalFold && c.second > result.folds.defects.size())
          result.folds.unlisted = c.second - result.folds.defects.size();
    }
    for (Defect& d : refined.report.defects) contacts.found.add(std::move(d));
    contacts.found.unlisted += refined.report.unlisted;
    for (const auto& c : refined.counts)
      if (c.first != DefectKind::LocalFold) contacts.counts.push_back(c);
    if (!result.folds.ok() || options.strict) {
      if (options.strict && result.folds.ok()) result.report = std::move(contacts.found);
      else if (!contacts.counts.empty()) result.contacts = std::move(contacts);  // folds alone are no contacts
      return finish();
    }
    // Resolve: the first perturbation under which every exact decision is generic.
    ValidationReport last;
    for (const PerturbationAttempt& attempt : perturbation_schedule()) {
      ++contacts.attempts;
      Surface moved = surface;
      const PerturbationSummary summary = perturb_surface(moved, attempt);
      if (options.progress) {
        options.progress("contacts: perturbing by at most 2^-" + std::to_string(attempt.bits) +
                         " of the scale (seed " + std::to_string(attempt.seed) + ")");
      }
      ValidationReport valid = validate_surface(moved);
      if (!valid.ok()) {
        last = std::move(valid);
        continue;
      }
      RefineResult again = refine_surface(moved, options.progress, options.threads);
      if (!again.report.ok()) {
        last = std::move(again.report);
        continue;
      }
      contacts.perturbation = summary;
      contacts.resolved = std::move(moved);
      refined = std::move(again);
      break;
    }
    if (!contacts.perturbation) {
      // Every attempt still meets a contact or a fold: folds are verdicts, the rest defects.
      ValidationReport folds = take_kind(last, DefectKind::LocalFold);
      if (!folds.ok()) {
        result.folds = std::move(folds);
      } else {
        // The input's own contacts, in the user's coordinates (the perturbed ones would quote
        // coordinates that are in no file); the last attempt's defects are counted only.
        result.report = contacts.found;
        result.report.add(Defect{DefectKind::Touching, "intersect",
                                 "the input's exact contacts (above) were not resolved by " +
                                     std::to_string(contacts.attempts) + " perturbations (the last one still had " +
                                     std::to_string(last.total()) + " defects)",
                                 {}, {}, {}});
      }
      result.contacts = std::move(contacts);
      return finish();
    }
    result.contacts = std::move(contacts);
    base = &result.contacts->resolved;
  }

  for (int attempt = 0; attempt < 2; ++attempt) {
    const bool reversed = attempt == 1;
    const Surface input = reversed ? flipped(*base) : *base;
    if (reversed) {
      refined = refine_surface(input, options.progress, options.threads);
      IMM_ASSERT(refined.report.ok(), "flipping a generic surface made it non-generic");
    }
    auto c3 = std::make_shared<Complex>();
    std::optional<Inversion> inversion;
    bool all_nonpositive = false;
    ComplexBuilder(input, *refined.mesh, options).build(*c3, inversion, all_nonpositive);
    if (inversion && all_nonpositive && !reversed) continue;  // inside-out input: flip it once
    if (inversion) {
      result.inversion = std::move(inversion);
      break;
    }
    c3->surface = input;
    c3->reversed = reversed;
    c3->components = count_components(input);
    c3->exact = std::move(refined.mesh);
    result.complex = std::move(c3);
    break;
  }
  return finish();
}

}  // namespace

BuildResult build_complex(const Surface& surface, const BuildOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  BuildResult result = build_once(surface, options);
  if (result.folds.ok() || !options.repair_folds) return result;
  if (options.progress) options.progress("local folds: repairing (--repair-folds)");
  FoldRepair repair = repair_folds(surface, *options.repair_folds, options.threads);
  if (!repair.ok) {
    result.repair = std::move(repair);
    return result;
  }
  BuildResult repaired = build_once(repair.surface, options);
  repaired.repair = std::move(repair);
  repaired.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return repaired;
}

std::string format_cut_mesh_obj(const Complex& c3) {
  std::string out = "# immerse: the cut mesh (per-sheet vertices), one group per patch\n";
  char buf[128];
  for (const Point3& p : c3.cut_vertices) {
    std::snprintf(buf, sizeof buf, "v %.17g %.17g %.17g\n", p[0], p[1], p[2]);
    out += buf;
  }
  std::vector<std::uint32_t> order(c3.cut_triangles.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return c3.cut_triangle_patch[a] < c3.cut_triangle_patch[b]; });
  PatchId current;
  for (std::uint32_t t : order) {
    if (c3.cut_triangle_patch[t] != current) {
      current = c3.cut_triangle_patch[t];
      out += "g patch_" + std::to_string(current.value()) + "\n";
    }
    const Triangle& tri = c3.cut_triangles[t];
    std::snprintf(buf, sizeof buf, "f %u %u %u\n", tri[0] + 1, tri[1] + 1, tri[2] + 1);
    out += buf;
  }
  return out;
}

}  // namespace imm::dim3
