// Virtual tets (paper §7.1 with d = 3): the exact local regions of every background tet.
//
// For each background tet T:
//  1. clipping: every cut triangle whose box overlaps T's is clipped to the closed tet by
//     Sutherland–Hodgman against the four face planes. Every polygon vertex is known
//     symbolically — a triangle corner, a triangle edge x a tet face, or a tet edge x the
//     triangle — and every polygon edge by its origin: a part of a triangle edge, or a trace on
//     a tet face. The input must meet the background generically: a polygon vertex lying on a
//     face plane it was not constructed on (an input point on a tet face, an input edge meeting
//     a tet edge, a tet vertex on the input) is reported, and the caller (dim3/mesh3.cpp) shifts
//     a generated grid, or translates the input by a tiny explicit vector relative to a read
//     background, and runs again.
//  2. pieces: polygons joined across the parts of cut edges inside T (across arcs the four
//     sheets meet at one geometric edge: the stitch map makes them one piece).
//  3. sides: the two sides of every polygon, joined across uncut edges (same side) and, around
//     an arc, through its four wedges (the same wedge rule as the cell complex). The classes are
//     the local regions next to a piece.
//  4. several pieces: for every ordered pair (P, Q), which side class of P holds Q. Each test
//     shoots a segment from a point inside a polygon of Q to a point inside a polygon of P and
//     reads the side of the first polygon of P it crosses; segments through an edge, a vertex
//     or two hits at once are replaced by another. Two (piece, class) pairs bound the same
//     local region iff they agree on every piece's class (the pieces are disjoint closed-in-T
//     surfaces of a ball, so the complement's components are the consistent class tuples, as in
//     the paper's region tree).
//
// Exactness: every tet is first run in interval arithmetic (IK below). Any sign the intervals
// cannot certify (an exact zero among them) throws, and the tet is run again with Epeck, so
// every decision is exact; the two paths give identical results (tests/dim3/virtual_tets_test).
// Tets are independent: blocks of them run on threads and are merged in tet order, so the
// result does not depend on the thread count.
//
// DEVIATION from the paper: §7.1.1 decides inside/outside with angle-weighted pseudo-normals at
// the closest site of each piece. Angle weights are not rational, so that test cannot be exact;
// the first crossing along a segment is, with rational arithmetic only, and it needs no closest-
// point computation. The region tree is the same.
//
// Across a shared face, a cut triangle crossing the face leaves a trace in both tets: the local
// regions on its outer sides are adjacent, and so are those on its inner sides (§7.1.2: "their
// embedded pieces share points on the boundary"). A face without traces lies in one local
// region on each side (classified by its centroid). Regions of tets without pieces follow by
// union-find over the input-free adjacencies, seeded by the sides of pieces; a component without
// any piece is located by one exact segment shooting against the whole cut mesh.
#include <CGAL/Interval_nt.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <limits>
#include <exception>
#include <map>
#include <memory>
#include <numeric>
#include <optional>
#include <thread>
#include <type_traits>
#include <unordered_map>

#include "core/huge_pages.h"
#include "core/parallel.h"
#include "core/union_find.h"
#include "core/unglue.h"
#include "dim3/background_limits.h"
#include "dim3/cut_mesh.h"
#include "dim3/mesh3_detail.h"

namespace imm::dim3::detail {

namespace {

using Point = EK::Point_3;
/// Interval arithmetic on doubles: the fast path. A sign it cannot certify throws
/// CGAL::Uncertain_conversion_exception, and the tet is redone with EK.
using IK = CGAL::Simple_cartesian<CGAL::Interval_nt<false>>;
constexpr std::uint32_t kNone = LocalRegions::kNone;

/// Face f of a tet is opposite vertex f; with these vertex orders the tet's own vertex f lies on
/// the positive side (CGAL::orientation(a, b, c, v_f) == POSITIVE for a positive tet).
constexpr int kFace[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  return (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
}

/// a[k] += a[k - 1] for k = 1 .. size-1 in order (an inclusive prefix sum, exact on integers), on
/// `threads` threads: block sums, a sum over the blocks, then every block adds up from its offset.
/// The same values as the serial loop, which over millions of tets was a serial pass.
template <class T>
void prefix_sum(unsigned threads, std::vector<T>& a) {
  constexpr std::size_t kBlock = 1 << 16;
  const std::size_t blocks = (a.size() + kBlock - 1) / kBlock;
  std::vector<T> offset(blocks + 1, 0);
  parallel_for(threads, blocks, [&](std::size_t b, unsigned) {
    T sum = 0;
    for (std::size_t k = b * kBlock; k < std::min(a.size(), (b + 1) * kBlock); ++k) sum += a[k];
    offset[b + 1] = sum;
  }, /*grain=*/1);
  for (std::size_t b = 0; b < blocks; ++b) offset[b + 1] += offset[b];
  parallel_for(threads, blocks, [&](std::size_t b, unsigned) {
    T sum = offset[b];
    for (std::size_t k = b * kBlock; k < std::min(a.size(), (b + 1) * kBlock); ++k) a[k] = sum += a[k];
  }, /*grain=*/1);
}

/// Whether the tets of interior face `face` (4 t + f) and its neighbour `other` (4 s + g) lie
/// on opposite sides of it. Both tets are positive (TetMesh: exact orientation on read), so
/// each tet's own vertex lies on the positive side of its face in kFace order: the tets are on
/// opposite sides iff the two tets give the face opposite vertex orders (s's order is not a
/// rotation of t's). Exact and combinatorial (no predicate).
bool opposite_sides(const TetMesh& bg, std::uint32_t face, std::uint32_t other) {
  const Tet& t = bg.tets[face / 4];
  const Tet& s = bg.tets[other / 4];
  const int* f = kFace[face % 4];
  const int* g = kFace[other % 4];
  const int a = t[f[0]], b = t[f[1]];
  // s's face order, rotated to start at a: then b second means the same orientation.
  for (int k = 0; k < 3; ++k)
    if (s[g[k]] == a) return s[g[(k + 1) % 3]] != b;
  return false;  // not the same face: unreachable
}

/// The defect for background tets t and s lying on the same side of their shared face `key`
/// (its vertices, sorted), found at `count` faces in all: the message both face pairings give.
Defect folded_face_defect(const TetMesh& bg, std::uint32_t t, std::uint32_t s, const std::array<int, 3>& key,
                          std::size_t count) {
  Defect d;
  d.kind = DefectKind::InconsistentOrientation;
  d.stage = "background";
  d.message = "background tets overlap: tets " + std::to_string(t) + " and " + std::to_string(s) +
              " lie on the same side of their shared face (" + std::to_string(key[0]) + ", " +
              std::to_string(key[1]) + ", " + std::to_string(key[2]) + ") near " +
              format_point(bg.vertices[static_cast<std::size_t>(key[0])]) +
              (count > 1 ? " (" + std::to_string(count) + " faces like this)" : "") +
              ": the background mesh is folded (an inverted or dragged vertex) and would be meshed twice there";
  d.vertices = {key[0], key[1], key[2]};
  return d;
}

/// Whether the interiors of (positive) background tets t and u intersect: exact separating-axis
/// test (two convex polytopes have disjoint interiors iff a plane parallel to a face of one, or
/// to an edge of each, separates them weakly).
bool interiors_meet(const TetMesh& bg, std::uint32_t t, std::uint32_t u) {
  std::array<Point, 4> a, b;
  for (int k = 0; k < 4; ++k) {
    const Point3& p = bg.vertices[static_cast<std::size_t>(bg.tets[t][k])];
    const Point3& q = bg.vertices[static_cast<std::size_t>(bg.tets[u][k])];
    a[k] = Point(p[0], p[1], p[2]);
    b[k] = Point(q[0], q[1], q[2]);
  }
  // Faces: the tet's own vertex f is on the positive side of face f (kFace order).
  const auto face_separates = [](const std::array<Point, 4>& x, const std::array<Point, 4>& y) {
    for (int f = 0; f < 4; ++f) {
      bool all = true;
      for (int k = 0; k < 4 && all; ++k)
        all = CGAL::orientation(x[kFace[f][0]], x[kFace[f][1]], x[kFace[f][2]], y[k]) != CGAL::POSITIVE;
      if (all) return true;
    }
    return false;
  };
  if (face_separates(a, b) || face_separates(b, a)) return false;
  constexpr int kEdge[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  for (const auto& ea : kEdge)
    for (const auto& eb : kEdge) {
      const EK::Vector_3 n = CGAL::cross_product(a[ea[1]] - a[ea[0]], b[eb[1]] - b[eb[0]]);
      if (n == CGAL::NULL_VECTOR) continue;
      // Sides of the plane through a[ea[0]] with normal n.
      int a_pos = 0, a_neg = 0, b_pos = 0, b_neg = 0;
      for (int k = 0; k < 4; ++k) {
        const CGAL::Sign sa = CGAL::sign(n * (a[k] - a[ea[0]]));
        const CGAL::Sign sb = CGAL::sign(n * (b[k] - a[ea[0]]));
        a_pos += sa == CGAL::POSITIVE;
        a_neg += sa == CGAL::NEGATIVE;
        b_pos += sb == CGAL::POSITIVE;
        b_neg += sb == CGAL::NEGATIVE;
      }
      if ((a_pos == 0 && b_neg == 0) || (a_neg == 0 && b_pos == 0)) return false;
    }
  return true;
}

/// Pieces of the background that overlap (two grids in one file, an unglued output reused as a
/// background, ...), given each tet's piece (tets joined across interior faces). Two pieces
/// overlap iff a tet of one and a tet of the other have intersecting interiors (the overlap is
/// open, so it meets open tets of both); pieces that only touch (a shared or coincident face,
/// edge or vertex) are fine. The tet pairs of different pieces whose boxes meet are tested
/// exactly, in (tet, tet) order, and the first overlapping pair is reported: the same for every
/// thread count. NOT detected: one piece overlapping itself away from its interior faces (a
/// slab bent round onto itself, a vertex star wound twice around); folds and inverted tets are
/// found across the faces (opposite_sides).
std::optional<Defect> overlapping_pieces(const TetMesh& bg, const std::vector<std::uint32_t>& piece) {
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::uint32_t>;
  std::vector<Box> boxes;
  boxes.reserve(bg.tets.size());
  for (std::uint32_t t = 0; t < bg.tets.size(); ++t) {
    CGAL::Bbox_3 box;
    for (int v : bg.tets[t]) {
      const Point3& p = bg.vertices[static_cast<std::size_t>(v)];
      box += CGAL::Bbox_3(p[0], p[1], p[2], p[0], p[1], p[2]);
    }
    boxes.emplace_back(box, t);
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& a, const Box& b) {
    if (piece[a.info()] != piece[b.info()]) pairs.emplace_back(std::min(a.info(), b.info()), std::max(a.info(), b.info()));
  });
  std::sort(pairs.begin(), pairs.end());
  for (const auto& [t, u] : pairs) {
    if (!interiors_meet(bg, t, u)) continue;
    const Tet& a = bg.tets[t];
    Defect d;
    d.kind = DefectKind::InconsistentOrientation;
    d.stage = "background";
    d.message = "background tets overlap: tets " + std::to_string(t) + " and " + std::to_string(u) +
                ", in different pieces of the background (tets joined across faces), overlap near " +
                format_point(bg.vertices[static_cast<std::size_t>(a[0])]) +
                ": the background would be meshed twice there (an unglued output has overlapping copies by "
                "design and cannot be a background: pass the glued mesh, or none)";
    d.vertices = {a[0], a[1], a[2], a[3]};
    return d;
  }
  return std::nullopt;
}

/// A vertex of a clipped polygon.
template <class K>
struct ClipVertexT {
  typename K::Point_3 point;
  std::uint8_t planes = 0;  ///< bit f: constructed on face plane f
  std::int32_t corner = -1; ///< the cut-mesh (sheet) vertex when a corner of the triangle
};

/// A clipped polygon: vertex i and the origin of the edge from vertex i to vertex i + 1
/// (0..2: part of triangle edge k, which joins corners k and k+1; 3 + f: trace on face f).
template <class K>
struct PolygonT {
  std::uint32_t triangle = 0;  ///< cut triangle
  std::vector<ClipVertexT<K>> vertices;
  std::vector<std::uint8_t> edge_origin;
};

/// The geometry of one tet in kernel K.
template <class K>
struct TetGeometryT {
  std::array<typename K::Point_3, 4> v;
  /// Side of p w.r.t. face plane f: POSITIVE inside, ZERO on the plane (certain, or it throws).
  [[nodiscard]] CGAL::Orientation side(int f, const typename K::Point_3& p) const {
    return CGAL::orientation(v[kFace[f][0]], v[kFace[f][1]], v[kFace[f][2]], p);
  }
  /// det(b - a, c - a, p - a) for face f = (a, b, c): its sign is side(f, p).
  [[nodiscard]] typename K::FT value(int f, const typename K::Point_3& p) const {
    const auto& a = v[kFace[f][0]];
    return CGAL::determinant(v[kFace[f][1]] - a, v[kFace[f][2]] - a, p - a);
  }
};

template <class K>
constexpr bool kInterval = std::is_same_v<K, IK>;

using Polygon = PolygonT<EK>;

/// Signals an uncertain interval decision (the tet is redone exactly).
[[noreturn]] void uncertain() { throw CGAL::Uncertain_conversion_exception("uncertain sign in interval arithmetic"); }

/// A piece's side classes and, per polygon, the class of each side.
struct PieceSides {
  std::vector<std::uint32_t> polygons;
  std::uint32_t class_count = 0;
};

class VirtualTets {
 public:
  VirtualTets(const Complex& complex, const TetMesh& background, const Point3& shift, bool record,
              unsigned threads, bool interval_filter, ValidationReport& report, bool& non_generic)
      : threads_(std::max(1u, threads)),
        interval_filter_(interval_filter),
        shift_(shift),
        c_(complex),
        m_(*complex.exact),
        bg_(background),
        record_(record),
        report_(report),
        non_generic_(non_generic) {}

  LocalRegions run() {
    non_generic_ = false;
    input_points_ = &m_.points;
    if (shift_ != Point3{0, 0, 0}) {
      // The input translated by an explicit (tiny) vector: every decision below is exact for it.
      const EK::Vector_3 v(shift_[0], shift_[1], shift_[2]);
      shifted_points_.reserve(m_.points.size());
      for (const Point& p : m_.points) shifted_points_.push_back(p + v);
      input_points_ = &shifted_points_;
    }
    input_intervals_.reserve(input_points_->size());
    for (const Point& p : *input_points_) input_intervals_.push_back(CGAL::approx(p));
    for (std::uint32_t i = 0; i < m_.pieces.size(); ++i)
      arc_edge_.emplace(edge_key(m_.pieces[i].points[0], m_.pieces[i].points[1]), i);
    StageClock clock;
    find_candidates();
    out_.seconds_candidates = clock.next();
    out_.vertices.resize(c_.surface.vertex_count());
    triangle_has_polygon_.assign(m_.triangles.size(), 0);
    // Written for the four faces of every tet with candidates (merge_block), read only for tets
    // with two local regions or more, which are among those: the rest is never touched, so it
    // is left uninitialised (no serial pass, and its pages are never mapped).
    face_region_.reset(new std::uint32_t[4 * bg_.tets.size()]);
    // Only tets with candidate triangles are processed; the others (most of a fine background)
    // have one local region and are appended in bulk between them, without a TetOut.
    std::vector<std::uint32_t> candidate_tets;
    parallel_ordered_append(
        threads_, bg_.tets.size(), [&](std::size_t t) { return std::size_t{cand_first_[t] != cand_first_[t + 1]}; },
        [&](std::size_t total) { candidate_tets.resize(total); },
        [&](std::size_t t, std::size_t at) { candidate_tets[at] = static_cast<std::uint32_t>(t); }, 1 << 16);
    out_.first.reserve(bg_.tets.size() + 1);
    out_.region.reserve(bg_.tets.size() + 2 * candidate_tets.size());
    out_.element.reserve(bg_.tets.size() + 2 * candidate_tets.size());
    trace_first_.reserve(bg_.tets.size() + 1);
    for (const auto* v : {&out_.first, &out_.element, &trace_first_}) advise_huge_pages(*v);
    advise_huge_pages(out_.region);
    // Tets are independent: blocks of them run on the threads, and are merged in tet order so
    // that the result does not depend on the thread count. Each block is merged while the next
    // one runs (the merge is the first item of the next block's loop, on one thread; the merge
    // writes only the outputs, which no tet reads): merged between the blocks, its serial part
    // left the other threads idle.
    constexpr std::size_t kBlock = 4096;
    // Block k in blocks[k % 2]; on one thread the merge of block k - 1 runs before block k's
    // tets, so one buffer does (its pages and cache lines are not doubled).
    const std::size_t buffers = threads_ > 1 ? 2 : 1;
    std::array<std::vector<TetOut>, 2> blocks;
    for (std::size_t b = 0; b < buffers; ++b) blocks[b].resize(std::min(kBlock, candidate_tets.size()));
    // Each worker's polygons, a cache line of their own: the vectors' headers are read and
    // written for every polygon, and two workers' headers on one line cost ~10 % of the
    // clipping's CPU on two threads (false sharing; BENCHMARKS.md, "Thread pool").
    struct alignas(64) WorkerPolygons {
      std::vector<PolygonT<IK>> interval;
      std::vector<Polygon> exact;
    };
    std::vector<WorkerPolygons> scratch(threads_);
    std::atomic<std::size_t> exact_tets{0};
    std::vector<double> exact_seconds(threads_, 0.0);  // per worker
    std::uint32_t next_tet = 0;  // tets before it are merged
    const std::size_t block_count = (candidate_tets.size() + kBlock - 1) / kBlock;
    const auto block_size = [&](std::size_t k) { return std::min(kBlock, candidate_tets.size() - k * kBlock); };
    // Merges block k up to the first tet that stops the run (a non-generic contact, or an
    // error, which is rethrown): the tets before it are merged, as one by one in tet order.
    // @return that tet's index in the block, or the block's size
    const auto merge = [&](std::size_t k) {
      std::vector<TetOut>& block = blocks[k % buffers];
      const std::size_t count = block_size(k);
      std::size_t stop = 0;
      while (stop < count && !block[stop].defect && !block[stop].error) ++stop;
      merge_block(candidate_tets.data() + k * kBlock, block, stop, next_tet);
      if (k == 0 && stop == count && count < candidate_tets.size()) {
        // The arrays whose sizes only the tets know, reserved from the first block's share
        // (with room to spare: reserving touches no page): grown by doubling they were copied
        // and faulted in again on the calling thread, a third of the merge's serial time.
        const double scale =
            1.5 * static_cast<double>(candidate_tets.size()) / static_cast<double>(count);
        const auto expect = [&](std::size_t n) {
          return static_cast<std::size_t>(scale * static_cast<double>(n)) + kBlock;
        };
        out_.fusions.reserve(expect(out_.fusions.size()));
        traces_.reserve(expect(traces_.size()));
        out_.embedded.reserve(expect(out_.embedded.size()));
        advise_huge_pages(out_.fusions);
        advise_huge_pages(traces_);
        advise_huge_pages(out_.embedded);
      }
      return stop;
    };
    for (std::size_t k = 0; k <= block_count; ++k) {
      // Block k runs (none after the last), and block k - 1 is merged, as item 0.
      const std::size_t count = k < block_count ? block_size(k) : 0;
      const std::size_t merged = k > 0 ? 1 : 0;
      std::vector<TetOut>& block = blocks[k % buffers];
      const std::uint32_t* tets = k < block_count ? candidate_tets.data() + k * kBlock : nullptr;
      const auto run_tet = [&](std::size_t i, unsigned worker) {
        const std::uint32_t t = tets[i];
        block[i].clear();
        if (interval_filter_) {
          try {
            const CGAL::Protect_FPU_rounding<true> rounding;  // upward, for Interval_nt<false>
            process_tet<IK>(t, cand_first_[t], cand_first_[t + 1], block[i], scratch[worker].interval);
            return;
          } catch (const CGAL::Uncertain_conversion_exception&) {
          }
        }
        block[i].clear();
        ++exact_tets;
        const double exact_start = thread_cpu_seconds();
        process_tet<EK>(t, cand_first_[t], cand_first_[t + 1], block[i], scratch[worker].exact);
        exact_seconds[worker] += thread_cpu_seconds() - exact_start;
      };
      std::size_t stop = kBlock;  // of block k - 1
      // Set when block k - 1 stops the run: block k's tets are then skipped (on one thread, where
      // the merge runs first and the blocks share a buffer, they would overwrite the stopping tet).
      std::atomic<bool> stopped{false};
      parallel_for(threads_, merged + count, [&](std::size_t i, unsigned worker) {
        if (i < merged) {
          stop = merge(k - 1);
          if (stop < block_size(k - 1)) stopped = true;
          return;
        }
        if (stopped.load(std::memory_order_relaxed)) return;
        try {
          run_tet(i - merged, worker);
        } catch (...) {
          block[i - merged].error = std::current_exception();  // rethrown by merge, so the first tet's wins
        }
      }, /*grain=*/16);
      if (stopped) {
        TetOut& o = blocks[(k - 1) % buffers][stop];
        if (!o.defect) std::rethrow_exception(o.error);
        non_generic_ = true;
        report_.add(std::move(*o.defect));
        return std::move(out_);
      }
    }
    append_uncut(next_tet, static_cast<std::uint32_t>(bg_.tets.size()));
    std::vector<std::pair<std::uint32_t, std::uint32_t>>().swap(candidates_);  // not held through the faces
    std::vector<std::uint32_t>().swap(cand_first_);
    out_.finish();
    out_.exact_tets = exact_tets;
    for (double s : exact_seconds) out_.seconds_exact += s;
    out_.seconds_tets = clock.next();
    connect_faces();
    out_.seconds_faces = clock.next();
    if (!report_.ok()) return std::move(out_);
    resolve_regions();
    out_.seconds_regions = clock.next();
    check_coverage();
    return std::move(out_);
  }

 private:
  // ---- set-up --------------------------------------------------------------------------------

  [[nodiscard]] const Point& corner(std::uint32_t cut_triangle, int k) const {
    return (*input_points_)[m_.vertex_point[m_.triangles[cut_triangle][k]]];
  }
  template <class K>
  [[nodiscard]] const typename K::Point_3& corner_in(std::uint32_t cut_triangle, int k) const {
    if constexpr (kInterval<K>) {
      return input_intervals_[m_.vertex_point[m_.triangles[cut_triangle][k]]];
    } else {
      return corner(cut_triangle, k);
    }
  }
  /// Background vertex v in kernel K, made from its doubles when needed (the whole background in
  /// Epeck points would cost an allocation and ~100 bytes per vertex).
  template <class K>
  [[nodiscard]] typename K::Point_3 background_point(std::size_t v) const {
    const Point3& p = bg_.vertices[v];
    return typename K::Point_3(p[0], p[1], p[2]);
  }

  /// Appends tets from .. to-1, which no cut triangle's box meets: one local region each, of a
  /// region found later (resolve_regions), no traces.
  void append_uncut(std::uint32_t from, std::uint32_t to) {
    if (from >= to) return;
    const std::size_t n = to - from, base = out_.region.size(), first = out_.first.size();
    IMM_ASSERT(base + n < kNone, "too many local regions");
    out_.first.resize(first + n);
    out_.element.resize(base + n);
    parallel_blocks(threads_, n, 1 << 16, [&](std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k) {
        out_.first[first + k] = static_cast<std::uint32_t>(base + k);
        out_.element[base + k] = static_cast<std::uint32_t>(from + k);
      }
    });
    out_.region.resize(base + n);  // unknown: resolve_regions
    trace_first_.resize(trace_first_.size() + n, static_cast<std::uint32_t>(traces_.size()));
  }

  /// The box of background tet t, from its double coordinates (exact: they are the points).
  [[nodiscard]] CGAL::Bbox_3 tet_box(std::size_t t) const {
    const Point3& p = bg_.vertices[static_cast<std::size_t>(bg_.tets[t][0])];
    double lo[3] = {p[0], p[1], p[2]}, hi[3] = {p[0], p[1], p[2]};
    for (int k = 1; k < 4; ++k) {
      const Point3& q = bg_.vertices[static_cast<std::size_t>(bg_.tets[t][k])];
      for (int d = 0; d < 3; ++d) {
        lo[d] = std::min(lo[d], q[d]);
        hi[d] = std::max(hi[d], q[d]);
      }
    }
    return {lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]};
  }

  /// (tet, cut triangle) pairs whose boxes overlap, sorted. Triangle boxes come from the interval
  /// approximations of the exact points (they contain the exact points): a conservative filter.
  /// The tets are binned in a hierarchy of uniform grids (CGAL's box_intersection_d, tried first,
  /// cost as much as the clipping): level 0's cells are about one tet across, each next level's
  /// twice as wide, up to cells as wide as the whole background. A tet goes into the one cell
  /// holding its box's low corner, on the finest level whose cells are at least as wide as its
  /// box: one entry per tet, however graded the background (a wide tet copied into every fine cell
  /// it overlaps made 36 entries per tet on a strongly graded one, and could overflow 32-bit
  /// offsets). Each triangle visits, on every level that holds tets, the cells its box overlaps,
  /// widened by that level's cell downwards (where the low corners of the tets that can overlap it
  /// lie), and keeps the tets whose boxes overlap its own. Triangles are split among the threads;
  /// each pair is found once. The binning is the only per-tet work here.
  void find_candidates() {
    const std::size_t tet_count = bg_.tets.size();
    cand_first_.assign(tet_count + 1, 0);
    if (tet_count == 0 || m_.triangles.empty()) return;
    // The boxes are recomputed from the doubles where needed rather than stored (48 bytes a tet).
    // Slices fixed by the size, so that the sums (and the cells) do not depend on the threads.
    const std::size_t tet_slices = 1 + tet_count / 65536;
    CGAL::Bbox_3 all;
    double extent = 0.0;
    {
      std::vector<CGAL::Bbox_3> slice_box(tet_slices);
      std::vector<double> slice_extent(tet_slices, 0.0);
      parallel_for(threads_, tet_slices, [&](std::size_t slice, unsigned) {
        // Summed in locals, stored once: neighbouring slices' sums share a cache line, and
        // writing them per tet made this loop 2-3x slower on two threads (false sharing).
        CGAL::Bbox_3 box;
        double sum = 0.0;
        for (std::size_t t = tet_count * slice / tet_slices; t < tet_count * (slice + 1) / tet_slices; ++t) {
          const CGAL::Bbox_3 b = tet_box(t);
          box += b;
          sum += std::max({b.xmax() - b.xmin(), b.ymax() - b.ymin(), b.zmax() - b.zmin()});
        }
        slice_box[slice] = box;
        slice_extent[slice] = sum;
      }, /*grain=*/1);
      for (std::size_t k = 0; k < tet_slices; ++k) {
        all += slice_box[k];
        extent += slice_extent[k];
      }
    }
    // Level 0's cells: about the mean tet extent (a little more, so that a uniform grid's tets
    // are all on level 0), at most ~8 per tet and 2^30 in all; the levels above add at most as
    // many again (a flat background halves only two of the counts per level), so every cell id
    // fits 32 bits below kNone.
    double cell = 1.01 * extent / static_cast<double>(tet_count);
    const double span[3] = {all.xmax() - all.xmin(), all.ymax() - all.ymin(), all.zmax() - all.zmin()};
    const double budget = std::min(8.0 * static_cast<double>(tet_count), std::ldexp(1.0, 30));
    if (!(cell > 0.0)) cell = 1.0;
    while ((span[0] / cell + 1) * (span[1] / cell + 1) * (span[2] / cell + 1) > budget) cell *= 1.25;
    const double lo[3] = {all.xmin(), all.ymin(), all.zmin()};
    // A tet's box is inside `all` (its extent is at most the span, in doubles too: rounding is
    // monotone), so the first level whose cells are as wide as the widest span takes every tet.
    struct Level {
      double cell;
      std::array<std::size_t, 3> dims;
      std::size_t offset;  ///< of its first cell among all levels' cells
    };
    std::vector<Level> levels;
    std::size_t cells = 0;
    for (double c = cell;; c *= 2) {
      Level level{c, {}, cells};
      for (int d = 0; d < 3; ++d) level.dims[d] = static_cast<std::size_t>(span[d] / c) + 1;
      cells += level.dims[0] * level.dims[1] * level.dims[2];
      levels.push_back(level);
      if (c >= std::max({span[0], span[1], span[2]})) break;
    }
    IMM_ASSERT(cells < kNone, "too many grid cells for the candidate search");
    const auto index = [&](const Level& level, double x, int d) {
      const double i = std::floor((x - lo[d]) / level.cell);
      return static_cast<std::size_t>(std::clamp(i, 0.0, static_cast<double>(level.dims[d] - 1)));
    };
    const auto cell_id = [&](const Level& level, std::size_t i, std::size_t j, std::size_t k) {
      return level.offset + (i * level.dims[1] + j) * level.dims[2] + k;
    };
    // The cell of every tet, on its level; then the tets per cell (counting sort).
    std::vector<std::uint32_t> tet_cell(tet_count);
    std::vector<std::vector<char>> slice_levels(tet_slices, std::vector<char>(levels.size(), 0));
    parallel_for(threads_, tet_slices, [&](std::size_t slice, unsigned) {
      std::vector<char> used(levels.size(), 0);
      for (std::size_t t = tet_count * slice / tet_slices; t < tet_count * (slice + 1) / tet_slices; ++t) {
        const CGAL::Bbox_3 b = tet_box(t);
        const double width = std::max({b.xmax() - b.xmin(), b.ymax() - b.ymin(), b.zmax() - b.zmin()});
        std::size_t l = 0;
        while (l + 1 < levels.size() && width > levels[l].cell) ++l;
        used[l] = 1;
        const Level& level = levels[l];
        tet_cell[t] = static_cast<std::uint32_t>(
            cell_id(level, index(level, b.xmin(), 0), index(level, b.ymin(), 1), index(level, b.zmin(), 2)));
      }
      slice_levels[slice] = std::move(used);
    }, /*grain=*/1);
    std::vector<std::size_t> occupied;  // levels holding tets, finest first
    for (std::size_t l = 0; l < levels.size(); ++l)
      for (const std::vector<char>& used : slice_levels)
        if (used[l]) {
          occupied.push_back(l);
          break;
        }
    // A counting sort on all threads with atomic counters: the order of the tets inside a cell
    // varies with the threads, but only the set of pairs found matters (sorted per tet below).
    std::vector<std::uint32_t> cell_first(cells + 1, 0), cell_tets(tet_count);
    parallel_blocks(threads_, tet_count, 1 << 14, [&](std::size_t begin, std::size_t end) {
      for (std::size_t t = begin; t < end; ++t)
        std::atomic_ref<std::uint32_t>(cell_first[std::size_t{tet_cell[t]} + 1]).fetch_add(1, std::memory_order_relaxed);
    });
    prefix_sum(threads_, cell_first);
    {
      std::vector<std::uint32_t> next(cell_first.begin(), cell_first.end() - 1);
      parallel_blocks(threads_, tet_count, 1 << 14, [&](std::size_t begin, std::size_t end) {
        for (std::size_t t = begin; t < end; ++t)
          cell_tets[std::atomic_ref<std::uint32_t>(next[tet_cell[t]]).fetch_add(1, std::memory_order_relaxed)] =
              static_cast<std::uint32_t>(t);
      });
    }
    std::vector<std::uint32_t>().swap(tet_cell);
    // Slices of ~1024 triangles taken dynamically (halves per thread left one thread idle where
    // the surface is unevenly cut, and with ~4096 the last slice still left it idle for ~9 ms of
    // the quintuple torus's 141); each slice's pairs are collected in a local vector (the slices'
    // vector headers share cache lines).
    const std::size_t slices = 1 + m_.triangles.size() / 1024;
    std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> found(slices);
    parallel_for(threads_, slices, [&](std::size_t slice, unsigned) {
      std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
      std::vector<std::array<std::size_t, 6>> ranges(occupied.size());  // per occupied level: from, to
      const std::size_t begin = m_.triangles.size() * slice / slices;
      const std::size_t end = m_.triangles.size() * (slice + 1) / slices;
      for (auto x = static_cast<std::uint32_t>(begin); x < end; ++x) {
        const CGAL::Bbox_3 b = corner(x, 0).bbox() + corner(x, 1).bbox() + corner(x, 2).bbox();
        // A tet of a level sits in the cell of its low corner, at most one cell (its width) below
        // the triangle's box when they overlap. Widened by two cells, not one: the level test and
        // this bound are rounded doubles, and a tet a rounding wider than a cell must still be
        // found (the exact overlap test below keeps exactly the overlapping pairs either way).
        // Rounded to nearest, as the binning.
        for (std::size_t o = 0; o < occupied.size(); ++o) {
          const Level& level = levels[occupied[o]];
          const double widen = 2 * level.cell;
          ranges[o] = {index(level, b.xmin() - widen, 0), index(level, b.ymin() - widen, 1),
                       index(level, b.zmin() - widen, 2), index(level, b.xmax(), 0),
                       index(level, b.ymax(), 1), index(level, b.zmax(), 2)};
        }
        const CGAL::Protect_FPU_rounding<true> rounding;  // upward, for Interval_nt<false>
        // The triangle's plane in intervals: a tet whose four corners are certainly strictly on
        // one side of it cannot meet the triangle (clipping would give an empty polygon), so it
        // is no candidate. Uncertain signs keep the pair.
        const IK::Point_3& a = corner_in<IK>(x, 0);
        const IK::Vector_3 normal = CGAL::cross_product(corner_in<IK>(x, 1) - a, corner_in<IK>(x, 2) - a);
        const auto plane_side = [&](std::uint32_t t) {
          int side = 0;
          for (int k = 0; k < 4; ++k) {
            const Point3& p = bg_.vertices[static_cast<std::size_t>(bg_.tets[t][k])];
            const IK::FT value = normal.x() * (p[0] - a.x()) + normal.y() * (p[1] - a.y()) + normal.z() * (p[2] - a.z());
            const int s = value.inf() > 0 ? 1 : value.sup() < 0 ? -1 : 0;
            if (s == 0 || (side != 0 && s != side)) return 0;
            side = s;
          }
          return side;
        };
        for (std::size_t o = 0; o < occupied.size(); ++o) {
          const Level& level = levels[occupied[o]];
          const std::array<std::size_t, 6>& r = ranges[o];
          for (std::size_t i = r[0]; i <= r[3]; ++i)
            for (std::size_t j = r[1]; j <= r[4]; ++j)
              for (std::size_t k = r[2]; k <= r[5]; ++k) {
                const std::size_t c = cell_id(level, i, j, k);
                for (std::uint32_t n = cell_first[c]; n < cell_first[c + 1]; ++n) {
                  const std::uint32_t t = cell_tets[n];
                  if (CGAL::do_overlap(b, tet_box(t)) && plane_side(t) == 0) pairs.emplace_back(t, x);
                }
              }
        }
      }
      found[slice] = std::move(pairs);
    }, /*grain=*/1);
    // Sorted by (tet, triangle): a counting sort by tet (atomic counters, on all threads: the
    // order inside a tet varies), then each tet's few triangles sorted, on all threads.
    std::vector<std::uint32_t>& first = cand_first_;
    std::size_t pair_count = 0;
    for (const auto& pairs : found) pair_count += pairs.size();
    IMM_ASSERT(pair_count < kNone, "more than 2^32 candidate pairs");  // the offsets are 32-bit
    parallel_for(threads_, slices, [&](std::size_t slice, unsigned) {
      for (const auto& [t, x] : found[slice])
        std::atomic_ref<std::uint32_t>(first[std::size_t{t} + 1]).fetch_add(1, std::memory_order_relaxed);
    }, /*grain=*/1);
    prefix_sum(threads_, first);
    candidates_.resize(first[tet_count]);
    {
      std::vector<std::uint32_t> next(first.begin(), first.end() - 1);
      parallel_for(threads_, slices, [&](std::size_t slice, unsigned) {
        for (const auto& pair : found[slice])
          candidates_[std::atomic_ref<std::uint32_t>(next[pair.first]).fetch_add(1, std::memory_order_relaxed)] = pair;
        std::vector<std::pair<std::uint32_t, std::uint32_t>>().swap(found[slice]);
      }, /*grain=*/1);
    }
    // Sorted per tet. Each pair was found once (a tet is in one cell, and a triangle visits a
    // cell once): checked here, where it costs one comparison per pair.
    std::atomic<std::size_t> repeats{0};
    parallel_blocks(threads_, tet_count, 1 << 12, [&](std::size_t begin_tet, std::size_t end_tet) {
      std::size_t n = 0;
      for (std::size_t t = begin_tet; t < end_tet; ++t) {
        const auto begin = candidates_.begin() + first[t], end = candidates_.begin() + first[t + 1];
        std::sort(begin, end);
        for (auto c = begin; c != end; ++c)
          if (c != begin && *c == *(c - 1)) ++n;
      }
      repeats += n;
    });
    IMM_ASSERT(repeats == 0, "a candidate pair found twice");
    out_.candidate_pairs = candidates_.size();
  }

  // ---- clipping ------------------------------------------------------------------------------

  /// Exact Sutherland–Hodgman clipping of cut triangle x to the closed tet. @return false when
  /// the contact is not generic (then a defect was reported).
  template <class K>
  bool clip(std::uint32_t tet, const TetGeometryT<K>& g, std::uint32_t x, PolygonT<K>& poly,
            std::optional<Defect>& defect) const {
    using P = typename K::Point_3;
    poly.triangle = x;
    poly.vertices.clear();
    poly.edge_origin.clear();
    for (int k = 0; k < 3; ++k) {
      poly.vertices.push_back({corner_in<K>(x, k), 0, static_cast<std::int32_t>(m_.triangles[x][k])});
      poly.edge_origin.push_back(static_cast<std::uint8_t>(k));
    }
    // Scratch reused across calls: no allocation per (tet, triangle) pair.
    thread_local std::vector<ClipVertexT<K>> next_vertices;
    thread_local std::vector<std::uint8_t> next_origin;
    thread_local std::vector<CGAL::Orientation> side;
    for (int f = 0; f < 4 && !poly.vertices.empty(); ++f) {
      const std::size_t n = poly.vertices.size();
      side.resize(n);
      bool any_out = false;
      for (std::size_t i = 0; i < n; ++i) {
        side[i] = (poly.vertices[i].planes >> f) & 1u ? CGAL::ZERO : g.side(f, poly.vertices[i].point);
        any_out = any_out || side[i] == CGAL::NEGATIVE;
      }
      if (!any_out) continue;
      next_vertices.clear();
      next_origin.clear();
      for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j = (i + 1) % n;
        const ClipVertexT<K>& p = poly.vertices[i];
        const ClipVertexT<K>& q = poly.vertices[j];
        if (side[i] != CGAL::NEGATIVE) {
          next_vertices.push_back(p);
          next_origin.push_back(side[i] == CGAL::ZERO && side[j] == CGAL::NEGATIVE ? static_cast<std::uint8_t>(3 + f)
                                                                                   : poly.edge_origin[i]);
        }
        if (side[i] != CGAL::ZERO && side[j] != CGAL::ZERO && side[i] != side[j]) {
          // The crossing of the edge with plane f: p + (q - p) sp / (sp - sq), exact in EK.
          const typename K::FT sp = g.value(f, p.point), sq = g.value(f, q.point);
          const P point = p.point + (q.point - p.point) * (sp / (sp - sq));
          ClipVertexT<K> v{point, static_cast<std::uint8_t>((p.planes & q.planes) | (1u << f)), -1};
          next_vertices.push_back(std::move(v));
          next_origin.push_back(side[i] == CGAL::POSITIVE ? static_cast<std::uint8_t>(3 + f) : poly.edge_origin[i]);
        }
      }
      poly.vertices.swap(next_vertices);
      poly.edge_origin.swap(next_origin);
    }
    if (poly.vertices.empty()) return true;
    // Generic contact: every vertex lies strictly inside every face plane it was not built on,
    // and the polygon is not flattened to a point or a segment.
    for (const ClipVertexT<K>& v : poly.vertices) {
      for (int f = 0; f < 4; ++f) {
        if ((v.planes >> f) & 1u) continue;
        if (g.side(f, v.point) == CGAL::ZERO) {
          if constexpr (kInterval<K>) {
            uncertain();  // decided exactly
          } else {
            const std::string what = v.corner >= 0 ? "a vertex of the input lies on face " + std::to_string(f)
                                     : std::popcount(v.planes) == 1 ? "an input edge meets an edge of the tet"
                                                                    : "a vertex of the tet lies on the input";
            defect = non_generic(tet, x, v.point, what);
            return false;
          }
        }
      }
    }
    if (poly.vertices.size() < 3) {
      if constexpr (kInterval<K>) {
        uncertain();
      } else {
        defect = non_generic(tet, x, poly.vertices.front().point, "the input touches the tet");
      }
      return false;
    }
    return true;
  }

  Defect non_generic(std::uint32_t tet, std::uint32_t x, const Point& where, const std::string& what) const {
    const Point3 p{CGAL::to_double(where.x()), CGAL::to_double(where.y()), CGAL::to_double(where.z())};
    Defect d;
    d.kind = DefectKind::Touching;
    d.stage = "mesh";
    d.message = "background tet " + std::to_string(tet) + " meets the input non-generically at " +
                format_point(p) + ": " + what + " (input triangle " + std::to_string(m_.triangle_source[x]) +
                "); move or perturb the background mesh";
    d.facets = {static_cast<long>(m_.triangle_source[x])};
    d.points = {{p[0], p[1], p[2]}};
    return d;
  }

  // ---- one tet ------------------------------------------------------------------------------

  [[nodiscard]] PatchId patch(std::uint32_t x) const { return c_.cut_triangle_patch[x]; }
  [[nodiscard]] RegionId side_region(std::uint32_t x, bool inner) const {
    const PatchSides& s = c_.complex.sides(patch(x));
    return inner ? s.negative : s.positive;
  }

  struct Trace {
    std::uint32_t tet;
    std::uint8_t face;
    std::uint32_t triangle;
    std::uint32_t outer, inner;
  };

  /// What one tet contributes, with local-region ids local to the tet (0 .. regions.size()-1).
  struct TetOut {
    std::vector<RegionId> regions;  ///< per local region (invalid: not known from a piece)
    std::vector<LocalRegions::Fusion> fusions;
    std::vector<Trace> traces;
    std::vector<LocalRegions::Embedded> embedded;
    std::vector<std::pair<std::uint32_t, LocalRegions::VertexLocation>> vertices;  ///< (input point, location)
    std::vector<std::uint32_t> triangles;  ///< cut triangles with a polygon in the tet
    std::array<std::uint32_t, 4> face_lr{kNone, kNone, kNone, kNone};  ///< untraced faces
    std::size_t polygons = 0, pieces = 0, side_tests = 0;
    std::optional<Defect> defect;  ///< a non-generic contact
    std::exception_ptr error;      ///< thrown while processing the tet; rethrown in tet order

    /// Empty again for the next tet, keeping the arrays' storage: a block's slots are reused by
    /// whichever thread takes them next, and freeing storage another thread's allocator owns
    /// cost ~10 % of the clipping's CPU on two threads (BENCHMARKS.md, "Thread pool"). It lists
    /// every member: a member added above must be reset here. (Building a fresh TetOut and
    /// moving the arrays into it, which needs no list, measured ~1.5 % slower on the quintuple
    /// torus on two threads.)
    void clear() {
      regions.clear();
      fusions.clear();
      traces.clear();
      embedded.clear();
      vertices.clear();
      triangles.clear();
      face_lr = {kNone, kNone, kNone, kNone};
      polygons = pieces = side_tests = 0;
      defect.reset();
      error = nullptr;
    }
  };

  template <class K>
  void process_tet(std::uint32_t t, std::size_t begin, std::size_t end, TetOut& o,
                   std::vector<PolygonT<K>>& polys) const {
    TetGeometryT<K> g;
    for (int k = 0; k < 4; ++k) g.v[k] = background_point<K>(static_cast<std::size_t>(bg_.tets[t][k]));
    polys.clear();
    PolygonT<K> poly;
    for (std::size_t c = begin; c < end; ++c) {
      if (!clip(t, g, candidates_[c].second, poly, o.defect)) return;
      if (!poly.vertices.empty()) polys.push_back(poly);
    }
    if (polys.empty()) {
      o.regions.emplace_back();
      o.face_lr = {0, 0, 0, 0};
      return;
    }
    o.polygons = polys.size();
    const std::size_t n = polys.size();

    // Pieces and sides: polygons meet only along parts of cut edges inside the tet.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> edges;  // (geometric edge, polygon)
    for (std::uint32_t i = 0; i < n; ++i) {
      const PolygonT<K>& p = polys[i];
      o.triangles.push_back(p.triangle);
      for (std::size_t e = 0; e < p.vertices.size(); ++e) {
        const int k = p.edge_origin[e];
        if (k >= 3) continue;
        const auto& tri = m_.triangles[p.triangle];
        edges.emplace_back(edge_key(m_.vertex_point[tri[k]], m_.vertex_point[tri[(k + 1) % 3]]), i);
      }
    }
    std::sort(edges.begin(), edges.end());
    UnionFind pieces(n), sides(2 * n);  // side 2i: outer, 2i + 1: inner
    std::unordered_map<std::uint32_t, std::uint32_t> local_of;  // cut triangle -> polygon
    for (std::uint32_t i = 0; i < n; ++i) local_of.emplace(polys[i].triangle, i);
    for (std::size_t a = 0; a < edges.size();) {
      std::size_t b = a;
      while (b < edges.size() && edges[b].first == edges[a].first) ++b;
      for (std::size_t i = a + 1; i < b; ++i) pieces.unite(edges[a].second, edges[i].second);
      if (b - a == 2) {
        const std::uint32_t p = edges[a].second, q = edges[a + 1].second;
        sides.unite(2 * p, 2 * q);
        sides.unite(2 * p + 1, 2 * q + 1);
      } else {
        IMM_ASSERT(b - a == 4, "a cut edge inside a tet with " + std::to_string(b - a) + " polygons");
        const auto arc = arc_edge_.find(edges[a].first);
        IMM_ASSERT(arc != arc_edge_.end(), "four polygons at an edge that is not on an arc");
        const CutPiece& piece = m_.pieces[arc->second];
        const auto local = [&](std::uint32_t sub) {
          const auto it = local_of.find(sub);
          IMM_ASSERT(it != local_of.end(), "a sheet at an arc inside a tet has no polygon");
          return it->second;
        };
        const std::uint32_t ap = local(piece.side[0][0]), an = local(piece.side[0][1]);
        const std::uint32_t bp = local(piece.side[1][0]), bn = local(piece.side[1][1]);
        // The four wedges, as in the cell complex (dim3/complex3.cpp, glue_wedges).
        sides.unite(2 * ap + 1, 2 * bn);
        sides.unite(2 * bn + 1, 2 * an + 1);
        sides.unite(2 * an, 2 * bp + 1);
        sides.unite(2 * bp, 2 * ap);
      }
      a = b;
    }
    // Compact piece ids and side classes (per piece).
    std::vector<std::uint32_t> piece_of(n), piece_id(n, kNone);
    std::vector<PieceSides> piece_list;
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t r = pieces.find(i);
      if (piece_id[r] == kNone) {
        piece_id[r] = static_cast<std::uint32_t>(piece_list.size());
        piece_list.emplace_back();
      }
      piece_of[i] = piece_id[r];
      piece_list[piece_of[i]].polygons.push_back(i);
    }
    std::vector<std::uint32_t> class_of(2 * n, kNone), class_root(2 * n, kNone);
    for (std::uint32_t s = 0; s < 2 * n; ++s) {
      const std::uint32_t r = sides.find(s);
      if (class_root[r] == kNone) class_root[r] = piece_list[piece_of[s / 2]].class_count++;
      class_of[s] = class_root[r];
    }
    o.pieces = piece_list.size();

    // Local regions: class tuples over all pieces.
    const std::size_t k = piece_list.size();
    std::vector<std::vector<std::uint32_t>> inside(k, std::vector<std::uint32_t>(k, kNone));  // [i][j]: class of i holding j
    for (std::size_t i = 0; i < k; ++i)
      for (std::size_t j = 0; j < k; ++j)
        if (i != j)
          inside[i][j] = class_of_point<K>(interior_point<K>(polys[piece_list[j].polygons.front()], 0), piece_list[i],
                                           class_of, polys, o.side_tests);
    std::map<std::vector<std::uint32_t>, std::uint32_t> lr_of_key;
    std::vector<std::vector<std::uint32_t>> lr_of_class(k);
    for (std::size_t i = 0; i < k; ++i) {
      lr_of_class[i].assign(piece_list[i].class_count, kNone);
      for (std::uint32_t cl = 0; cl < piece_list[i].class_count; ++cl) {
        std::vector<std::uint32_t> key(k);
        for (std::size_t j = 0; j < k; ++j) key[j] = j == i ? cl : inside[j][i];
        const auto [it, inserted] = lr_of_key.emplace(std::move(key), static_cast<std::uint32_t>(o.regions.size()));
        if (inserted) o.regions.emplace_back();
        lr_of_class[i][cl] = it->second;
      }
    }
    const auto lr_of_side = [&](std::uint32_t p, bool inner) {
      return lr_of_class[piece_of[p]][class_of[2 * p + (inner ? 1 : 0)]];
    };

    // Regions, fusions, traces, embedded pieces, input vertices.
    for (std::uint32_t i = 0; i < n; ++i) {
      const PolygonT<K>& p = polys[i];
      const std::uint32_t outer = lr_of_side(i, false), inner = lr_of_side(i, true);
      LocalRegions::set_region(o.regions, outer, side_region(p.triangle, false));
      LocalRegions::set_region(o.regions, inner, side_region(p.triangle, true));
      if (inner != outer) o.fusions.push_back({inner, outer, patch(p.triangle)});
      if (record_) {
        o.embedded.push_back({inner, p.triangle, true});
        o.embedded.push_back({outer, p.triangle, false});
      }
      for (std::size_t e = 0; e < p.vertices.size(); ++e) {
        if (p.edge_origin[e] >= 3)
          o.traces.push_back({t, static_cast<std::uint8_t>(p.edge_origin[e] - 3), p.triangle, outer, inner});
        const ClipVertexT<K>& v = p.vertices[e];
        if (v.corner < 0) continue;
        const std::uint32_t point = m_.vertex_point[static_cast<std::size_t>(v.corner)];
        if (point >= c_.surface.vertex_count()) continue;
        o.vertices.push_back({point, {inner, patch(p.triangle), {}}});  // weights: on merge, once
      }
    }
    LocalRegions::normalise(o.fusions);

    // Faces without traces lie in one local region: the one holding the face's centroid.
    std::uint8_t traced = 0;
    for (const PolygonT<K>& p : polys)
      for (std::uint8_t e : p.edge_origin)
        if (e >= 3) traced |= static_cast<std::uint8_t>(1u << (e - 3));
    for (int f = 0; f < 4; ++f) {
      if ((traced >> f) & 1u) continue;
      const typename K::Point_3 y = CGAL::centroid(g.v[kFace[f][0]], g.v[kFace[f][1]], g.v[kFace[f][2]]);
      std::vector<std::uint32_t> key(k);
      for (std::size_t j = 0; j < k; ++j) key[j] = class_of_point<K>(y, piece_list[j], class_of, polys, o.side_tests);
      const auto it = lr_of_key.find(key);
      IMM_ASSERT(it != lr_of_key.end(), "a face point in no local region");
      o.face_lr[static_cast<std::size_t>(f)] = it->second;
    }
  }

  /// Appends the tets from next_tet to tets[count - 1] in tet order: the uncut ones between (as
  /// append_uncut) and each tets[i] with its result outs[i], everything that refers to their
  /// local regions included. Each tet's share of every array is counted first, then all are
  /// written at their offsets on all threads: the arrays are the one-by-one merge's for every
  /// thread count (this merge was the largest serial part of the tets stage, BENCHMARKS.md).
  void merge_block(const std::uint32_t* tets, std::vector<TetOut>& outs, std::size_t count, std::uint32_t& next_tet) {
    if (count == 0) return;
    // at[i]: where the uncut tets before tets[i] (from gap_begin(i)) start writing, per array.
    struct Offsets {
      std::size_t regions, fusions, traces, embedded;
    };
    const auto gap_begin = [&](std::size_t i) { return i == 0 ? next_tet : tets[i - 1] + 1; };
    std::vector<Offsets> at(count + 1);
    at[0] = {out_.region.size(), out_.fusions.size(), traces_.size(), out_.embedded.size()};
    for (std::size_t i = 0; i < count; ++i) {
      const TetOut& o = outs[i];
      at[i + 1] = {at[i].regions + (tets[i] - gap_begin(i)) + o.regions.size(), at[i].fusions + o.fusions.size(),
                   at[i].traces + o.traces.size(), at[i].embedded + o.embedded.size()};
      out_.polygons += o.polygons;
      out_.pieces += o.pieces;
      out_.side_tests += o.side_tests;
      if (o.regions.size() > 1) ++out_.cut_elements;
    }
    const std::uint32_t end = tets[count - 1] + 1;
    IMM_ASSERT(at[count].regions < kNone && at[count].traces < kNone, "too many local regions or traces");
    out_.first.resize(end);
    out_.region.resize(at[count].regions);  // the uncut tets' regions stay unknown: resolve_regions
    out_.element.resize(at[count].regions);
    out_.fusions.resize(at[count].fusions);
    traces_.resize(at[count].traces);
    trace_first_.resize(std::size_t{end} + 1);
    out_.embedded.resize(at[count].embedded);
    parallel_for(threads_, count, [&](std::size_t i, unsigned) {
      TetOut& o = outs[i];
      const std::uint32_t t = tets[i];
      auto lr = static_cast<std::uint32_t>(at[i].regions);
      const auto traces_before = static_cast<std::uint32_t>(at[i].traces);
      for (std::uint32_t u = gap_begin(i); u < t; ++u, ++lr) {
        out_.first[u] = lr;
        out_.element[lr] = u;
        trace_first_[std::size_t{u} + 1] = traces_before;
      }
      const std::uint32_t base = lr;
      out_.first[t] = base;
      for (std::size_t k = 0; k < o.regions.size(); ++k) {
        out_.region[base + k] = o.regions[k];
        out_.element[base + k] = t;
      }
      for (std::size_t k = 0; k < o.fusions.size(); ++k) {
        const LocalRegions::Fusion& f = o.fusions[k];
        out_.fusions[at[i].fusions + k] = {base + f.inner, base + f.outer, f.patch};
      }
      std::sort(o.traces.begin(), o.traces.end(), [](const Trace& a, const Trace& b) {
        return std::tie(a.face, a.triangle) < std::tie(b.face, b.triangle);
      });
      for (std::size_t k = 0; k < o.traces.size(); ++k) {
        const Trace& tr = o.traces[k];
        traces_[traces_before + k] = {tr.tet, tr.face, tr.triangle, base + tr.outer, base + tr.inner};
      }
      trace_first_[std::size_t{t} + 1] = static_cast<std::uint32_t>(at[i + 1].traces);
      for (std::size_t k = 0; k < o.embedded.size(); ++k) {
        const LocalRegions::Embedded& e = o.embedded[k];
        out_.embedded[at[i].embedded + k] = {base + e.local_region, e.cut_triangle, e.inner};
      }
      for (std::uint32_t x : o.triangles) std::atomic_ref<char>(triangle_has_polygon_[x]).store(1, std::memory_order_relaxed);
      for (std::size_t f = 0; f < 4; ++f) face_region_[4 * std::size_t{t} + f] = o.face_lr[f] != kNone ? base + o.face_lr[f] : kNone;
    }, /*grain=*/16);
    // Input vertices: the first tet in tet order (and the first entry in it) wins; its weights
    // are computed afterwards, on all threads, once per vertex.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> located;  // (input point, tet)
    for (std::size_t i = 0; i < count; ++i) {
      for (auto& [point, location] : outs[i].vertices) {
        if (out_.vertices[point].local_region != kNone) continue;
        location.local_region += out_.first[tets[i]];
        out_.vertices[point] = location;
        located.emplace_back(point, tets[i]);
      }
    }
    parallel_for(threads_, located.size(), [&](std::size_t k, unsigned) {
      const auto [point, t] = located[k];
      const Point3& q = c_.surface.vertices[point];
      out_.vertices[point].weights = tet_barycentric(bg_, t, {q[0] + shift_[0], q[1] + shift_[1], q[2] + shift_[2]});
    }, /*grain=*/256);
    next_tet = end;
  }

  // ---- which side of a piece -----------------------------------------------------------------

  /// A point strictly inside polygon p: a weighted mean of three of its vertices (variant v
  /// chooses the vertices and weights; every variant is inside, they differ for retries).
  template <class K>
  static typename K::Point_3 interior_point(const PolygonT<K>& p, unsigned variant) {
    using FT = typename K::FT;
    const std::size_t n = p.vertices.size();
    const std::size_t a = variant % n;
    const std::size_t b = (a + 1) % n, c = (a + 2) % n;
    static constexpr int kWeights[4][3] = {{1, 1, 1}, {3, 2, 2}, {2, 3, 2}, {2, 2, 3}};
    const auto& w = kWeights[(variant / n) % 4];
    const FT sum = w[0] + w[1] + w[2];
    const auto& pa = p.vertices[a].point;
    const auto& pb = p.vertices[b].point;
    const auto& pc = p.vertices[c].point;
    return typename K::Point_3((w[0] * pa.x() + w[1] * pb.x() + w[2] * pc.x()) / sum,
                 (w[0] * pa.y() + w[1] * pb.y() + w[2] * pc.y()) / sum,
                 (w[0] * pa.z() + w[1] * pb.z() + w[2] * pc.z()) / sum);
  }

  /// The first cut triangle among `triangles` that the segment from x to m crosses, and whether
  /// x is on its inner side; nullopt when the segment is not clean (through an edge or a vertex,
  /// in a triangle's plane, or two crossings at once). x must not lie on any of the triangles.
  /// `m_plane`: an input triangle whose plane holds m by construction (the sub-triangles of one
  /// input triangle are coplanar), so that the orientation of m against those is known without
  /// evaluating an exact zero; UINT32_MAX when none.
  template <class K>
  std::optional<std::pair<std::uint32_t, bool>> first_crossing(const typename K::Point_3& x,
                                                               const typename K::Point_3& m, std::uint32_t m_plane,
                                                               const std::vector<std::uint32_t>& triangles) const {
    using FT = typename K::FT;
    std::optional<FT> best;
    std::pair<std::uint32_t, bool> hit{0, false};
    for (std::uint32_t tri : triangles) {
      const auto& a = corner_in<K>(tri, 0);
      const auto& b = corner_in<K>(tri, 1);
      const auto& c = corner_in<K>(tri, 2);
      const CGAL::Orientation ox = CGAL::orientation(a, b, c, x);
      const bool m_on_plane = m_.triangle_source[tri] == m_plane;
      const CGAL::Orientation om = m_on_plane ? CGAL::ZERO : CGAL::Orientation(CGAL::orientation(a, b, c, m));
      if (ox == CGAL::ZERO && om == CGAL::ZERO) {
        if constexpr (kInterval<K>) {
          uncertain();  // decided exactly
        } else {
          if (CGAL::do_intersect(EK::Segment_3(x, m), EK::Triangle_3(a, b, c))) return std::nullopt;
        }
        continue;
      }
      if (ox == CGAL::ZERO || ox == om) continue;  // x is off the triangles; no crossing
      const CGAL::Orientation e0 = CGAL::orientation(x, m, a, b);
      const CGAL::Orientation e1 = CGAL::orientation(x, m, b, c);
      const CGAL::Orientation e2 = CGAL::orientation(x, m, c, a);
      const bool pos = e0 == CGAL::POSITIVE || e1 == CGAL::POSITIVE || e2 == CGAL::POSITIVE;
      const bool neg = e0 == CGAL::NEGATIVE || e1 == CGAL::NEGATIVE || e2 == CGAL::NEGATIVE;
      if (pos && neg) continue;  // the line passes beside the triangle
      if (e0 == CGAL::ZERO || e1 == CGAL::ZERO || e2 == CGAL::ZERO) {
        // Through an edge or a vertex, or (om == ZERO) m in the triangle's plane: only clean when
        // the line misses the closed triangle, which the three signs just ruled out.
        return std::nullopt;
      }
      if (om == CGAL::ZERO) {
        // The segment ends on the plane: it crosses iff m is inside the triangle (checked above).
      }
      FT lambda(1);  // m itself when it lies on the triangle's plane
      if (om != CGAL::ZERO) {
        const FT vx = CGAL::determinant(b - a, c - a, x - a);
        const FT vm = CGAL::determinant(b - a, c - a, m - a);
        lambda = vx / (vx - vm);
      }
      if (!best || lambda < *best) {
        best = lambda;
        hit = {tri, ox == CGAL::NEGATIVE};
      } else if (lambda == *best) {
        if constexpr (kInterval<K>) uncertain();  // a tie is decided exactly
        return std::nullopt;
      }
    }
    if (!best) return std::nullopt;
    return hit;
  }

  /// The side class of `piece` whose local region holds point x (x off the piece).
  template <class K>
  std::uint32_t class_of_point(const typename K::Point_3& x, const PieceSides& piece,
                               const std::vector<std::uint32_t>& class_of, const std::vector<PolygonT<K>>& polys,
                               std::size_t& tests) const {
    ++tests;
    if (piece.class_count == 1) return 0;
    std::vector<std::uint32_t> triangles;
    triangles.reserve(piece.polygons.size());
    for (std::uint32_t i : piece.polygons) triangles.push_back(polys[i].triangle);
    for (unsigned variant = 0; variant < 64; ++variant) {
      for (std::uint32_t i : piece.polygons) {
        const typename K::Point_3 m = interior_point<K>(polys[i], variant);
        const auto hit = first_crossing<K>(x, m, m_.triangle_source[polys[i].triangle], triangles);
        if (!hit) {
          if constexpr (kInterval<K>) uncertain();  // another segment is chosen exactly
          continue;
        }
        std::uint32_t poly = kNone;
        for (std::uint32_t j : piece.polygons)
          if (polys[j].triangle == hit->first) poly = j;
        return class_of[2 * poly + (hit->second ? 1 : 0)];
      }
    }
    IMM_ASSERT(false, "no clean segment to a piece");
    return 0;
  }

  // ---- faces ----------------------------------------------------------------------------------

  /// Pairs the faces of the background tets and records what touches across each: for every
  /// interior face, the adjacencies of its two tets' local regions (LocalRegions::Adjacency,
  /// `first` in the smaller tet), in the order LocalRegions::normalise gives them; boundary faces
  /// (in face-key order) for the coverage check; a face shared by more than two tets is a
  /// defect. The neighbours come from the tets around each face's smallest vertex, so the work
  /// is per tet and runs on all threads (no sort of all faces).
  void connect_faces() {
    const std::size_t tet_count = bg_.tets.size();
    const auto key_of = [&](std::uint32_t t, int f) {
      std::array<int, 3> key = {bg_.tets[t][kFace[f][0]], bg_.tets[t][kFace[f][1]], bg_.tets[t][kFace[f][2]]};
      std::sort(key.begin(), key.end());
      return key;
    };
    // Tets around each background vertex (a counting sort on all threads with atomic counters: the
    // order inside a star varies, but the faces at a vertex are sorted before they pair).
    constexpr std::size_t kTetChunk = 4096;
    const std::size_t tet_chunks = (tet_count + kTetChunk - 1) / kTetChunk;
    std::vector<std::uint32_t> star_first(bg_.vertices.size() + 1, 0);
    parallel_for(threads_, tet_chunks, [&](std::size_t chunk, unsigned) {
      for (std::size_t t = chunk * kTetChunk; t < std::min(tet_count, (chunk + 1) * kTetChunk); ++t)
        for (int v : bg_.tets[t])
          std::atomic_ref<std::uint32_t>(star_first[static_cast<std::size_t>(v) + 1]).fetch_add(1, std::memory_order_relaxed);
    }, /*grain=*/1);
    for (std::size_t v = 0; v + 1 < star_first.size(); ++v) star_first[v + 1] += star_first[v];
    // Uninitialised: every entry is written below (a value-initialised 16 bytes per tet was a
    // serial pass).
    std::unique_ptr<std::uint32_t[]> star(new std::uint32_t[star_first.back()]);
    advise_huge_pages(star.get(), sizeof(std::uint32_t) * star_first.back());
    {
      std::vector<std::uint32_t> next(star_first.begin(), star_first.end() - 1);
      parallel_for(threads_, tet_chunks, [&](std::size_t chunk, unsigned) {
        for (std::size_t t = chunk * kTetChunk; t < std::min(tet_count, (chunk + 1) * kTetChunk); ++t)
          for (int v : bg_.tets[t]) {
            const std::uint32_t at =
                std::atomic_ref<std::uint32_t>(next[static_cast<std::size_t>(v)]).fetch_add(1, std::memory_order_relaxed);
            star[at] = static_cast<std::uint32_t>(t);
          }
      }, /*grain=*/1);
    }
    // Neighbour across face (t, f): 4 s + g, or a mark. Every face is paired at its smallest
    // vertex: the faces there whose smallest vertex it is, sorted by their other two vertices
    // (a few dozen per vertex), pair up. Vertices are independent: all threads.
    constexpr std::uint32_t kBoundaryFace = kNone, kSharedByMore = kNone - 1;
    // Uninitialised as `star`: every face has a smallest vertex, where it is written.
    std::unique_ptr<std::uint32_t[]> neighbour(new std::uint32_t[4 * tet_count]);
    advise_huge_pages(neighbour.get(), sizeof(std::uint32_t) * 4 * tet_count);
    struct StarFace {
      std::array<int, 2> rest;  ///< the face's two larger vertices
      std::uint32_t face;       ///< 4 t + f
    };
    const std::size_t vertex_count = bg_.vertices.size();
    constexpr std::size_t kVertexChunk = 1024;
    parallel_for(threads_, (vertex_count + kVertexChunk - 1) / kVertexChunk, [&](std::size_t chunk, unsigned) {
      std::vector<StarFace> faces;
      for (std::size_t v = chunk * kVertexChunk; v < std::min(vertex_count, (chunk + 1) * kVertexChunk); ++v) {
        faces.clear();
        for (std::uint32_t n = star_first[v]; n < star_first[v + 1]; ++n) {
          const std::uint32_t t = star[n];
          const Tet& tet = bg_.tets[t];
          const int at = tet[0] == static_cast<int>(v) ? 0 : tet[1] == static_cast<int>(v) ? 1 : tet[2] == static_cast<int>(v) ? 2 : 3;
          // The three faces of t through v: each leaves out one other vertex.
          for (int f = 0; f < 4; ++f) {
            if (f == at) continue;
            int b = -1, c = -1;
            for (int k = 0; k < 4; ++k) {
              if (k == at || k == f) continue;
              (b < 0 ? b : c) = tet[k];
            }
            if (b < static_cast<int>(v) || c < static_cast<int>(v)) continue;  // not its smallest vertex
            faces.push_back({{std::min(b, c), std::max(b, c)}, 4 * t + static_cast<std::uint32_t>(f)});
          }
        }
        std::sort(faces.begin(), faces.end(), [](const StarFace& a, const StarFace& b) {
          return std::tie(a.rest, a.face) < std::tie(b.rest, b.face);
        });
        for (std::size_t i = 0; i < faces.size();) {
          std::size_t j = i + 1;
          while (j < faces.size() && faces[j].rest == faces[i].rest) ++j;
          for (std::size_t k = i; k < j; ++k)
            neighbour[faces[k].face] = j - i == 1 ? kBoundaryFace
                                       : j - i == 2 ? faces[i + (k == i ? 1 : 0)].face
                                                    : kSharedByMore;
          i = j;
        }
      }
    }, /*grain=*/1);
    star.reset();  // 16 bytes a tet, not held through the adjacencies below (peak memory)
    std::vector<std::uint32_t>().swap(star_first);
    // Defects (tets with the same vertices in tet order, then faces shared by more than two tets
    // in face-key order) and boundary faces (in face order: the coverage check reports the one
    // with the smallest key, no sort of them all).
    // Two tets paired across two faces have the same four vertices (one tet twice): a defect,
    // since an adjacency's face is the three vertices its two tets share (LocalRegions::face).
    // Overlaps across a face: the two tets of an interior face must lie on opposite sides of it,
    // i.e. list it in opposite vertex orders (opposite_sides: the tets are positive, so this is
    // combinatorial). Once per face, from the smaller tet; each chunk keeps its face with the
    // smallest key, so the one reported is the same for every thread count.
    using Folded = std::pair<std::array<int, 3>, std::uint32_t>;  // face key, face 4 t + f
    std::vector<std::pair<std::array<int, 3>, std::uint32_t>> shared_by_more;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> same_vertices;
    std::optional<Folded> folded;
    std::size_t folded_count = 0;
    // The background's pieces (tets joined across interior faces), rooted at their smallest tet:
    // one piece unless tet 0 is not every tet's root (see check_pieces).
    MinRootUnionFind pieces(tet_count, threads_);
    {
      std::vector<std::vector<std::uint32_t>> chunk_boundary(tet_chunks);
      std::vector<std::vector<std::pair<std::array<int, 3>, std::uint32_t>>> chunk_shared(tet_chunks);
      std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> chunk_same(tet_chunks);
      std::vector<std::optional<Folded>> chunk_folded(tet_chunks);
      std::vector<std::size_t> chunk_folded_count(tet_chunks, 0);
      parallel_for(threads_, tet_chunks, [&](std::size_t chunk, unsigned) {
        for (std::size_t i = 4 * chunk * kTetChunk; i < 4 * std::min(tet_count, (chunk + 1) * kTetChunk); ++i) {
          const auto face = static_cast<std::uint32_t>(i);
          if (neighbour[i] == kBoundaryFace) chunk_boundary[chunk].push_back(face);
          if (neighbour[i] == kSharedByMore) chunk_shared[chunk].emplace_back(key_of(face / 4, static_cast<int>(face % 4)), face);
          if (neighbour[i] >= kSharedByMore) continue;
          if (face / 4 < neighbour[i] / 4) {
            pieces.unite(face / 4, neighbour[i] / 4);
            if (!opposite_sides(face, neighbour[i])) {
              ++chunk_folded_count[chunk];
              Folded f{key_of(face / 4, static_cast<int>(face % 4)), face};
              if (!chunk_folded[chunk] || f < *chunk_folded[chunk]) chunk_folded[chunk] = f;
            }
          }
          if (face % 4 == 0) continue;
          const std::uint32_t t = face / 4, s = neighbour[i] / 4;
          for (std::uint32_t g = 4 * t; g < face; ++g)
            if (neighbour[g] < kSharedByMore && neighbour[g] / 4 == s && t < s) chunk_same[chunk].emplace_back(t, s);
        }
      }, /*grain=*/1);
      for (std::size_t chunk = 0; chunk < tet_chunks; ++chunk) {
        boundary_.insert(boundary_.end(), chunk_boundary[chunk].begin(), chunk_boundary[chunk].end());
        shared_by_more.insert(shared_by_more.end(), chunk_shared[chunk].begin(), chunk_shared[chunk].end());
        same_vertices.insert(same_vertices.end(), chunk_same[chunk].begin(), chunk_same[chunk].end());
        folded_count += chunk_folded_count[chunk];
        if (chunk_folded[chunk] && (!folded || *chunk_folded[chunk] < *folded)) folded = chunk_folded[chunk];
      }
    }
    if (folded && shared_by_more.empty() && same_vertices.empty()) {
      report_.add(folded_face_defect(bg_, folded->second / 4, neighbour[folded->second] / 4, folded->first, folded_count));
    } else if (shared_by_more.empty() && same_vertices.empty()) {
      check_pieces(pieces);
    }
    pieces.release();
    std::sort(same_vertices.begin(), same_vertices.end());
    same_vertices.erase(std::unique(same_vertices.begin(), same_vertices.end()), same_vertices.end());
    for (const auto& [t, s] : same_vertices) report_.add(same_vertices_defect(t, s, bg_.tets[t]));
    std::sort(shared_by_more.begin(), shared_by_more.end());
    for (std::size_t i = 0; i < shared_by_more.size();) {
      std::size_t j = i + 1;
      while (j < shared_by_more.size() && shared_by_more[j].first == shared_by_more[i].first) ++j;
      const std::array<int, 3>& key = shared_by_more[i].first;
      background_defect(DefectKind::NonManifoldEdge, "background face (" + std::to_string(key[0]) + ", " +
                                                         std::to_string(key[1]) + ", " + std::to_string(key[2]) +
                                                         ") is shared by " + std::to_string(j - i) +
                                                             " tets (an unglued output of immerse has such faces by "
                                                             "design: it cannot be a background)",
                        key);
      i = j;
    }
    // The traced boundary face with the smallest key (keys of boundary faces are distinct).
    std::array<int, 3> crossing_key{};
    for (const std::uint32_t face : boundary_) {
      const auto [lo, hi] = traces_of(face / 4, static_cast<std::uint8_t>(face % 4));
      if (lo == hi) continue;
      const std::array<int, 3> key = key_of(face / 4, static_cast<int>(face % 4));
      if (boundary_crossing_ == kNone || key < crossing_key) {
        boundary_crossing_ = static_cast<std::uint32_t>(lo - traces_.begin());
        crossing_key = key;
      }
    }
    // Adjacencies, tet by tet: those whose `first` lies in tet t come from its faces towards larger
    // tets; sorted and unique per tet, so in tet order they are sorted and unique overall. Counted
    // first, then written at their offsets, on all threads.
    const auto face_lr = [&](std::uint32_t t, std::uint8_t f) {
      if (out_.first[t + 1] - out_.first[t] == 1) return out_.first[t];
      const std::uint32_t lr = face_region_[4 * t + f];
      IMM_ASSERT(lr != kNone, "an untraced face without a local region");
      return lr;
    };
    using Adjacency = LocalRegions::Adjacency;
    const auto tet_adjacencies = [&](std::uint32_t t, std::vector<Adjacency>& list) {
      list.clear();
      for (std::uint8_t f = 0; f < 4; ++f) {
        const std::uint32_t other = neighbour[4 * t + f];
        if (other >= kSharedByMore || other / 4 < t) continue;
        const std::uint32_t s = other / 4;
        const auto g = static_cast<std::uint8_t>(other % 4);
        const auto [alo, ahi] = traces_of(t, f);
        const auto [blo, bhi] = traces_of(s, g);
        IMM_ASSERT(ahi - alo == bhi - blo, "a cut triangle crosses a shared face in one tet only");
        if (alo == ahi) {
          list.push_back({face_lr(t, f), face_lr(s, g), PatchId()});
        } else {
          for (auto x = alo, y = blo; x != ahi; ++x, ++y) {
            IMM_ASSERT(x->triangle == y->triangle, "the two tets of a face see different traces");
            list.push_back({x->outer, y->outer, PatchId()});
            list.push_back({x->inner, y->inner, PatchId()});
          }
        }
      }
      LocalRegions::normalise(list);
    };
    // Per chunk of tets: its count, a prefix sum over the chunks (not over the tets: that was a
    // serial pass), then each chunk writes its tets' lists one after the other.
    constexpr std::size_t kChunk = 2048;
    const std::size_t chunks = (tet_count + kChunk - 1) / kChunk;
    std::vector<std::size_t> chunk_first(chunks + 1, 0);
    parallel_for(threads_, chunks, [&](std::size_t chunk, unsigned) {
      std::vector<Adjacency> list;
      std::size_t n = 0;
      for (std::size_t t = chunk * kChunk; t < std::min(tet_count, (chunk + 1) * kChunk); ++t) {
        tet_adjacencies(static_cast<std::uint32_t>(t), list);
        n += list.size();
      }
      chunk_first[chunk + 1] = n;
    }, /*grain=*/1);
    for (std::size_t chunk = 0; chunk < chunks; ++chunk) chunk_first[chunk + 1] += chunk_first[chunk];
    out_.adjacencies.reserve(chunk_first[chunks]);
    advise_huge_pages(out_.adjacencies);
    out_.adjacencies.resize(chunk_first[chunks]);
    parallel_for(threads_, chunks, [&](std::size_t chunk, unsigned) {
      std::vector<Adjacency> list;
      auto at = out_.adjacencies.begin() + static_cast<std::ptrdiff_t>(chunk_first[chunk]);
      for (std::size_t t = chunk * kChunk; t < std::min(tet_count, (chunk + 1) * kChunk); ++t) {
        tet_adjacencies(static_cast<std::uint32_t>(t), list);
        at = std::copy(list.begin(), list.end(), at);
      }
    }, /*grain=*/1);
  }

  /// Pieces of the background that overlap (overlapping_pieces): only when it has more than one
  /// piece, which costs one parallel pass over the tets to see (tet 0 every tet's root).
  void check_pieces(MinRootUnionFind& pieces) {
    const std::size_t tet_count = bg_.tets.size();
    std::atomic<bool> several{false};
    parallel_blocks(threads_, tet_count, 1 << 14, [&](std::size_t begin, std::size_t end) {
      for (std::size_t t = begin; t < end && !several.load(std::memory_order_relaxed); ++t)
        if (pieces.find(static_cast<std::uint32_t>(t)) != 0) several = true;
    });
    if (!several) return;
    std::vector<std::uint32_t> piece(tet_count);
    parallel_blocks(threads_, tet_count, 1 << 14, [&](std::size_t begin, std::size_t end) {
      for (std::size_t t = begin; t < end; ++t) piece[t] = pieces.find(static_cast<std::uint32_t>(t));
    });
    if (auto d = overlapping_pieces(bg_, piece)) report_.add(std::move(*d));
  }

  [[nodiscard]] bool opposite_sides(std::uint32_t face, std::uint32_t other) const {
    return detail::opposite_sides(bg_, face, other);
  }

  /// The traces of tet t on face f (traces_ is in (tet, face, triangle) order).
  [[nodiscard]] std::pair<std::vector<Trace>::const_iterator, std::vector<Trace>::const_iterator> traces_of(
      std::uint32_t t, std::uint8_t f) const {
    auto lo = traces_.cbegin() + trace_first_[t];
    const auto end = traces_.cbegin() + trace_first_[t + 1];
    while (lo != end && lo->face < f) ++lo;
    auto hi = lo;
    while (hi != end && hi->face == f) ++hi;
    return {lo, hi};
  }

  void background_defect(DefectKind kind, std::string message, const std::array<int, 3>& face) {
    Defect d;
    d.kind = kind;
    d.stage = "background";
    d.message = std::move(message);
    d.vertices = {face[0], face[1], face[2]};
    report_.add(std::move(d));
  }

  // ---- regions --------------------------------------------------------------------------------

  void resolve_regions() {
    out_.resolve_regions([&](std::uint32_t lr) { return locate(out_.element[lr]); }, threads_);
  }


  /// The region holding the centroid of tet t (a tet the input does not meet): the first cut
  /// triangle crossed by an exact segment from it to a point inside some cut triangle.
  RegionId locate(std::uint32_t t) const {
    const auto corner_point = [&](int k) { return background_point<EK>(static_cast<std::size_t>(bg_.tets[t][k])); };
    Point q = CGAL::centroid(corner_point(0), corner_point(1), corner_point(2), corner_point(3));
    std::vector<std::uint32_t> all(m_.triangles.size());
    std::iota(all.begin(), all.end(), 0u);
    for (std::uint32_t aim = 0; aim < m_.triangles.size(); ++aim) {
      for (unsigned variant = 0; variant < 4; ++variant) {
        Polygon p;
        for (int k = 0; k < 3; ++k) p.vertices.push_back({corner(aim, k), 0, -1});
        const auto hit = first_crossing<EK>(q, interior_point<EK>(p, 3 * variant), m_.triangle_source[aim], all);
        if (hit) return side_region(hit->first, hit->second);
      }
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
    // The input must not cross the background's boundary, and no boundary face may have a cell
    // on its inner side (the background would end inside a cell).
    if (boundary_crossing_ != kNone) {
      const Trace& tr = traces_[boundary_crossing_];
      const Point3& p = bg_.vertices[static_cast<std::size_t>(bg_.tets[tr.tet][kFace[tr.face][0]])];
      not_covered("the input (triangle " + std::to_string(m_.triangle_source[tr.triangle]) +
                      ") crosses the boundary of the background mesh at boundary tet " + std::to_string(tr.tet) +
                      " near " + format_point(p),
                  p);
      return;
    }
    // Of the boundary faces with a cell on their inner side, the one with the smallest key.
    std::uint32_t inside = kNone;
    std::array<int, 3> inside_key{};
    int inside_winding = 0;
    for (const std::uint32_t face : boundary_) {
      const std::uint32_t t = face / 4, f = face % 4;
      if (out_.first[t + 1] - out_.first[t] > 1 && face_region_[face] == kNone) continue;  // traced
      const std::uint32_t lr = out_.first[t + 1] - out_.first[t] == 1 ? out_.first[t] : face_region_[face];
      const int w = c_.complex.winding_number(out_.region[lr]);
      if (w == 0) continue;
      std::array<int, 3> key = {bg_.tets[t][kFace[f][0]], bg_.tets[t][kFace[f][1]], bg_.tets[t][kFace[f][2]]};
      std::sort(key.begin(), key.end());
      if (inside == kNone || key < inside_key) {
        inside = face;
        inside_key = key;
        inside_winding = w;
      }
    }
    if (inside != kNone) {
      const std::uint32_t t = inside / 4, f = inside % 4;
      const Point3& p = bg_.vertices[static_cast<std::size_t>(bg_.tets[t][kFace[f][0]])];
      not_covered("the background mesh ends inside a cell (winding number " + std::to_string(inside_winding) +
                      ") at boundary tet " + std::to_string(t) + " near " + format_point(p),
                  p);
      return;
    }
    for (std::uint32_t x = 0; x < m_.triangles.size(); ++x) {
      if (triangle_has_polygon_[x]) continue;
      const Point& a = corner(x, 0);
      const Point3 p{CGAL::to_double(a.x()), CGAL::to_double(a.y()), CGAL::to_double(a.z())};
      not_covered("the background mesh does not cover input triangle " + std::to_string(m_.triangle_source[x]) +
                      " near " + format_point(p),
                  p);
      return;
    }
  }

  const unsigned threads_;
  const bool interval_filter_;
  const Point3 shift_;
  const Complex& c_;
  const CutMesh& m_;
  const TetMesh& bg_;
  const bool record_;
  ValidationReport& report_;
  bool& non_generic_;

  const std::vector<Point>* input_points_ = nullptr;  ///< cut-mesh points (shifted when asked)
  std::vector<Point> shifted_points_;
  std::vector<IK::Point_3> input_intervals_;
  std::unordered_map<std::uint64_t, std::uint32_t> arc_edge_;  ///< geometric cut edge -> CutPiece
  std::vector<std::pair<std::uint32_t, std::uint32_t>> candidates_;
  std::vector<std::uint32_t> cand_first_;  ///< candidates of tet t: cand_first_[t] .. [t+1]-1
  std::vector<Trace> traces_;               ///< in (tet, face, triangle) order
  std::vector<std::uint32_t> trace_first_{0};  ///< traces of tet t: trace_first_[t] .. [t+1]-1
  /// Per face 4 t + f of a tet with candidates: its local region when untraced, else kNone
  /// (uninitialised for the other tets, never read: they have one local region).
  std::unique_ptr<std::uint32_t[]> face_region_;
  std::vector<char> triangle_has_polygon_;
  std::vector<std::uint32_t> boundary_;       ///< boundary faces 4 t + f, in face order
  std::uint32_t boundary_crossing_ = kNone;  ///< a trace on a boundary face, if any
  LocalRegions out_;
};

}  // namespace

LocalRegions compute_local_regions(const Complex& complex, const TetMesh& background, const Point3& shift,
                                   bool record_embedded, unsigned threads, bool interval_filter,
                                   ValidationReport& report, bool& non_generic) {
  IMM_ASSERT(complex.exact != nullptr, "complex without exact geometry");
  threads = resolve_threads(threads);
  if (background.tets.size() > kMaxBackgroundTets) {
    // Faces are numbered 4 t + f in 32 bits (connect_faces): a larger background would overflow.
    Defect d;
    d.kind = DefectKind::OutOfRange;
    d.stage = "background";
    d.message = "the background mesh has " + std::to_string(background.tets.size()) + " tets, more than the " +
                std::to_string(kMaxBackgroundTets) + " the mesher takes";
    report.add(std::move(d));
    non_generic = false;
    return LocalRegions();
  }
  return VirtualTets(complex, background, shift, record_embedded, threads, interval_filter, report, non_generic)
      .run();
}

ValidationReport check_background_overlap(const TetMesh& background) {
  ValidationReport report;
  const std::size_t n = background.tets.size();
  if (n > kMaxBackgroundTets) return report;  // refused by compute_local_regions*
  std::vector<std::pair<std::array<int, 3>, std::uint32_t>> faces;
  faces.reserve(4 * n);
  for (std::uint32_t t = 0; t < n; ++t)
    for (int f = 0; f < 4; ++f) {
      std::array<int, 3> key = {background.tets[t][kFace[f][0]], background.tets[t][kFace[f][1]],
                                background.tets[t][kFace[f][2]]};
      std::sort(key.begin(), key.end());
      faces.emplace_back(key, 4 * t + static_cast<std::uint32_t>(f));
    }
  std::sort(faces.begin(), faces.end());
  UnionFind pieces(n);
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].first == faces[i].first) ++j;
    if (j - i > 2) return report;  // a face shared by more tets: reported where faces are paired
    if (j - i == 2) {
      const std::uint32_t face = faces[i].second, other = faces[i + 1].second;
      Tet a = background.tets[face / 4], b = background.tets[other / 4];
      std::sort(a.begin(), a.end());
      std::sort(b.begin(), b.end());
      if (a == b) return report;  // one tet twice: reported where faces are paired
      if (!opposite_sides(background, face, other)) {
        // Faces in key order: the smallest key, as the clipping path reports it (uncounted here).
        report.add(folded_face_defect(background, face / 4, other / 4, faces[i].first, 1));
        return report;
      }
      pieces.unite(face / 4, other / 4);
    }
    i = j;
  }
  std::vector<std::uint32_t> piece(n);
  bool several = false;
  for (std::uint32_t t = 0; t < n; ++t) {
    piece[t] = pieces.find(t);
    several = several || piece[t] != piece[0];
  }
  if (several)
    if (auto d = overlapping_pieces(background, piece)) report.add(std::move(*d));
  return report;
}

}  // namespace imm::dim3::detail
