// Graded background (dim3/graded_background.h): Kuhn grid + Maubach bisection + closure, on an
// exact integer lattice.
//
// Refinement is top-down per base tet with the list of input triangles near it (children filter
// their parent's list), so the cost follows the surface, not the volume. A tet is bisected while
//  - it meets an input triangle and it is coarser than the surface size, or
//  - it is coarser than the gap size and sits at a near self-intersection (two teeth, two lips,
//    two sheets that cross): the triangles meeting its box grown by one element form two or more
//    pieces not joined inside that grown box, or the triangles meeting the tet itself form two
//    or more pieces not joined inside the tet (the bottom of a comb's gap: the teeth join just
//    beyond the tet, which would otherwise span the gap). Pieces join through shared vertices
//    inside, or shared edges meeting, the box or tet. Joining inside the tet's own box for both
//    refined every tet within one element of any surface (3x the tets on comb 2, 2.5x on a torus).
// These tests run in doubles on lattice coordinates: they only choose sizes, never topology.
// Then the closure bisects every tet with a vertex at the midpoint of one of its edges until none
// has one (repeated sweeps; Maubach's scheme on the Kuhn grid terminates and is conforming).
#include "dim3/graded_background.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <sstream>
#include <bit>

#include "core/union_find.h"

namespace imm::dim3 {
namespace {

using Lattice = std::array<std::int32_t, 3>;
constexpr int kLatticeBits = 21;  // per axis, packed into one 64-bit key
constexpr std::int32_t kLatticeLimit = 1 << kLatticeBits;
/// The counting pass before building (Builder::run) runs when the input's area, in cube faces
/// at the surface size, times this exceeds max_tets. Backgrounds make about 25 tets per cube
/// face of area (sphere, torus, two-tori, helix, tube-overlap at surface resolutions 64-512), so
/// one that fits seldom pays for the count, and one of more than about 1.6 times the maximum is
/// refused by it.
constexpr double kCountingPassCells = 16.0;

/// As make_grid_background's shift (dim3/background3.cpp), so that a graded and a uniform grid
/// with the same base cube start from the same lattice planes; see there for why these numbers.
double shift_fraction(int attempt, int axis) {
  constexpr double kStep[3] = {0.7548776662466927, 0.5698402909980532, 0.4301597090019468};
  const double first = 0.0123457 + 0.00731 * axis;
  return std::fmod(first + attempt * kStep[axis], 1.0);
}

struct Node {
  std::array<int, 4> v;  ///< Maubach order: bisect the edge v0-vk with k = 3 - level mod 3
  int level = 0;
};

int tag(int level) { return 3 - level % 3; }

std::uint64_t key(const Lattice& p) {
  return static_cast<std::uint64_t>(p[0]) | (static_cast<std::uint64_t>(p[1]) << kLatticeBits) |
         (static_cast<std::uint64_t>(p[2]) << (2 * kLatticeBits));
}

/// Lattice point -> vertex id: open addressing, power-of-two capacity, multiplicative hash. The
/// closure looks up six edge midpoints per tet per sweep; std::unordered_map's division by a
/// prime and pointer chasing made that half the run time.
class PointIndex {
 public:
  /// The id of `k`, or -1.
  int find(std::uint64_t k) const {
    for (std::size_t i = slot(k);; i = (i + 1) & mask_) {
      if (keys_[i] == k) return ids_[i];
      if (keys_[i] == kEmpty) return -1;
    }
  }
  /// The id of `k`, inserting `id` first if absent; `inserted` says which.
  int emplace(std::uint64_t k, int id, bool& inserted) {
    if ((size_ + 1) * 2 > keys_.size()) grow();
    for (std::size_t i = slot(k);; i = (i + 1) & mask_) {
      if (keys_[i] == k) {
        inserted = false;
        return ids_[i];
      }
      if (keys_[i] == kEmpty) {
        keys_[i] = k;
        ids_[i] = id;
        ++size_;
        inserted = true;
        return id;
      }
    }
  }

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};
  std::size_t slot(std::uint64_t k) const { return static_cast<std::size_t>((k * 0x9E3779B97F4A7C15ull) >> shift_); }
  void grow() {
    std::vector<std::uint64_t> keys = std::move(keys_);
    std::vector<int> ids = std::move(ids_);
    const std::size_t capacity = keys.empty() ? 1024 : keys.size() * 2;
    keys_.assign(capacity, kEmpty);
    ids_.assign(capacity, -1);
    mask_ = capacity - 1;
    shift_ = 64 - std::countr_zero(capacity);
    size_ = 0;
    for (std::size_t i = 0; i < keys.size(); ++i) {
      if (keys[i] == kEmpty) continue;
      bool inserted = false;
      emplace(keys[i], ids[i], inserted);
    }
  }
  std::vector<std::uint64_t> keys_;
  std::vector<int> ids_;
  std::size_t mask_ = 0, size_ = 0;
  int shift_ = 64;
};

struct DBox {
  std::array<double, 3> lo, hi;
};

/// Triangle vs axis-aligned box overlap by separating axes (Akenine-Möller), in doubles.
bool triangle_meets_box(const std::array<Point3, 3>& t, const DBox& b) {
  Point3 c, h;
  for (int d = 0; d < 3; ++d) {
    c[d] = 0.5 * (b.lo[d] + b.hi[d]);
    h[d] = 0.5 * (b.hi[d] - b.lo[d]);
  }
  std::array<Point3, 3> v;
  for (int i = 0; i < 3; ++i)
    for (int d = 0; d < 3; ++d) v[i][d] = t[i][d] - c[d];
  for (int d = 0; d < 3; ++d) {  // box faces
    const double lo = std::min({v[0][d], v[1][d], v[2][d]}), hi = std::max({v[0][d], v[1][d], v[2][d]});
    if (lo > h[d] || hi < -h[d]) return false;
  }
  auto sub = [](const Point3& a, const Point3& b) { return Point3{a[0] - b[0], a[1] - b[1], a[2] - b[2]}; };
  auto cross = [](const Point3& a, const Point3& b) {
    return Point3{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  };
  auto dot = [](const Point3& a, const Point3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  auto separated = [&](const Point3& axis) {
    const double p0 = dot(v[0], axis), p1 = dot(v[1], axis), p2 = dot(v[2], axis);
    const double r = h[0] * std::abs(axis[0]) + h[1] * std::abs(axis[1]) + h[2] * std::abs(axis[2]);
    return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
  };
  const std::array<Point3, 3> edges{sub(v[1], v[0]), sub(v[2], v[1]), sub(v[0], v[2])};
  if (separated(cross(edges[0], edges[1]))) return false;  // triangle plane
  for (const Point3& e : edges)
    for (int d = 0; d < 3; ++d) {
      Point3 axis{0, 0, 0};
      axis[d] = 1;
      if (separated(cross(e, axis))) return false;
    }
  return true;
}

/// Triangle vs tetrahedron overlap by separating axes (both convex: the face normals of each and
/// the cross products of their edges), in doubles: whether a tet meets the surface decides its
/// size only. Its box would mark about three times the tets (a Kuhn tet fills 1/6 of its box).
bool triangle_meets_tet(const std::array<Point3, 3>& t, const std::array<Point3, 4>& q) {
  auto sub = [](const Point3& a, const Point3& b) { return Point3{a[0] - b[0], a[1] - b[1], a[2] - b[2]}; };
  auto cross = [](const Point3& a, const Point3& b) {
    return Point3{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  };
  auto dot = [](const Point3& a, const Point3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  auto separated = [&](const Point3& axis) {
    double tlo = dot(t[0], axis), thi = tlo;
    for (int i = 1; i < 3; ++i) {
      const double x = dot(t[i], axis);
      tlo = std::min(tlo, x);
      thi = std::max(thi, x);
    }
    double qlo = dot(q[0], axis), qhi = qlo;
    for (int i = 1; i < 4; ++i) {
      const double x = dot(q[i], axis);
      qlo = std::min(qlo, x);
      qhi = std::max(qhi, x);
    }
    return thi < qlo || qhi < tlo;
  };
  const std::array<Point3, 3> te{sub(t[1], t[0]), sub(t[2], t[1]), sub(t[0], t[2])};
  const std::array<Point3, 6> qe{sub(q[1], q[0]), sub(q[2], q[0]), sub(q[3], q[0]),
                                 sub(q[2], q[1]), sub(q[3], q[1]), sub(q[3], q[2])};
  if (separated(cross(te[0], te[1]))) return false;
  const int faces[4][2] = {{3, 4}, {1, 2}, {0, 2}, {0, 1}};  // two edges of each face
  for (const auto& f : faces)
    if (separated(cross(qe[f[0]], qe[f[1]]))) return false;
  for (const Point3& a : te)
    for (const Point3& b : qe)
      if (separated(cross(a, b))) return false;
  return true;
}

bool point_in_box(const Point3& p, const DBox& b) {
  for (int d = 0; d < 3; ++d)
    if (p[d] < b.lo[d] || p[d] > b.hi[d]) return false;
  return true;
}

/// Segment vs box (slab method).
bool segment_meets_box(const Point3& a, const Point3& b, const DBox& box) {
  double t0 = 0.0, t1 = 1.0;
  for (int d = 0; d < 3; ++d) {
    const double delta = b[d] - a[d];
    if (delta == 0.0) {
      if (a[d] < box.lo[d] || a[d] > box.hi[d]) return false;
      continue;
    }
    double s0 = (box.lo[d] - a[d]) / delta, s1 = (box.hi[d] - a[d]) / delta;
    if (s0 > s1) std::swap(s0, s1);
    t0 = std::max(t0, s0);
    t1 = std::min(t1, s1);
    if (t0 > t1) return false;
  }
  return true;
}

class Builder {
 public:
  Builder(const Surface& surface, const GradedOptions& options, GradedBackground& out)
      : surface_(surface), options_(options), out_(out) {}

  void run(const Box3& box, int attempt);

 private:
  int vertex(const Lattice& p) {
    bool inserted = false;
    const int id = index_.emplace(key(p), static_cast<int>(points_.size()), inserted);
    if (inserted) points_.push_back(p);
    return id;
  }
  /// The vertex at the midpoint of (a, b), or -1 when there is none (or it is off the lattice).
  int find_midpoint(int a, int b) const {
    Lattice m{};
    for (int d = 0; d < 3; ++d) {
      const std::int32_t s = points_[a][d] + points_[b][d];
      if (s % 2 != 0) return -1;
      m[d] = s / 2;
    }
    return index_.find(key(m));
  }
  std::array<Node, 2> bisect(const Node& n) {
    const int k = tag(n.level);
    Lattice m{};
    for (int d = 0; d < 3; ++d) {
      const std::int32_t s = points_[n.v[0]][d] + points_[n.v[k]][d];
      IMM_ASSERT(s % 2 == 0, "graded background: a bisection left the lattice");
      m[d] = s / 2;
    }
    const int z = vertex(m);
    Node a{n.v, n.level + 1}, b{n.v, n.level + 1};
    a.v[k] = z;                                        // (x0 .. x_{k-1}, z, x_{k+1} .. x3)
    for (int i = 0; i < k; ++i) b.v[i] = n.v[i + 1];   // (x1 .. xk, z, x_{k+1} .. x3)
    b.v[k] = z;
    return {a, b};
  }
  DBox box_of(const Node& n, double grow) const {
    DBox b;
    for (int d = 0; d < 3; ++d) {
      std::int32_t lo = points_[n.v[0]][d], hi = lo;
      for (int i = 1; i < 4; ++i) {
        lo = std::min(lo, points_[n.v[i]][d]);
        hi = std::max(hi, points_[n.v[i]][d]);
      }
      b.lo[d] = lo - grow;
      b.hi[d] = hi + grow;
    }
    return b;
  }
  bool has_hanging_vertex(const Node& n) const {
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        if (find_midpoint(n.v[i], n.v[j]) >= 0) return true;
    return false;
  }
  std::array<Point3, 3> triangle(std::uint32_t t) const {
    return {tri_points_[surface_.triangles[t][0]], tri_points_[surface_.triangles[t][1]],
            tri_points_[surface_.triangles[t][2]]};
  }
  /// Pieces of the triangles `list` connected through edges or vertices inside `box`: more than
  /// one means two parts of the surface come close without joining there.
  bool several_pieces(const std::vector<std::uint32_t>& list, const DBox& box,
                      const std::array<Point3, 4>* tet = nullptr);
  void refine(const Node& n, const std::vector<std::uint32_t>& candidates);
  /// A tet by its lattice corners (the counting pass makes no vertices).
  struct Corners {
    std::array<Lattice, 4> p;
    int level = 0;
  };
  /// Adds to count_ the leaves refine() would make from `n` by the surface rule alone (no gap
  /// refinement, no closure), with refine()'s own tests on the same candidate lists: every such
  /// leaf is a leaf of the build or is split further by it, so count_ is a lower bound of its
  /// tets. Stops once count_ exceeds the maximum.
  void count_surface_leaves(const Corners& n, const std::vector<std::uint32_t>& candidates);
  void too_many();
  /// Called per tet made: a progress message every options_.progress_every tets.
  void made_tet() {
    if (!options_.progress || options_.progress_every == 0 || leaves_.size() % options_.progress_every != 0) return;
    options_.progress("graded background: " + std::to_string(leaves_.size()) + " tets so far (" +
                      (closing_ ? "closure sweep " + std::to_string(out_.stats.closure_sweeps)
                                : std::to_string(base_done_) + " of " + std::to_string(out_.stats.base_tets) +
                                      " base tets refined") +
                      "; at most " + std::to_string(options_.max_tets) + ")");
  }

  const Surface& surface_;
  const GradedOptions& options_;
  GradedBackground& out_;
  std::vector<Point3> tri_points_;  ///< input vertices in lattice units (doubles)
  std::vector<DBox> tri_boxes_;     ///< input triangles' boxes in lattice units
  std::vector<Lattice> points_;
  PointIndex index_;
  std::vector<Node> leaves_;
  std::vector<char> leaf_near_;
  int surface_level_ = 0, gap_level_ = 0;
  std::int32_t base_cube_ = 0;
  bool overflow_ = false;
  std::size_t count_ = 0;      ///< count_surface_leaves's leaves
  std::size_t count_reported_ = 0;  ///< the count the last progress message gave
  std::vector<std::vector<std::uint32_t>> count_lists_;  ///< count_surface_leaves's lists per level
  std::size_t base_done_ = 0;  ///< base tets refined so far (progress)
  bool closing_ = false;       ///< in the closure (progress)
};

void Builder::too_many() {
  if (overflow_) return;
  overflow_ = true;
  out_.report.add({DefectKind::OutOfRange, "background",
                   "graded background: more than " + std::to_string(options_.max_tets) +
                       " tets; lower --surface-resolution or --gap-resolution",
                   {}, {}, {}});
}

bool Builder::several_pieces(const std::vector<std::uint32_t>& list, const DBox& box,
                             const std::array<Point3, 4>* tet) {
  // Inside `tet` when given (a point or a segment as a flat triangle: the separating axes stay
  // right), else inside `box`.
  const auto vertex_inside = [&](std::uint32_t v) {
    const Point3& p = tri_points_[v];
    return tet != nullptr ? triangle_meets_tet({p, p, p}, *tet) : point_in_box(p, box);
  };
  const auto edge_inside = [&](std::uint32_t a, std::uint32_t b) {
    return tet != nullptr ? triangle_meets_tet({tri_points_[a], tri_points_[b], tri_points_[b]}, *tet)
                          : segment_meets_box(tri_points_[a], tri_points_[b], box);
  };
  if (list.size() < 2) return false;
  UnionFind pieces(list.size());
  std::vector<std::pair<std::uint32_t, std::uint32_t>> at_vertex;  // (vertex, local triangle)
  std::vector<std::pair<std::uint64_t, std::uint32_t>> at_edge;   // (edge, local triangle)
  for (std::uint32_t i = 0; i < list.size(); ++i) {
    const Triangle& t = surface_.triangles[list[i]];
    for (int c = 0; c < 3; ++c) {
      at_vertex.emplace_back(t[c], i);
      const std::uint32_t a = std::min(t[c], t[(c + 1) % 3]), b = std::max(t[c], t[(c + 1) % 3]);
      at_edge.emplace_back((static_cast<std::uint64_t>(a) << 32) | b, i);
    }
  }
  std::sort(at_vertex.begin(), at_vertex.end());
  for (std::size_t i = 0, j = 0; i < at_vertex.size(); i = j) {
    for (j = i + 1; j < at_vertex.size() && at_vertex[j].first == at_vertex[i].first;) ++j;
    if (j - i < 2 || !vertex_inside(at_vertex[i].first)) continue;
    for (std::size_t k = i + 1; k < j; ++k) pieces.unite(at_vertex[i].second, at_vertex[k].second);
  }
  std::sort(at_edge.begin(), at_edge.end());
  for (std::size_t i = 0, j = 0; i < at_edge.size(); i = j) {
    for (j = i + 1; j < at_edge.size() && at_edge[j].first == at_edge[i].first;) ++j;
    if (j - i < 2) continue;
    const auto a = static_cast<std::uint32_t>(at_edge[i].first >> 32);
    const auto b = static_cast<std::uint32_t>(at_edge[i].first & 0xffffffffu);
    if (!edge_inside(a, b)) continue;
    for (std::size_t k = i + 1; k < j; ++k) pieces.unite(at_edge[i].second, at_edge[k].second);
  }
  const std::size_t root = pieces.find(0);
  for (std::size_t i = 1; i < list.size(); ++i)
    if (pieces.find(i) != root) return true;
  return false;
}

void Builder::refine(const Node& n, const std::vector<std::uint32_t>& candidates) {
  if (overflow_) return;
  // Cube side at this level in lattice units: halves every three bisections.
  const double side = static_cast<double>(base_cube_ >> (n.level / 3));
  const DBox own = box_of(n, 0.0);
  const DBox grown = box_of(n, side);
  auto boxes_meet = [](const DBox& a, const DBox& b) {
    for (int d = 0; d < 3; ++d)
      if (a.lo[d] > b.hi[d] || b.lo[d] > a.hi[d]) return false;
    return true;
  };
  std::vector<std::uint32_t> near;
  for (std::uint32_t t : candidates)
    if (boxes_meet(tri_boxes_[t], grown) && triangle_meets_box(triangle(t), grown)) near.push_back(t);
  std::array<Point3, 4> corners;
  for (int i = 0; i < 4; ++i)
    for (int d = 0; d < 3; ++d) corners[i][d] = static_cast<double>(points_[n.v[i]][d]);
  std::vector<std::uint32_t> touching;
  for (std::uint32_t t : near)
    if (boxes_meet(tri_boxes_[t], own) && triangle_meets_tet(triangle(t), corners)) touching.push_back(t);
  const bool meets = !touching.empty();
  bool split = meets && n.level < surface_level_;
  // Near self-intersection: pieces within one element that do not join within one element, or
  // pieces the tet itself meets that do not join inside it (the bottom of a gap, where the teeth
  // join just beyond the tet).
  if (!split && n.level < gap_level_ && near.size() >= 2)
    split = several_pieces(near, grown) || (touching.size() >= 2 && several_pieces(touching, own, &corners));
  if (!split) {
    leaves_.push_back(n);
    leaf_near_.push_back(static_cast<char>(meets ? 1 : 0));
    if (leaves_.size() > options_.max_tets) too_many();
    made_tet();
    return;
  }
  for (const Node& child : bisect(n)) refine(child, near);
}

void Builder::count_surface_leaves(const Corners& n, const std::vector<std::uint32_t>& candidates) {
  if (count_ > options_.max_tets) return;
  // As refine(): the candidates near the tet (its box grown by one element), those touching it.
  const double side = static_cast<double>(base_cube_ >> (n.level / 3));
  DBox own, grown;
  for (int d = 0; d < 3; ++d) {
    std::int32_t lo = n.p[0][d], hi = lo;
    for (int i = 1; i < 4; ++i) {
      lo = std::min(lo, n.p[i][d]);
      hi = std::max(hi, n.p[i][d]);
    }
    own.lo[d] = lo;
    own.hi[d] = hi;
    grown.lo[d] = lo - side;
    grown.hi[d] = hi + side;
  }
  auto boxes_meet = [](const DBox& a, const DBox& b) {
    for (int d = 0; d < 3; ++d)
      if (a.lo[d] > b.hi[d] || b.lo[d] > a.hi[d]) return false;
    return true;
  };
  // One list per level, reused (sized before the pass: the parents' lists stay in place).
  std::vector<std::uint32_t>& near = count_lists_[static_cast<std::size_t>(n.level)];
  near.clear();
  for (std::uint32_t t : candidates)
    if (boxes_meet(tri_boxes_[t], grown) && triangle_meets_box(triangle(t), grown)) near.push_back(t);
  std::array<Point3, 4> corners;
  for (int i = 0; i < 4; ++i)
    for (int d = 0; d < 3; ++d) corners[i][d] = static_cast<double>(n.p[i][d]);
  bool meets = false;
  for (std::uint32_t t : near)
    if (boxes_meet(tri_boxes_[t], own) && triangle_meets_tet(triangle(t), corners)) {
      meets = true;
      break;
    }
  const std::size_t leaves = !(meets && n.level < surface_level_) ? 1
                             : n.level + 1 >= surface_level_    ? 2  // children at the surface level: leaves
                                                                : 0;
  if (leaves > 0) {
    count_ += leaves;
    if (options_.progress && options_.progress_every > 0 && count_ >= count_reported_ + options_.progress_every) {
      count_reported_ = count_ - count_ % options_.progress_every;
      options_.progress("graded background: counting before building: " + std::to_string(count_reported_) +
                        " tets counted (at most " + std::to_string(options_.max_tets) + ")");
    }
    return;
  }
  // bisect()'s children, on lattice points.
  const int k = tag(n.level);
  Lattice m{};
  for (int d = 0; d < 3; ++d) m[d] = (n.p[0][d] + n.p[k][d]) / 2;
  Corners a{n.p, n.level + 1}, b{n.p, n.level + 1};
  a.p[k] = m;
  for (int i = 0; i < k; ++i) b.p[i] = n.p[i + 1];
  b.p[k] = m;
  count_surface_leaves(a, near);
  count_surface_leaves(b, near);
}

void Builder::run(const Box3& box, int attempt) {
  IMM_ASSERT(options_.far_resolution >= 1 && options_.surface_resolution >= 1,
             "graded background: resolutions must be at least 1");
  double longest = 0;
  for (int d = 0; d < 3; ++d) {
    IMM_ASSERT(std::isfinite(box.lo[d]) && std::isfinite(box.hi[d]) && box.lo[d] <= box.hi[d],
               "graded background needs a finite box with lo <= hi");
    longest = std::max(longest, box.hi[d] - box.lo[d]);
  }
  IMM_ASSERT(longest > 0 && std::isfinite(longest), "graded background needs a box of positive size");
  const int surface_resolution = options_.surface_resolution;
  const int gap_resolution = std::max(options_.gap_resolution, surface_resolution);
  // Halvings: far -> surface and surface -> gap, powers of two nearest to the ratios asked.
  const int levels = std::max(0, static_cast<int>(std::lround(std::log2(
                                     static_cast<double>(surface_resolution) / options_.far_resolution))));
  const int gap_levels = std::max(0, static_cast<int>(std::lround(std::log2(
                                         static_cast<double>(gap_resolution) / surface_resolution))));
  if (levels + gap_levels + 2 > 24) {
    out_.report.add({DefectKind::OutOfRange, "background",
                     "graded background: the surface and gap sizes are more than 2^22 times finer than the far size",
                     {}, {}, {}});
    return;
  }
  surface_level_ = 3 * levels;
  gap_level_ = 3 * (levels + gap_levels);
  // One lattice unit = a quarter of the gap cube (midpoints of its long diagonal, and one bit to
  // spare), rounded down to a 12-bit mantissa so that lattice coordinates are exact doubles.
  base_cube_ = std::int32_t{1} << (levels + gap_levels + 2);
  const double surface_side = longest / surface_resolution;
  const double wanted_unit = surface_side / static_cast<double>(std::int64_t{1} << (gap_levels + 2));
  const int exponent = std::ilogb(wanted_unit) - 11;
  const double mantissa = std::floor(std::ldexp(wanted_unit, -exponent));  // in [2^11, 2^12)
  const double unit = std::ldexp(mantissa, exponent);
  const double base_side = unit * base_cube_;

  std::array<std::int64_t, 3> cubes{};
  std::array<double, 3> wanted_origin{};
  for (int d = 0; d < 3; ++d) {
    wanted_origin[d] = box.lo[d] - base_side * (1 + shift_fraction(attempt, d));
    const double end = box.hi[d] + base_side;
    std::int64_t n = std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil((end - wanted_origin[d]) / base_side)));
    while (wanted_origin[d] + static_cast<double>(n) * base_side < end) ++n;
    cubes[d] = n;
    if (static_cast<double>(n) * base_cube_ >= kLatticeLimit) {
      out_.report.add({DefectKind::OutOfRange, "background",
                       "graded background: more than 2^21 lattice units along an axis; lower the resolutions",
                       {}, {}, {}});
      return;
    }
  }
  const double base_count = 6.0 * static_cast<double>(cubes[0]) * static_cast<double>(cubes[1]) *
                            static_cast<double>(cubes[2]);
  if (base_count > static_cast<double>(options_.max_tets)) {
    too_many();
    return;
  }
  // origin = O * 2^(exponent - S): then origin + i * unit = (O + i * mantissa * 2^S) * 2^(exponent - S),
  // exact while |O| + i * mantissa * 2^S < 2^53. The finer S, the less the rounding moves the shift.
  Point3 origin{};
  for (int d = 0; d < 3; ++d) {
    const double span = static_cast<double>(cubes[d]) * base_cube_ * mantissa;
    int s = 20;
    for (; s >= 0; --s) {
      const double scaled = std::abs(std::ldexp(wanted_origin[d], -(exponent - s)));
      if (scaled + std::ldexp(span, s) < 0x1p52) break;
    }
    if (s < 0) {
      out_.report.add({DefectKind::OutOfRange, "background",
                       "graded background: the input is too far from the origin for its element size "
                       "(lattice coordinates would not be exact doubles)",
                       {}, {}, {}});
      return;
    }
    origin[d] = std::ldexp(std::nearbyint(std::ldexp(wanted_origin[d], -(exponent - s))), exponent - s);
  }
  out_.origin = origin;
  out_.unit = unit;
  out_.base_cube = base_cube_;
  GradedStats& st = out_.stats;
  st.far_size = base_side;
  st.surface_size = unit * (base_cube_ >> levels);
  st.gap_size = unit * (base_cube_ >> (levels + gap_levels));
  st.surface_levels = levels;
  st.gap_levels = gap_levels;
  st.base_tets = static_cast<std::size_t>(base_count);
  if (options_.progress) {
    std::ostringstream msg;
    msg << "graded background: " << st.base_tets << " base tets of side " << st.far_size << ", refined to "
        << st.surface_size << " at the surface";
    if (gap_levels > 0) msg << " and " << st.gap_size << " at near self-intersections";
    msg << " (at most " << options_.max_tets << " tets)";
    options_.progress(msg.str());
  }

  // Input triangles in lattice units; triangles listed per base cube (grown by one cube).
  tri_points_.resize(surface_.vertices.size());
  for (std::size_t v = 0; v < surface_.vertices.size(); ++v)
    for (int d = 0; d < 3; ++d) tri_points_[v][d] = (surface_.vertices[v][d] - origin[d]) / unit;
  tri_boxes_.resize(surface_.triangles.size());
  for (std::uint32_t t = 0; t < surface_.triangles.size(); ++t) {
    const auto corners = triangle(t);
    for (int d = 0; d < 3; ++d) {
      tri_boxes_[t].lo[d] = std::min({corners[0][d], corners[1][d], corners[2][d]});
      tri_boxes_[t].hi[d] = std::max({corners[0][d], corners[1][d], corners[2][d]});
    }
  }
  const std::int64_t nx = cubes[0], ny = cubes[1], nz = cubes[2];
  std::vector<std::vector<std::uint32_t>> per_cube(static_cast<std::size_t>(nx * ny * nz));
  for (std::uint32_t t = 0; t < surface_.triangles.size(); ++t) {
    const auto corners = triangle(t);
    std::array<std::int64_t, 3> lo{}, hi{};
    for (int d = 0; d < 3; ++d) {
      const double a = std::min({corners[0][d], corners[1][d], corners[2][d]}) / base_cube_;
      const double b = std::max({corners[0][d], corners[1][d], corners[2][d]}) / base_cube_;
      lo[d] = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(a)) - 1, 0, cubes[d] - 1);
      hi[d] = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(b)) + 1, 0, cubes[d] - 1);
    }
    for (std::int64_t z = lo[2]; z <= hi[2]; ++z)
      for (std::int64_t y = lo[1]; y <= hi[1]; ++y)
        for (std::int64_t x = lo[0]; x <= hi[0]; ++x) per_cube[static_cast<std::size_t>(x + nx * (y + ny * z))].push_back(t);
  }

  // A background beyond max_tets took as long and as much memory to refuse as to build up to
  // that size (35 s and 1.7 GB for 50 million tets). When the surface's area is large for the
  // maximum at the surface size (kCountingPassCells), the surface refinement is first counted
  // without building anything (count_surface_leaves: a lower bound of the tets, so a refusal
  // here is true; about half the tets, at about a quarter of the time per tet, no memory).
  {
    double area = 0.0;  // in lattice units
    for (std::uint32_t t = 0; t < surface_.triangles.size(); ++t) {
      const auto c = triangle(t);
      const Point3 u{c[1][0] - c[0][0], c[1][1] - c[0][1], c[1][2] - c[0][2]};
      const Point3 v{c[2][0] - c[0][0], c[2][1] - c[0][1], c[2][2] - c[0][2]};
      const Point3 n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
      area += 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    }
    const double side = static_cast<double>(base_cube_ >> levels);
    if (area / (side * side) * kCountingPassCells > static_cast<double>(options_.max_tets)) {
      const int permutations[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
      count_lists_.resize(static_cast<std::size_t>(surface_level_) + 1);
      for (std::int64_t z = 0; z < cubes[2] && count_ <= options_.max_tets; ++z)
        for (std::int64_t y = 0; y < cubes[1] && count_ <= options_.max_tets; ++y)
          for (std::int64_t x = 0; x < cubes[0] && count_ <= options_.max_tets; ++x)
            for (const auto& p : permutations) {
              Lattice c{static_cast<std::int32_t>(x * base_cube_), static_cast<std::int32_t>(y * base_cube_),
                        static_cast<std::int32_t>(z * base_cube_)};
              Corners n{{c, c, c, c}, 0};
              for (int i = 0; i < 3; ++i) {
                c[p[i]] += base_cube_;
                n.p[i + 1] = c;
              }
              count_surface_leaves(n, per_cube[static_cast<std::size_t>(x + cubes[0] * (y + cubes[1] * z))]);
            }
      if (options_.progress)
        options_.progress("graded background: the refinement toward the surface alone makes " +
                          std::string(count_ > options_.max_tets ? "more than " : "") +
                          std::to_string(std::min(count_, options_.max_tets)) + " tets (counted before building)");
      if (count_ > options_.max_tets) {
        too_many();
        return;
      }
    }
  }

  // Base grid vertices first (x fastest), as the uniform grid orders them.
  points_.reserve(static_cast<std::size_t>((nx + 1) * (ny + 1) * (nz + 1)));
  for (std::int64_t z = 0; z <= nz; ++z)
    for (std::int64_t y = 0; y <= ny; ++y)
      for (std::int64_t x = 0; x <= nx; ++x)
        vertex({static_cast<std::int32_t>(x * base_cube_), static_cast<std::int32_t>(y * base_cube_),
                static_cast<std::int32_t>(z * base_cube_)});
  const int permutations[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (std::int64_t z = 0; z < nz && !overflow_; ++z)
    for (std::int64_t y = 0; y < ny && !overflow_; ++y)
      for (std::int64_t x = 0; x < nx && !overflow_; ++x) {
        const auto& list = per_cube[static_cast<std::size_t>(x + nx * (y + ny * z))];
        for (const auto& p : permutations) {
          // The Kuhn path corner -> +e_a -> +e_b -> +e_c, tag 3: bisected first at its long
          // diagonal, the same in every cube, which is what makes the scheme conforming.
          Lattice c{static_cast<std::int32_t>(x * base_cube_), static_cast<std::int32_t>(y * base_cube_),
                    static_cast<std::int32_t>(z * base_cube_)};
          Node n{{vertex(c), 0, 0, 0}, 0};
          for (int i = 0; i < 3; ++i) {
            c[p[i]] += base_cube_;
            n.v[i + 1] = vertex(c);
          }
          refine(n, list);
          ++base_done_;
        }
      }
  if (overflow_) return;

  // Closure: sweep until no tet has a vertex at the midpoint of one of its edges.
  closing_ = true;
  std::size_t closure = 0;
  for (bool changed = true; changed && !overflow_;) {
    changed = false;
    ++st.closure_sweeps;
    for (std::size_t i = 0; i < leaves_.size(); ++i) {
      while (has_hanging_vertex(leaves_[i])) {
        const auto children = bisect(leaves_[i]);
        leaves_[i] = children[0];
        leaves_.push_back(children[1]);
        leaf_near_.push_back(leaf_near_[i]);
        ++closure;
        changed = true;
        if (leaves_.size() > options_.max_tets) {
          too_many();
          return;
        }
        made_tet();
      }
    }
  }
  st.closure_bisections = closure;

  // Output: exact doubles, positive orientation from the integer determinant.
  TetMesh& mesh = out_.mesh;
  mesh.vertices.resize(points_.size());
  for (std::size_t v = 0; v < points_.size(); ++v)
    for (int d = 0; d < 3; ++d) mesh.vertices[v][d] = origin[d] + static_cast<double>(points_[v][d]) * unit;
  out_.lattice = points_;
  mesh.tets.reserve(leaves_.size());
  out_.level.reserve(leaves_.size());
  for (std::size_t i = 0; i < leaves_.size(); ++i) {
    Tet t = leaves_[i].v;
    std::array<std::array<__int128, 3>, 3> e{};
    for (int r = 0; r < 3; ++r)
      for (int d = 0; d < 3; ++d) e[r][d] = points_[t[r + 1]][d] - points_[t[0]][d];
    const __int128 det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                         e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                         e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
    IMM_ASSERT(det != 0, "graded background: a flat tet");
    if (det < 0) std::swap(t[2], t[3]);
    mesh.tets.push_back(t);
    out_.level.push_back(static_cast<std::uint8_t>(leaves_[i].level));
    st.surface_tets += leaf_near_[i] ? 1 : 0;
    st.gap_tets += leaves_[i].level >= gap_level_ && gap_level_ > surface_level_ ? 1 : 0;
  }
  st.tets = mesh.tets.size();
  st.vertices = mesh.vertices.size();
  const auto range = dihedral_range(mesh);
  st.min_dihedral_deg = range[0];
  st.max_dihedral_deg = range[1];
}

}  // namespace

double graded_min_dihedral_bound() {
  // The Kuhn tet and its first two bisection generations on the unit cube (doubled to stay
  // integral); every later tet is similar to one of these three.
  TetMesh m;
  m.vertices = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {2, 2, 2}, {1, 1, 1}, {1, 1, 0}};
  m.tets = {{0, 1, 2, 3}, {0, 1, 2, 4}, {0, 1, 5, 4}};
  return dihedral_range(m)[0];
}

Point3 scaled_to_unit(Point3 v) {
  const double big = std::max({std::abs(v[0]), std::abs(v[1]), std::abs(v[2])});
  if (!(big > 0) || !std::isfinite(big)) return v;
  const int e = std::ilogb(big);
  for (double& x : v) x = std::ldexp(x, -e);
  return v;
}

std::array<double, 2> dihedral_range(const TetMesh& mesh) {
  double lo = 180.0, hi = 0.0;
  constexpr double kDegrees = 180.0 / 3.14159265358979323846;
  // Vectors scaled_to_unit: products of coordinates near 1e300 overflowed (every normal NaN:
  // "min 180, max 0") and those near 1e-300 underflowed.
  for (const Tet& t : mesh.tets) {
    std::array<Point3, 4> p;
    for (int k = 0; k < 4; ++k) p[k] = mesh.vertices[static_cast<std::size_t>(t[k])];
    // Face normals (outward up to a common sign); the dihedral angle at edge (i, j) is pi minus
    // the angle between the normals of the two faces sharing it.
    std::array<Point3, 4> normal;
    for (int f = 0; f < 4; ++f) {
      std::array<int, 3> idx{};
      for (int k = 0, j = 0; k < 4; ++k)
        if (k != f) idx[j++] = k;
      const Point3& a = p[idx[0]];
      const Point3 u = scaled_to_unit({p[idx[1]][0] - a[0], p[idx[1]][1] - a[1], p[idx[1]][2] - a[2]});
      const Point3 v = scaled_to_unit({p[idx[2]][0] - a[0], p[idx[2]][1] - a[1], p[idx[2]][2] - a[2]});
      Point3 n = scaled_to_unit({u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]});
      // Point it away from the opposite vertex.
      const Point3 w = scaled_to_unit({p[f][0] - a[0], p[f][1] - a[1], p[f][2] - a[2]});
      if (n[0] * w[0] + n[1] * w[1] + n[2] * w[2] > 0) n = {-n[0], -n[1], -n[2]};
      const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      normal[f] = {n[0] / len, n[1] / len, n[2] / len};
    }
    for (int f = 0; f < 4; ++f)
      for (int g = f + 1; g < 4; ++g) {
        const double c = normal[f][0] * normal[g][0] + normal[f][1] * normal[g][1] + normal[f][2] * normal[g][2];
        const double angle = 180.0 - std::acos(std::clamp(c, -1.0, 1.0)) * kDegrees;
        lo = std::min(lo, angle);
        hi = std::max(hi, angle);
      }
  }
  return {lo, hi};
}

std::string graded_order_error(const GradedOptions& options, const GradedOptionNames& names) {
  const auto coarser = [](const char* finer, int f, const char* coarse, int c) {
    return std::string(finer) + " " + std::to_string(f) + " is coarser than " + coarse + " " + std::to_string(c);
  };
  if (options.far_resolution < 1) return std::string(names.far) + " must be at least 1";
  if (options.surface_resolution < options.far_resolution)
    return coarser(names.surface, options.surface_resolution, names.far, options.far_resolution);
  if (options.gap_resolution != 0 && options.gap_resolution < options.surface_resolution)
    return coarser(names.gap, options.gap_resolution, names.surface, options.surface_resolution);
  return {};
}

GradedBackground make_graded_background(const Surface& surface, const Box3& box, const GradedOptions& options,
                                        int attempt) {
  const auto start = std::chrono::steady_clock::now();
  GradedBackground out;
  Builder(surface, options, out).run(box, attempt);
  if (!out.report.ok()) {
    out.mesh = {};
    out.lattice.clear();
    out.level.clear();
  }
  out.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace imm::dim3
