// Virtual triangles (paper §7.1 with d = 2): the exact local regions of every background triangle.
//
// For each background triangle t:
//  - the cut segments whose (conservative) bounding boxes overlap t are clipped to the closed
//    triangle, exactly (Sutherland–Hodgman against the three edge half-planes, Epeck);
//  - a triangle with no clipped piece of positive length has one local region (its interior is
//    free of the input); its region is found by flood fill (below);
//  - when every piece is a chord between the interiors of two edges (the common case away from
//    input vertices and crossings), the k disjoint chords split t into k + 1 local regions read
//    off the cyclic order of their ends around the boundary (process_chords);
//  - otherwise the pieces and the three edges go into a small exact arrangement whose bounded
//    faces are the local regions ("atoms") of t. The region of a face is read off any boundary
//    halfedge that lies on a cut segment: the face is on the halfedge's left, so it is the
//    segment's inner (negative) side when the halfedge runs along the segment, else the outer
//    one. Every face of a triangle with pieces has such a halfedge.
//
// DEVIATION from the paper (accepted for 2D): §7.1.1 builds a region graph per element with
// angle-weighted pseudo-normal inside tests against the pieces. Here the local regions are the
// faces of an exact arrangement instead. Reason: it is exact in every degenerate contact — the
// input through a triangle vertex, along a triangle edge, a vertex of the input on an edge, pieces
// meeting at a crossing point inside the triangle — with no epsilon and no special case, and
// it is cheap for the few pieces one triangle holds.
//
// Local regions are connected across shared edges where their parts of the edge overlap along a
// positive length (exact comparisons along the edge). Regions of triangles without pieces come
// from union-find over those input-free overlaps, seeded by faces with known regions; a flood
// component without any known member gets one exact ray shooting against the cut segments.
#include <CGAL/Arr_consolidated_curve_data_traits_2.h>
#include <CGAL/Arr_extended_dcel.h>
#include <CGAL/Arr_segment_traits_2.h>
#include <CGAL/Arrangement_2.h>
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <sstream>
#include <tuple>

#include "core/union_find.h"
#include "core/unglue.h"
#include "dim2/cut_curve.h"
#include "dim2/kernel.h"
#include "dim2/mesh2_detail.h"

namespace imm::dim2::detail {

namespace {

using SegmentTraits = CGAL::Arr_segment_traits_2<Kernel>;
/// Curve data: 0, 1, 2 for the triangle edges, 3 + j for piece j.
using DataTraits = CGAL::Arr_consolidated_curve_data_traits_2<SegmentTraits, int>;
using Dcel = CGAL::Arr_face_extended_dcel<DataTraits, int>;
using Arrangement = CGAL::Arrangement_2<DataTraits, Dcel>;
using ArrCurve = DataTraits::Curve_2;

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

/// What a constructed point is, when known: two triangles (or two pieces) that computed the same
/// point separately recognise it without comparing lazy-exact coordinates (comparing two equal
/// constructed points forces the exact evaluation of both). Unknown or different keys fall back
/// to exact comparisons of the points, so keys only save time; they never decide alone that two
/// points differ.
struct Key {
  enum Kind : std::uint8_t { Unknown, Vertex, Crossing, Source, Target };
  Kind kind = Unknown;
  std::uint32_t id = 0;    ///< background vertex (Vertex) or cut segment (Crossing, Source, Target)
  std::uint64_t edge = 0;  ///< Crossing: the background edge whose line the segment's line meets
  bool operator==(const Key&) const = default;
};

/// A point with its key.
struct Mark {
  Point_2 point;
  Key key;
};

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  return (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
}

/// Orders points on one line along a direction (`dir` = compare_xy of the direction's ends).
bool before(const Mark& a, const Mark& b, CGAL::Comparison_result dir) {
  if (a.key.kind != Key::Unknown && a.key == b.key) return false;
  return CGAL::compare_xy(a.point, b.point) == dir;
}

bool same_point(const Mark& a, const Mark& b) {
  if (a.key.kind != Key::Unknown && a.key == b.key) return true;
  return a.point == b.point;
}

/// A piece of a cut segment inside one closed triangle, oriented like the segment.
struct Piece {
  Mark source;
  Mark target;
  std::uint32_t segment;
};

/// Part of a triangle edge on the boundary of one local region, oriented like the edge
/// (counter-clockwise around the triangle).
struct EdgeInterval {
  Mark source;
  Mark target;
  std::uint32_t local_region;
  PatchId patch;       ///< valid when the input runs along this part of the edge
  bool inner = false;  ///< the local region is on the patch's inner side
};

enum class Clip { Empty, Point, Segment };

class LocalRegionBuilder {
 public:
  LocalRegionBuilder(const Complex2& complex, const Background& background, bool record_pieces,
                     ValidationReport& report)
      : complex_(complex),
        cut_(*complex.exact),
        background_(background),
        record_pieces_(record_pieces),
        report_(report) {}

  LocalRegions run() {
    make_points();
    find_candidates();
    segment_pieces_.resize(cut_.segments.size());
    out_.first.reserve(background_.triangles.size() + 1);
    out_.vertices.resize(cut_.input_points.size());
    for (std::size_t v = 0; v < cut_.vertex_patch.size(); ++v)
      out_.vertices[v].patch = cut_.vertex_patch[v];
    cut_index_.assign(background_.triangles.size(), kNone);
    std::size_t next_candidate = 0;
    for (std::uint32_t t = 0; t < background_.triangles.size(); ++t) {
      const std::size_t begin = next_candidate;
      while (next_candidate < candidates_.size() && candidates_[next_candidate].first == t)
        ++next_candidate;
      out_.begin_element();
      process_triangle(t, begin, next_candidate);
      out_.end_element();
    }
    out_.finish();
    connect_edges();
    if (!report_.ok()) return std::move(out_);
    resolve_regions();
    check_coverage();
    return std::move(out_);
  }

 private:
  // ---- set-up ----------------------------------------------------------------------------

  void make_points() {
    const std::size_t n = background_.vertices.size();
    points_.reserve(n);
    if (background_.exact_vertices.empty()) {
      for (const Point& p : background_.vertices) points_.emplace_back(p.x, p.y);
    } else {
      for (const auto& q : background_.exact_vertices) points_.emplace_back(FT(q[0]), FT(q[1]));
    }
    // Original input segment i joins vertex i and the next vertex of its curve.
    std::vector<std::size_t> next_vertex;
    for (const Curve& curve : complex_.curves.curves) {
      const std::size_t offset = next_vertex.size();
      for (std::size_t l = 0; l < curve.vertices.size(); ++l)
        next_vertex.push_back(offset + (l + 1) % curve.vertices.size());
    }
    IMM_ASSERT(next_vertex.size() == cut_.input_points.size(), "curve sizes and input points differ");
    segment_vertex_.resize(cut_.segments.size(), {-1, -1});
    for (std::size_t s = 0; s < cut_.segments.size(); ++s) {
      const CutSegment& seg = cut_.segments[s];
      const std::size_t ends[2] = {seg.input_segment, next_vertex[seg.input_segment]};
      for (std::size_t v : ends) {
        if (seg.source == cut_.input_points[v]) segment_vertex_[s][0] = static_cast<long>(v);
        if (seg.target == cut_.input_points[v]) segment_vertex_[s][1] = static_cast<long>(v);
      }
    }
  }

  /// (triangle, segment) pairs whose bounding boxes overlap, sorted. Long segments are split
  /// into chunks about one triangle long so that the number of pairs stays proportional to the
  /// number of triangles a segment actually crosses. Chunk boxes are enlarged by a bound on the
  /// rounding error: this is a conservative filter; the decisions are the exact clippings.
  void find_candidates() {
    using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 2, std::uint32_t>;
    const auto& triangles = background_.triangles;
    std::vector<Box> triangle_boxes;
    triangle_boxes.reserve(triangles.size());
    double extent_sum = 0.0;
    for (std::uint32_t t = 0; t < triangles.size(); ++t) {
      CGAL::Bbox_2 b = points_[triangles[t][0]].bbox() + points_[triangles[t][1]].bbox() +
                       points_[triangles[t][2]].bbox();
      extent_sum += std::max(b.xmax() - b.xmin(), b.ymax() - b.ymin());
      triangle_boxes.emplace_back(b, t);
    }
    const double step = triangles.empty() ? 1.0 : extent_sum / static_cast<double>(triangles.size());
    constexpr double kEps = std::numeric_limits<double>::epsilon();
    std::vector<Box> chunk_boxes;
    for (std::uint32_t s = 0; s < cut_.segments.size(); ++s) {
      const CutSegment& seg = cut_.segments[s];
      const CGAL::Bbox_2 bs = seg.source.bbox();
      const CGAL::Bbox_2 bt = seg.target.bbox();
      const double ax = 0.5 * (bs.xmin() + bs.xmax()), ay = 0.5 * (bs.ymin() + bs.ymax());
      const double bx = 0.5 * (bt.xmin() + bt.xmax()), by = 0.5 * (bt.ymin() + bt.ymax());
      const double magnitude = std::max({std::abs(ax), std::abs(ay), std::abs(bx), std::abs(by)});
      const double margin = 2.0 * std::max({bs.xmax() - bs.xmin(), bs.ymax() - bs.ymin(),
                                            bt.xmax() - bt.xmin(), bt.ymax() - bt.ymin()}) +
                            16.0 * kEps * magnitude + std::numeric_limits<double>::min();
      const double length = std::max(std::abs(bx - ax), std::abs(by - ay));
      const auto chunks =
          static_cast<std::uint32_t>(std::clamp(std::ceil(length / step), 1.0, 1.0e6));
      for (std::uint32_t i = 0; i < chunks; ++i) {
        const double t0 = static_cast<double>(i) / chunks;
        const double t1 = static_cast<double>(i + 1) / chunks;
        const double x0 = ax + (bx - ax) * t0, y0 = ay + (by - ay) * t0;
        const double x1 = i + 1 == chunks ? bx : ax + (bx - ax) * t1;
        const double y1 = i + 1 == chunks ? by : ay + (by - ay) * t1;
        chunk_boxes.emplace_back(CGAL::Bbox_2(std::min(x0, x1) - margin, std::min(y0, y1) - margin,
                                              std::max(x0, x1) + margin, std::max(y0, y1) + margin),
                                 s | 0x80000000u);
      }
    }
    IMM_ASSERT(triangles.size() < 0x80000000u && cut_.segments.size() < 0x80000000u,
               "too many triangles or segments for the candidate filter");
    CGAL::box_intersection_d(triangle_boxes.begin(), triangle_boxes.end(), chunk_boxes.begin(),
                             chunk_boxes.end(), [&](const Box& a, const Box& b) {
                               std::uint32_t t = a.info(), s = b.info();
                               if (t & 0x80000000u) std::swap(t, s);
                               candidates_.emplace_back(t, s & 0x7fffffffu);
                             });
    std::sort(candidates_.begin(), candidates_.end());
    candidates_.erase(std::unique(candidates_.begin(), candidates_.end()), candidates_.end());
  }

  // ---- one triangle ------------------------------------------------------------------------

  std::array<Point_2, 3> triangle_points(std::uint32_t t) const {
    const auto& v = background_.triangles[t];
    return {points_[v[0]], points_[v[1]], points_[v[2]]};
  }

  void process_triangle(std::uint32_t t, std::size_t begin, std::size_t end) {
    if (begin == end) {
      out_.add_local_region(t);
      return;
    }
    const std::array<Point_2, 3> tri = triangle_points(t);
    if (process_chords(t, tri, begin, end)) return;
    std::vector<Piece> pieces;
    for (std::size_t c = begin; c < end; ++c) {
      const std::uint32_t s = candidates_[c].second;
      Piece piece{{cut_.segments[s].source, {Key::Source, s}},
                  {cut_.segments[s].target, {Key::Target, s}},
                  s};
      if (clip_to_triangle(t, tri, piece) == Clip::Segment) pieces.push_back(piece);
    }
    if (pieces.empty()) {
      // Touched at isolated points at most: the interior is free of the input.
      out_.add_local_region(t);
      return;
    }
    for (const Piece& piece : pieces)
      segment_pieces_[piece.segment].push_back({piece.source, piece.target});

    Arrangement arr;
    std::vector<ArrCurve> curves;
    curves.reserve(3 + pieces.size());
    for (int k = 0; k < 3; ++k) curves.emplace_back(Segment_2(tri[k], tri[(k + 1) % 3]), k);
    for (std::size_t j = 0; j < pieces.size(); ++j)
      curves.emplace_back(Segment_2(pieces[j].source.point, pieces[j].target.point),
                          static_cast<int>(3 + j));
    CGAL::insert(arr, curves.begin(), curves.end());

    const std::uint32_t base = static_cast<std::uint32_t>(out_.region.size());
    int faces = 0;
    for (auto f = arr.faces_begin(); f != arr.faces_end(); ++f) {
      if (f->is_unbounded()) continue;
      f->set_data(faces++);
      out_.add_local_region(t);
    }
    const std::uint32_t cut = static_cast<std::uint32_t>(cut_edges_.size());
    cut_index_[t] = cut;
    cut_edges_.emplace_back();
    std::vector<LocalRegions::Fusion> fusions;

    auto visit = [&](Arrangement::Halfedge_const_handle h) {
      const std::uint32_t lr = base + static_cast<std::uint32_t>(h->face()->data());
      int edge = -1;
      int piece = -1;
      for (int d : h->curve().data()) {
        if (d < 3) {
          IMM_ASSERT(edge < 0, "two triangle edges overlap");
          edge = d;
        } else {
          IMM_ASSERT(piece < 0, "two cut segments overlap");
          piece = d - 3;
        }
      }
      bool inner = false;
      PatchId patch;
      if (piece >= 0) {
        const std::uint32_t s = pieces[static_cast<std::size_t>(piece)].segment;
        const CutSegment& seg = cut_.segments[s];
        patch = seg.patch;
        inner = CGAL::compare_xy(h->source()->point(), h->target()->point()) ==
                CGAL::compare_xy(seg.source, seg.target);
        const PatchSides& sides = complex_.complex.sides(patch);
        LocalRegions::set_region(out_.region, lr, inner ? sides.negative : sides.positive);
        if (inner) {
          if (edge < 0) {
            const std::uint32_t other = base + static_cast<std::uint32_t>(h->twin()->face()->data());
            fusions.push_back({lr, other, patch});
          }
          if (record_pieces_) out_.inner_pieces.push_back({lr, patch, seg.input_segment});
          locate_vertices(tri, s, h, lr);
        }
      }
      if (edge >= 0) {
        IMM_ASSERT(CGAL::compare_xy(h->source()->point(), h->target()->point()) ==
                       CGAL::compare_xy(tri[edge], tri[(edge + 1) % 3]),
                   "triangle edge halfedge against the edge direction");
        cut_edges_[cut][edge].push_back({vertex_mark(t, tri, edge, h->source()->point()),
                                          vertex_mark(t, tri, (edge + 1) % 3, h->target()->point()),
                                          lr, patch, inner});
      }
    };
    for (auto f = arr.faces_begin(); f != arr.faces_end(); ++f) {
      if (f->is_unbounded()) continue;
      auto h = f->outer_ccb();
      const auto first = h;
      do visit(h);
      while (++h != first);
      for (auto hole = f->inner_ccbs_begin(); hole != f->inner_ccbs_end(); ++hole) {
        auto g = *hole;
        const auto start = g;
        do visit(g);
        while (++g != start);
      }
    }
    for (std::uint32_t lr = base; lr < out_.region.size(); ++lr)
      IMM_ASSERT(out_.region[lr].is_valid(), "a face of a cut triangle has no input on its boundary");
    out_.add_fusions(std::move(fusions));
  }

  /// The crossing of cut segment s's line with the line of background edge (a, b), computed the
  /// same way from both triangles of the edge. @pre the lines cross.
  Mark crossing(std::uint32_t s, std::uint32_t a, std::uint32_t b) const {
    if (a > b) std::swap(a, b);
    const CutSegment& seg = cut_.segments[s];
    const Point_2& u = points_[a];
    const Point_2& v = points_[b];
    const FT du = CGAL::determinant(seg.target - seg.source, u - seg.source);
    const FT dv = CGAL::determinant(seg.target - seg.source, v - seg.source);
    return {u + (v - u) * (du / (du - dv)), {Key::Crossing, s, edge_key(a, b)}};
  }

  /// Exact Sutherland–Hodgman clipping of a piece (initially the whole segment) to the closed
  /// counter-clockwise triangle t: the piece is cut by the three edge half-planes in turn.
  Clip clip_to_triangle(std::uint32_t t, const std::array<Point_2, 3>& tri, Piece& piece) const {
    const auto& v = background_.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const Point_2& a = tri[k];
      const Point_2& b = tri[(k + 1) % 3];
      const CGAL::Orientation op = CGAL::orientation(a, b, piece.source.point);
      const CGAL::Orientation oq = CGAL::orientation(a, b, piece.target.point);
      if (op != CGAL::RIGHT_TURN && oq != CGAL::RIGHT_TURN) continue;
      if (op == CGAL::RIGHT_TURN && oq == CGAL::RIGHT_TURN) return Clip::Empty;
      // One end strictly outside: replace it by the crossing with the edge's line (the piece
      // lies on the segment's line, so this is the segment's crossing with that line).
      const Mark x = crossing(piece.segment, static_cast<std::uint32_t>(v[k]),
                              static_cast<std::uint32_t>(v[(k + 1) % 3]));
      (op == CGAL::RIGHT_TURN ? piece.source : piece.target) = x;
    }
    return same_point(piece.source, piece.target) ? Clip::Point : Clip::Segment;
  }

  /// A point of triangle edge k's line, keyed as the background vertex when it is triangle
  /// vertex `corner` (an end of the edge).
  Mark vertex_mark(std::uint32_t t, const std::array<Point_2, 3>& tri, int corner,
                   const Point_2& p) const {
    if (p == tri[corner])
      return {p, {Key::Vertex, static_cast<std::uint32_t>(background_.triangles[t][corner])}};
    return {p, {}};
  }

  /// The common case, without an arrangement: every nearby segment either misses the closed
  /// triangle or crosses it as a chord between the interiors of two edges (its line avoids the
  /// three vertices and both its ends lie strictly outside). Cut segments meet only at their ends,
  /// so such chords are pairwise disjoint, and k chords cut the triangle into k + 1 local regions
  /// read off the cyclic order of the chord ends around the boundary.
  /// @return false (having changed nothing) when some segment is not of that kind.
  bool process_chords(std::uint32_t t, const std::array<Point_2, 3>& tri, std::size_t begin,
                      std::size_t end) {
    struct Chord {
      std::uint32_t segment;
      int entry_edge, exit_edge;
      Mark entry, exit;
    };
    const auto& v = background_.triangles[t];
    std::vector<Chord> chords;
    for (std::size_t c = begin; c < end; ++c) {
      const std::uint32_t s = candidates_[c].second;
      const CutSegment& seg = cut_.segments[s];
      CGAL::Orientation side[3];
      for (int k = 0; k < 3; ++k) {
        side[k] = CGAL::orientation(seg.source, seg.target, tri[k]);
        if (side[k] == CGAL::COLLINEAR) return false;  // the line meets a vertex
      }
      if (side[0] == side[1] && side[1] == side[2]) continue;  // the line misses the triangle
      for (const Point_2* end_point : {&seg.source, &seg.target}) {
        bool inside = true;
        for (int k = 0; k < 3; ++k)
          inside = inside && CGAL::orientation(tri[k], tri[(k + 1) % 3], *end_point) != CGAL::RIGHT_TURN;
        if (inside) return false;  // an end of the segment in the closed triangle
      }
      int crossed[2] = {-1, -1};
      for (int k = 0; k < 3; ++k)
        if (side[k] != side[(k + 1) % 3]) crossed[crossed[0] < 0 ? 0 : 1] = k;
      // Both ends strictly outside: the segment holds the whole chord iff it crosses the line of
      // one crossed edge (its ends cannot lie on that line: the crossing is inside the edge).
      const Point_2& a = tri[crossed[0]];
      const Point_2& b = tri[(crossed[0] + 1) % 3];
      const CGAL::Orientation from = CGAL::orientation(a, b, seg.source);
      if (from == CGAL::orientation(a, b, seg.target)) continue;
      // The segment enters through the edge whose outside holds its source.
      const int entry = from == CGAL::RIGHT_TURN ? crossed[0] : crossed[1];
      const int exit = entry == crossed[0] ? crossed[1] : crossed[0];
      const auto at = [&](int k) {
        return crossing(s, static_cast<std::uint32_t>(v[k]), static_cast<std::uint32_t>(v[(k + 1) % 3]));
      };
      chords.push_back({s, entry, exit, at(entry), at(exit)});
    }
    if (chords.empty()) {
      out_.add_local_region(t);
      return true;
    }
    // Chord ends around the boundary, counter-clockwise: edge 0, edge 1, edge 2.
    struct End {
      const Mark* mark;
      std::size_t chord;
      bool entry;
    };
    std::array<std::vector<End>, 3> on_edge;
    for (std::size_t c = 0; c < chords.size(); ++c) {
      on_edge[chords[c].entry_edge].push_back({&chords[c].entry, c, true});
      on_edge[chords[c].exit_edge].push_back({&chords[c].exit, c, false});
    }
    std::vector<End> ends;
    std::array<std::size_t, 3> edge_offset{};
    for (int k = 0; k < 3; ++k) {
      const CGAL::Comparison_result dir = CGAL::compare_xy(tri[k], tri[(k + 1) % 3]);
      std::sort(on_edge[k].begin(), on_edge[k].end(),
                [dir](const End& x, const End& y) { return before(*x.mark, *y.mark, dir); });
      edge_offset[k] = ends.size();
      ends.insert(ends.end(), on_edge[k].begin(), on_edge[k].end());
    }
    // Boundary interval i runs from end i to end i+1. Walking counter-clockwise, the arc from a
    // chord's entry A to its exit B lies on the chord's right (outer side), the arc from B to A
    // on its left (inner side).
    const std::size_t n = ends.size();
    std::vector<std::size_t> entry_at(chords.size()), exit_at(chords.size());
    for (std::size_t i = 0; i < n; ++i) (ends[i].entry ? entry_at : exit_at)[ends[i].chord] = i;
    UnionFind faces(n);
    for (std::size_t c = 0; c < chords.size(); ++c) {
      faces.unite(static_cast<std::uint32_t>(entry_at[c]), static_cast<std::uint32_t>((exit_at[c] + n - 1) % n));
      faces.unite(static_cast<std::uint32_t>(exit_at[c]), static_cast<std::uint32_t>((entry_at[c] + n - 1) % n));
    }
    std::vector<std::uint32_t> face_of_root(n, kNone);
    std::vector<std::uint32_t> local(n);
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t root = faces.find(static_cast<std::uint32_t>(i));
      if (face_of_root[root] == kNone) face_of_root[root] = out_.add_local_region(t);
      local[i] = face_of_root[root];
    }
    std::vector<LocalRegions::Fusion> fusions;
    for (std::size_t c = 0; c < chords.size(); ++c) {
      const Chord& chord = chords[c];
      const PatchId patch = cut_.segments[chord.segment].patch;
      const PatchSides& sides = complex_.complex.sides(patch);
      const std::uint32_t outer = local[entry_at[c]];
      const std::uint32_t inner = local[exit_at[c]];
      IMM_ASSERT(outer != inner, "a chord with one local region on both sides");
      LocalRegions::set_region(out_.region, outer, sides.positive);
      LocalRegions::set_region(out_.region, inner, sides.negative);
      fusions.push_back({inner, outer, patch});
      if (record_pieces_) out_.inner_pieces.push_back({inner, patch, cut_.segments[chord.segment].input_segment});
      segment_pieces_[chord.segment].push_back({chord.entry, chord.exit});
    }
    out_.add_fusions(std::move(fusions));
    // Edge parts: edge k runs from its first vertex through its chord ends to its second vertex;
    // the part before its first end belongs to the interval ending there.
    const std::uint32_t cut = static_cast<std::uint32_t>(cut_edges_.size());
    cut_index_[t] = cut;
    cut_edges_.emplace_back();
    for (int k = 0; k < 3; ++k) {
      Mark from{tri[k], {Key::Vertex, static_cast<std::uint32_t>(v[k])}};
      std::size_t interval = (edge_offset[k] + n - 1) % n;
      for (std::size_t j = 0; j < on_edge[k].size(); ++j) {
        const std::size_t at = edge_offset[k] + j;
        cut_edges_[cut][k].push_back({from, *ends[at].mark, local[interval], PatchId(), false});
        from = *ends[at].mark;
        interval = at;
      }
      const int next = (k + 1) % 3;
      cut_edges_[cut][k].push_back({from,
                                    {tri[next], {Key::Vertex, static_cast<std::uint32_t>(v[next])}},
                                    local[interval],
                                    PatchId(),
                                    false});
    }
    return true;
  }

  /// An input vertex at an end of halfedge h (which runs along cut segment s, with local region
  /// lr on its left = the inner side) is embedded in lr. The first triangle found wins.
  void locate_vertices(const std::array<Point_2, 3>& tri, std::uint32_t s,
                       Arrangement::Halfedge_const_handle h, std::uint32_t lr) {
    for (long v : segment_vertex_[s]) {
      if (v < 0) continue;
      auto& location = out_.vertices[static_cast<std::size_t>(v)];
      if (location.local_region != kNone) continue;
      const Point_2& p = cut_.input_points[static_cast<std::size_t>(v)];
      if (h->source()->point() != p && h->target()->point() != p) continue;
      const FT area = CGAL::area(tri[0], tri[1], tri[2]);
      const FT w0 = CGAL::area(p, tri[1], tri[2]) / area;
      const FT w1 = CGAL::area(tri[0], p, tri[2]) / area;
      const FT w2 = CGAL::area(tri[0], tri[1], p) / area;
      location.local_region = lr;
      location.weights = {CGAL::to_double(CGAL::exact(w0)), CGAL::to_double(CGAL::exact(w1)),
                          CGAL::to_double(CGAL::exact(w2))};
    }
  }

  // ---- edges ---------------------------------------------------------------------------

  /// The parts of edge k of triangle t, in the edge's counter-clockwise direction.
  std::vector<EdgeInterval> edge_intervals(std::uint32_t t, int k) const {
    if (cut_index_[t] != kNone) return cut_edges_[cut_index_[t]][k];
    const auto& v = background_.triangles[t];
    const int next = (k + 1) % 3;
    return {{{points_[v[k]], {Key::Vertex, static_cast<std::uint32_t>(v[k])}},
             {points_[v[next]], {Key::Vertex, static_cast<std::uint32_t>(v[next])}},
             out_.first[t],
             PatchId(),
             false}};
  }

  /// Pairs the triangles across every edge. Edges are bucketed by their smaller vertex (linear
  /// time; a global sort of 3 x 10^6 edge records was the largest single cost at 10^6 triangles).
  void connect_edges() {
    struct EdgeRef {
      std::uint32_t other;  ///< the larger vertex id
      std::uint32_t triangle;
      std::uint8_t k;
    };
    const auto& triangles = background_.triangles;
    std::vector<std::uint32_t> bucket_start(background_.vertices.size() + 1, 0);
    for (const auto& t : triangles)
      for (int k = 0; k < 3; ++k) ++bucket_start[std::min(t[k], t[(k + 1) % 3]) + 1];
    for (std::size_t v = 0; v + 1 < bucket_start.size(); ++v) bucket_start[v + 1] += bucket_start[v];
    std::vector<EdgeRef> edges(3 * triangles.size());
    {
      std::vector<std::uint32_t> next(bucket_start.begin(), bucket_start.end() - 1);
      for (std::uint32_t t = 0; t < triangles.size(); ++t)
        for (std::uint8_t k = 0; k < 3; ++k) {
          const auto a = static_cast<std::uint32_t>(triangles[t][k]);
          const auto b = static_cast<std::uint32_t>(triangles[t][(k + 1) % 3]);
          edges[next[std::min(a, b)]++] = {std::max(a, b), t, k};
        }
    }
    out_.adjacencies.reserve(edges.size() / 2);
    for (std::size_t lo = 0; lo + 1 < bucket_start.size(); ++lo) {
      const auto first = edges.begin() + bucket_start[lo];
      const auto last = edges.begin() + bucket_start[lo + 1];
      std::stable_sort(first, last, [](const EdgeRef& x, const EdgeRef& y) { return x.other < y.other; });
      for (auto i = first; i != last;) {
        auto j = i + 1;
        while (j != last && j->other == i->other) ++j;
        const std::array<int, 2> edge = {static_cast<int>(lo), static_cast<int>(i->other)};
        const auto count = j - i;
        if (count == 1) {
          boundary_edges_.push_back({i->triangle, i->k});
        } else if (count > 2) {
          Defect d;
          d.kind = DefectKind::NonManifoldEdge;
          d.stage = "background";
          d.message = "background edge (" + std::to_string(edge[0]) + ", " +
                      std::to_string(edge[1]) + ") is shared by " + std::to_string(count) +
                      " triangles";
          d.vertices = {edge[0], edge[1]};
          report_.add(std::move(d));
        } else {
          const EdgeRef& a = *i;
          const EdgeRef& b = *(i + 1);
          if (triangles[a.triangle][a.k] == triangles[b.triangle][b.k]) {
            Defect d;
            d.kind = DefectKind::InconsistentOrientation;
            d.stage = "background";
            d.message = "background triangles " + std::to_string(a.triangle) + " and " +
                        std::to_string(b.triangle) + " overlap along edge (" +
                        std::to_string(edge[0]) + ", " + std::to_string(edge[1]) + ")";
            d.facets = {a.triangle, b.triangle};
            report_.add(std::move(d));
          } else {
            connect_edge(a.triangle, a.k, b.triangle, b.k);
          }
        }
        i = j;
      }
    }
  }

  void connect_edge(std::uint32_t ta, int ka, std::uint32_t tb, int kb) {
    if (cut_index_[ta] == kNone && cut_index_[tb] == kNone) {
      out_.adjacencies.push_back({out_.first[ta], out_.first[tb], PatchId()});
      return;
    }
    const auto& va = background_.triangles[ta];
    const CGAL::Comparison_result dir =
        CGAL::compare_xy(points_[va[ka]], points_[va[(ka + 1) % 3]]);
    std::vector<EdgeInterval> a = edge_intervals(ta, ka);
    std::vector<EdgeInterval> b = edge_intervals(tb, kb);
    for (EdgeInterval& i : b) std::swap(i.source, i.target);  // b runs the other way
    const auto by_start = [dir](const EdgeInterval& x, const EdgeInterval& y) {
      return before(x.source, y.source, dir);
    };
    std::sort(a.begin(), a.end(), by_start);
    std::sort(b.begin(), b.end(), by_start);
    // Both lists partition the edge into positive-length parts: merge them.
    std::vector<LocalRegions::Adjacency> found;
    std::size_t i = 0, j = 0;
    while (i < a.size() && j < b.size()) {
      const EdgeInterval& x = a[i];
      const EdgeInterval& y = b[j];
      IMM_ASSERT(x.patch == y.patch, "the input runs along a background edge on one side only");
      if (!x.patch.is_valid()) {
        found.push_back({x.local_region, y.local_region, PatchId()});
      } else {
        IMM_ASSERT(x.inner != y.inner, "both sides of a background edge on one side of the input");
        found.push_back(x.inner ? LocalRegions::Adjacency{x.local_region, y.local_region, x.patch}
                                : LocalRegions::Adjacency{y.local_region, x.local_region, x.patch});
      }
      if (before(x.target, y.target, dir)) {
        ++i;
      } else if (before(y.target, x.target, dir)) {
        ++j;
      } else {
        ++i;
        ++j;
      }
    }
    IMM_ASSERT(i == a.size() && j == b.size(), "edge parts do not cover the edge");
    LocalRegions::normalise(found);
    out_.adjacencies.insert(out_.adjacencies.end(), found.begin(), found.end());
  }

  // ---- regions -------------------------------------------------------------------------

  void resolve_regions() {
    out_.resolve_regions([&](std::uint32_t lr) {
      const auto tri = triangle_points(out_.element[lr]);
      return locate(CGAL::centroid(tri[0], tri[1], tri[2]));
    });
  }


  /// The region of a point off the input: exact ray shooting from q towards a point m on a cut
  /// segment; the first segment crossed in its interior, alone, decides by the side q is on.
  /// Rays through an end of a segment, or along one, are retried with another m.
  RegionId locate(const Point_2& q) const {
    const auto& segments = cut_.segments;
    for (const CutSegment& aim : segments) {
      if (CGAL::orientation(aim.source, aim.target, q) == CGAL::COLLINEAR) continue;
      for (int den = 2; den <= 9; ++den) {
        for (int num = 1; num < den; ++num) {
          if (std::gcd(num, den) != 1) continue;
          const Point_2 m = aim.source + (aim.target - aim.source) * (FT(num) / FT(den));
          std::optional<FT> best;
          std::size_t best_segment = 0;
          bool clean = false;
          bool give_up = false;
          for (std::size_t s = 0; s < segments.size() && !give_up; ++s) {
            const CutSegment& seg = segments[s];
            const CGAL::Orientation o1 = CGAL::orientation(q, m, seg.source);
            const CGAL::Orientation o2 = CGAL::orientation(q, m, seg.target);
            if (o1 == o2 && o1 != CGAL::COLLINEAR) continue;
            if (o1 == CGAL::COLLINEAR && o2 == CGAL::COLLINEAR) {
              give_up = CGAL::do_intersect(Segment_2(q, m), Segment_2(seg.source, seg.target));
              continue;
            }
            const FT aq = CGAL::determinant(seg.target - seg.source, q - seg.source);
            const FT am = CGAL::determinant(seg.target - seg.source, m - seg.source);
            if (CGAL::sign(aq) == CGAL::sign(am) && CGAL::sign(aq) != CGAL::ZERO) continue;
            const FT lambda = aq / (aq - am);  // position of the crossing along q -> m
            const bool interior = o1 != CGAL::COLLINEAR && o2 != CGAL::COLLINEAR;
            if (!best || lambda < *best) {
              best = lambda;
              best_segment = s;
              clean = interior;
            } else if (lambda == *best) {
              clean = false;
            }
          }
          if (give_up || !best || !clean) continue;
          const CutSegment& hit = segments[best_segment];
          const PatchSides& sides = complex_.complex.sides(hit.patch);
          return CGAL::orientation(hit.source, hit.target, q) == CGAL::LEFT_TURN ? sides.negative
                                                                                 : sides.positive;
        }
      }
    }
    IMM_ASSERT(false, "exact ray shooting found no clean ray");
    return RegionId();
  }

  // ---- coverage ------------------------------------------------------------------------

  void not_covered(std::string message, std::vector<double> point) {
    Defect d;
    d.kind = DefectKind::NotCovered;
    d.stage = "mesh";
    d.message = std::move(message);
    d.points.push_back(std::move(point));
    report_.add(std::move(d));
  }

  void check_coverage() {
    // Every cut segment is the union of its pieces.
    for (std::uint32_t s = 0; s < cut_.segments.size(); ++s) {
      const CutSegment& seg = cut_.segments[s];
      auto& pieces = segment_pieces_[s];
      const CGAL::Comparison_result dir = CGAL::compare_xy(seg.source, seg.target);
      std::sort(pieces.begin(), pieces.end(),
                [dir](const auto& a, const auto& b) { return before(a[0], b[0], dir); });
      Mark reached{seg.source, {Key::Source, s}};
      bool covered = true;
      for (const auto& piece : pieces) {
        if (before(reached, piece[0], dir)) {
          covered = false;
          break;
        }
        if (before(reached, piece[1], dir)) reached = piece[1];
      }
      if (!covered || !same_point(reached, {seg.target, {Key::Target, s}})) {
        const Point p = to_double(covered ? reached.point : seg.source);
        std::ostringstream msg;
        msg << "the background mesh does not cover input segment " << seg.input_segment
            << " near (" << p.x << ", " << p.y << ")";
        not_covered(msg.str(), {p.x, p.y});
        return;
      }
    }
    // The background's boundary must not pass through a cell.
    for (const auto& [t, k] : boundary_edges_) {
      for (const EdgeInterval& part : edge_intervals(t, k)) {
        const RegionId inside = out_.region[part.local_region];
        RegionId outside = inside;
        if (part.patch.is_valid()) outside = complex_.complex.sides(part.patch).opposite(inside);
        if (complex_.complex.winding_number(outside) != 0) {
          const Point p = to_double(CGAL::midpoint(part.source.point, part.target.point));
          std::ostringstream msg;
          msg << "the background mesh does not cover the input: its boundary edge (" << p.x
              << ", " << p.y << ") has a region of winding number "
              << complex_.complex.winding_number(outside) << " outside";
          not_covered(msg.str(), {p.x, p.y});
          return;
        }
      }
    }
    for (std::size_t v = 0; v < out_.vertices.size(); ++v) {
      if (out_.vertices[v].local_region == kNone) {
        const Point p = to_double(cut_.input_points[v]);
        not_covered("the background mesh does not cover input vertex " + std::to_string(v),
                    {p.x, p.y});
        return;
      }
    }
  }

  const Complex2& complex_;
  const CutCurve& cut_;
  const Background& background_;
  const bool record_pieces_;
  ValidationReport& report_;

  std::vector<Point_2> points_;
  std::vector<std::array<long, 2>> segment_vertex_;  ///< input vertex at source / target, or -1
  std::vector<std::pair<std::uint32_t, std::uint32_t>> candidates_;  ///< (triangle, segment)
  std::vector<std::vector<std::array<Mark, 2>>> segment_pieces_;
  std::vector<std::uint32_t> cut_index_;
  std::vector<std::array<std::vector<EdgeInterval>, 3>> cut_edges_;
  std::vector<std::pair<std::uint32_t, int>> boundary_edges_;
  LocalRegions out_;
};

}  // namespace

LocalRegions compute_local_regions(const Complex2& complex, const Background& background,
                                   bool record_pieces, ValidationReport& report) {
  IMM_ASSERT(complex.exact != nullptr, "complex without exact geometry");
  return LocalRegionBuilder(complex, background, record_pieces, report).run();
}

}  // namespace imm::dim2::detail
