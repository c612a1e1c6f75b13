// CSG baseline for virtual triangles (Sifakis et al. 2007, as Li & Barbič 2018 compare it): the
// same detail::LocalRegions as dim2/virtual_triangles.cpp, computed with CGAL's exact 2D regularized
// booleans instead of per-triangle clipping and local arrangements.
//
//  - Every region of the complex becomes an exact polygon set (CGAL Polygon_set_2 over Epeck):
//    a bounded region is one face of the arrangement of the cut segments, i.e. one polygon with
//    holes (outer CCB counter-clockwise, inner CCBs clockwise; both may be relatively simple
//    where the region self-touches at a crossing); the unbounded region 0 is the complement of
//    the union of the outer boundaries of all curve components.
//  - For each background triangle t whose box meets the box of a cut segment, t is intersected
//    with every region bordered by such a segment (whose box meets t's): the triangle's polygon
//    set intersected with the region's. Each contained face of the result's arrangement is one
//    connected component of the open set (region ∩ t), i.e. one local region labelled with that
//    region. (Polygons with holes would not do: where a region self-touches at a crossing inside
//    t, its two wedges come out as one relatively simple polygon.) A triangle whose intersections are all empty lies inside a region that
//    borders none of its nearby segments: it is labelled like the uncut triangles.
//  - Fusions, edge parts and input-vertex locations are read off the boundary halfedges of
//    those faces: an edge lies on a triangle edge, on a cut segment (exact collinearity and
//    containment tests against the nearby segments), or on both. The local region is on the
//    left of every boundary edge, so an edge running along its segment is on the inner side.
//  - Edge adjacencies, flood labels of uncut triangles and coverage defects follow the same
//    contract as the clipping path; unseeded flood components are located with the region sets
//    (Polygon_set_2::oriented_side of the triangle's centroid).
//
// The baseline exists for timing comparisons and as an independent check of the clipping path
// (tests/dim2/csg_test.cpp); meshing never calls it. It assumes a generic input (cut segments
// meet only at their ends), as the complex guarantees.
#include <CGAL/Arr_curve_data_traits_2.h>
#include <CGAL/Arr_segment_traits_2.h>
#include <CGAL/Arrangement_2.h>
#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_set_2.h>
#include <CGAL/Polygon_with_holes_2.h>
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <limits>
#include <sstream>
#include <tuple>

#include "core/union_find.h"
#include "core/unglue.h"
#include "dim2/cut_curve.h"
#include "dim2/kernel.h"
#include "dim2/mesh2_detail.h"

namespace imm::dim2::detail {

namespace {

using Polygon = CGAL::Polygon_2<Kernel>;
using PolygonWithHoles = CGAL::Polygon_with_holes_2<Kernel>;
using PolygonSet = CGAL::Polygon_set_2<Kernel>;
/// The input arrangement: every cut segment carries its index.
using SegmentData = CGAL::Arr_curve_data_traits_2<CGAL::Arr_segment_traits_2<Kernel>, std::uint32_t>;
using InputArrangement = CGAL::Arrangement_2<SegmentData>;

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

/// An edge of a local region's boundary (the local region on its left), classified.
struct BoundaryEdge {
  Point_2 source;
  Point_2 target;
  std::uint32_t local_region;
  int triangle_edge = -1;          ///< k when on edge (v[k], v[k+1]) of the triangle
  std::uint32_t segment = kNone;   ///< the cut segment it lies on, if any
  bool inner = false;              ///< runs along the segment: the local region is on its inner side
};

/// Part of a triangle edge on the boundary of one local region, oriented like the edge.
struct EdgeInterval {
  Point_2 source;
  Point_2 target;
  std::uint32_t local_region;
  PatchId patch;
  bool inner = false;
};

class CsgBuilder {
 public:
  CsgBuilder(const Complex2& complex, const Background& background, bool record_pieces,
             ValidationReport& report)
      : complex_(complex),
        cut_(*complex.exact),
        background_(background),
        record_pieces_(record_pieces),
        report_(report) {}

  LocalRegions run() {
    make_points();
    make_region_sets();
    find_candidates();
    out_.vertices.resize(cut_.input_points.size());
    for (std::size_t v = 0; v < cut_.vertex_patch.size(); ++v)
      out_.vertices[v].patch = cut_.vertex_patch[v];
    intervals_.assign(background_.triangles.size(), {});
    is_cut_.assign(background_.triangles.size(), false);
    std::size_t next = 0;
    for (std::uint32_t t = 0; t < background_.triangles.size(); ++t) {
      const std::size_t begin = next;
      while (next < candidates_.size() && candidates_[next].first == t) ++next;
      out_.begin_element();
      process_triangle(t, begin, next);
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
    if (background_.exact_vertices.empty()) {
      for (const Point& p : background_.vertices) points_.emplace_back(p.x, p.y);
    } else {
      for (const auto& q : background_.exact_vertices) points_.emplace_back(FT(q[0]), FT(q[1]));
    }
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

  /// The region on the left of a halfedge of the input arrangement.
  RegionId left_region(InputArrangement::Halfedge_const_handle h) const {
    const CutSegment& seg = cut_.segments[h->curve().data()];
    const PatchSides& sides = complex_.complex.sides(seg.patch);
    return h->source()->point() == seg.source ? sides.negative : sides.positive;
  }

  static Polygon ccb_polygon(InputArrangement::Ccb_halfedge_const_circulator first) {
    Polygon polygon;
    auto h = first;
    do polygon.push_back(h->source()->point());
    while (++h != first);
    return polygon;
  }

  /// One polygon set per region (see the file comment).
  void make_region_sets() {
    InputArrangement arr;
    std::vector<SegmentData::X_monotone_curve_2> curves;
    curves.reserve(cut_.segments.size());
    for (std::uint32_t s = 0; s < cut_.segments.size(); ++s)
      curves.emplace_back(Segment_2(cut_.segments[s].source, cut_.segments[s].target), s);
    CGAL::insert_non_intersecting_curves(arr, curves.begin(), curves.end());

    const std::size_t n = complex_.complex.region_count();
    region_set_.assign(n, PolygonSet());
    region_box_.assign(n, CGAL::Bbox_2());
    std::vector<bool> seen(n, false);
    PolygonSet components;  // union of the curve components' outer boundaries
    for (auto f = arr.faces_begin(); f != arr.faces_end(); ++f) {
      if (f->is_unbounded()) {
        for (auto hole = f->inner_ccbs_begin(); hole != f->inner_ccbs_end(); ++hole) {
          Polygon p = ccb_polygon(*hole);
          p.reverse_orientation();
          components.join(p);
        }
        continue;
      }
      const RegionId r = left_region(f->outer_ccb());
      IMM_ASSERT(r.index() != 0 && !seen[r.index()], "a bounded face is region 0 or a repeated region");
      seen[r.index()] = true;
      const Polygon outer = ccb_polygon(f->outer_ccb());
      std::vector<Polygon> holes;
      for (auto hole = f->inner_ccbs_begin(); hole != f->inner_ccbs_end(); ++hole)
        holes.push_back(ccb_polygon(*hole));
      region_box_[r.index()] = outer.bbox();
      region_set_[r.index()] = PolygonSet(PolygonWithHoles(outer, holes.begin(), holes.end()));
    }
    components.complement();
    region_set_[0] = std::move(components);
    region_box_[0] = CGAL::Bbox_2(-std::numeric_limits<double>::infinity(),
                                  -std::numeric_limits<double>::infinity(),
                                  std::numeric_limits<double>::infinity(),
                                  std::numeric_limits<double>::infinity());
  }

  /// (triangle, segment) pairs whose bounding boxes overlap (Epeck boxes are conservative).
  void find_candidates() {
    using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 2, std::uint32_t>;
    std::vector<Box> triangle_boxes, segment_boxes;
    for (std::uint32_t t = 0; t < background_.triangles.size(); ++t) {
      const auto& v = background_.triangles[t];
      triangle_boxes.emplace_back(points_[v[0]].bbox() + points_[v[1]].bbox() + points_[v[2]].bbox(), t);
    }
    for (std::uint32_t s = 0; s < cut_.segments.size(); ++s)
      segment_boxes.emplace_back(cut_.segments[s].source.bbox() + cut_.segments[s].target.bbox(),
                                 s | 0x80000000u);
    CGAL::box_intersection_d(triangle_boxes.begin(), triangle_boxes.end(), segment_boxes.begin(),
                             segment_boxes.end(), [&](const Box& a, const Box& b) {
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
    const CGAL::Bbox_2 box = tri[0].bbox() + tri[1].bbox() + tri[2].bbox();
    std::vector<std::uint32_t> segments;
    std::vector<RegionId> regions;
    for (std::size_t c = begin; c < end; ++c) {
      const std::uint32_t s = candidates_[c].second;
      segments.push_back(s);
      const PatchSides& sides = complex_.complex.sides(cut_.segments[s].patch);
      for (RegionId r : {sides.negative, sides.positive})
        if (CGAL::do_overlap(region_box_[r.index()], box)) regions.push_back(r);
    }
    std::sort(regions.begin(), regions.end());
    regions.erase(std::unique(regions.begin(), regions.end()), regions.end());

    // The booleans. A polygon with holes of the result may be pinched (two wedges of one region
    // at a crossing inside t form one relatively simple polygon), so the local regions are read
    // from the result's arrangement instead: each contained face is one connected component of
    // the open set (region ∩ t), i.e. one local region, on the left of its boundary halfedges.
    const Polygon triangle(tri.begin(), tri.end());
    const std::uint32_t base = static_cast<std::uint32_t>(out_.region.size());
    std::vector<BoundaryEdge> edges;
    for (RegionId r : regions) {
      PolygonSet piece(triangle);
      piece.intersection(region_set_[r.index()]);
      const auto& arr = piece.arrangement();
      for (auto f = arr.faces_begin(); f != arr.faces_end(); ++f) {
        if (!f->contained()) continue;
        IMM_ASSERT(!f->is_unbounded(), "an unbounded part of a triangle");
        const std::uint32_t lr = out_.add_local_region(t, r);
        const auto add_edges = [&](auto first) {
          auto h = first;
          do classify(tri, segments, h->source()->point(), h->target()->point(), lr, edges);
          while (++h != first);
        };
        add_edges(f->outer_ccb());
        for (auto hole = f->inner_ccbs_begin(); hole != f->inner_ccbs_end(); ++hole) add_edges(*hole);
      }
    }
    const auto count = static_cast<std::uint32_t>(out_.region.size()) - base;
    if (count == 0) {
      // Inside a region bordering none of the nearby segments: labelled by flood fill.
      out_.add_local_region(t);
      return;
    }
    is_cut_[t] = true;

    std::vector<LocalRegions::Fusion> fusions;
    for (const BoundaryEdge& e : edges) {
      if (e.triangle_edge >= 0) {
        IMM_ASSERT(CGAL::compare_xy(e.source, e.target) ==
                       CGAL::compare_xy(tri[e.triangle_edge], tri[(e.triangle_edge + 1) % 3]),
                   "a local region's boundary runs against a triangle edge");
        const PatchId patch = e.segment == kNone ? PatchId() : cut_.segments[e.segment].patch;
        intervals_[t][e.triangle_edge].push_back({e.source, e.target, e.local_region, patch, e.inner});
      }
      if (e.segment == kNone || !e.inner) continue;
      const CutSegment& seg = cut_.segments[e.segment];
      if (record_pieces_) out_.inner_pieces.push_back({e.local_region, seg.patch, seg.input_segment});
      locate_vertices(tri, e);
      if (e.triangle_edge >= 0) continue;
      // The local region across this inner piece: an outer edge on the same segment covering
      // the piece's midpoint.
      const Point_2 m = CGAL::midpoint(e.source, e.target);
      std::uint32_t across = kNone;
      for (const BoundaryEdge& f : edges)
        if (f.segment == e.segment && !f.inner && f.triangle_edge < 0 &&
            CGAL::collinear_are_ordered_along_line(f.source, m, f.target)) {
          across = f.local_region;
          break;
        }
      IMM_ASSERT(across != kNone, "a piece of the input inside a triangle with one side only");
      fusions.push_back({e.local_region, across, seg.patch});
    }
    out_.add_fusions(std::move(fusions));
  }

  /// Classifies boundary edge (p, q) of local region lr; edges along a triangle edge are split at
  /// the ends of nearby segments so that each part is on the input entirely or not at all.
  void classify(const std::array<Point_2, 3>& tri, const std::vector<std::uint32_t>& segments,
                const Point_2& p, const Point_2& q, std::uint32_t lr, std::vector<BoundaryEdge>& edges) const {
    int k = -1;
    for (int i = 0; i < 3 && k < 0; ++i)
      if (CGAL::collinear(tri[i], tri[(i + 1) % 3], p) && CGAL::collinear(tri[i], tri[(i + 1) % 3], q)) k = i;
    std::vector<Point_2> cuts{p, q};
    if (k >= 0) {
      for (std::uint32_t s : segments)
        for (const Point_2* end : {&cut_.segments[s].source, &cut_.segments[s].target})
          if (CGAL::collinear(p, q, *end) && CGAL::collinear_are_strictly_ordered_along_line(p, *end, q))
            cuts.push_back(*end);
      const CGAL::Comparison_result dir = CGAL::compare_xy(p, q);
      std::sort(cuts.begin(), cuts.end(),
                [dir](const Point_2& a, const Point_2& b) { return CGAL::compare_xy(a, b) == dir; });
      cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
    }
    for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
      BoundaryEdge e{cuts[i], cuts[i + 1], lr, k, kNone, false};
      const Point_2 m = CGAL::midpoint(e.source, e.target);
      for (std::uint32_t s : segments) {
        const CutSegment& seg = cut_.segments[s];
        if (CGAL::collinear(seg.source, seg.target, e.source) &&
            CGAL::collinear(seg.source, seg.target, e.target) &&
            CGAL::collinear_are_ordered_along_line(seg.source, m, seg.target)) {
          e.segment = s;
          e.inner = CGAL::compare_xy(e.source, e.target) == CGAL::compare_xy(seg.source, seg.target);
          break;
        }
      }
      IMM_ASSERT(e.triangle_edge >= 0 || e.segment != kNone,
                 "a local region's boundary edge lies neither on the triangle nor on the input");
      edges.push_back(std::move(e));
    }
  }

  /// An input vertex at an end of an inner boundary edge is embedded in its local region; the
  /// first triangle found wins (as in the clipping path).
  void locate_vertices(const std::array<Point_2, 3>& tri, const BoundaryEdge& e) {
    for (long v : segment_vertex_[e.segment]) {
      if (v < 0) continue;
      auto& location = out_.vertices[static_cast<std::size_t>(v)];
      if (location.local_region != kNone) continue;
      const Point_2& p = cut_.input_points[static_cast<std::size_t>(v)];
      if (e.source != p && e.target != p) continue;
      const FT area = CGAL::area(tri[0], tri[1], tri[2]);
      const FT w0 = CGAL::area(p, tri[1], tri[2]) / area;
      const FT w1 = CGAL::area(tri[0], p, tri[2]) / area;
      const FT w2 = CGAL::area(tri[0], tri[1], p) / area;
      location.local_region = e.local_region;
      location.weights = {CGAL::to_double(CGAL::exact(w0)), CGAL::to_double(CGAL::exact(w1)),
                          CGAL::to_double(CGAL::exact(w2))};
    }
  }

  // ---- edges ---------------------------------------------------------------------------

  std::vector<EdgeInterval> edge_intervals(std::uint32_t t, int k) const {
    if (is_cut_[t]) return intervals_[t][k];
    const auto& v = background_.triangles[t];
    return {{points_[v[k]], points_[v[(k + 1) % 3]], out_.first[t], PatchId(), false}};
  }

  void connect_edges() {
    struct EdgeRef {
      int lo, hi;
      std::uint32_t triangle;
      int k;
    };
    std::vector<EdgeRef> refs;
    refs.reserve(3 * background_.triangles.size());
    for (std::uint32_t t = 0; t < background_.triangles.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const int a = background_.triangles[t][k], b = background_.triangles[t][(k + 1) % 3];
        refs.push_back({std::min(a, b), std::max(a, b), t, k});
      }
    std::stable_sort(refs.begin(), refs.end(), [](const EdgeRef& x, const EdgeRef& y) {
      return std::tie(x.lo, x.hi) < std::tie(y.lo, y.hi);
    });
    for (std::size_t i = 0; i < refs.size();) {
      std::size_t j = i + 1;
      while (j < refs.size() && refs[j].lo == refs[i].lo && refs[j].hi == refs[i].hi) ++j;
      const std::array<int, 2> edge = {refs[i].lo, refs[i].hi};
      if (j - i == 1) {
        boundary_edges_.emplace_back(refs[i].triangle, refs[i].k);
      } else if (j - i > 2) {
        Defect d;
        d.kind = DefectKind::NonManifoldEdge;
        d.stage = "background";
        d.message = "background edge (" + std::to_string(edge[0]) + ", " + std::to_string(edge[1]) +
                    ") is shared by " + std::to_string(j - i) + " triangles";
        d.vertices = {edge[0], edge[1]};
        report_.add(std::move(d));
      } else {
        const EdgeRef& a = refs[i];
        const EdgeRef& b = refs[i + 1];
        if (background_.triangles[a.triangle][a.k] == background_.triangles[b.triangle][b.k]) {
          Defect d;
          d.kind = DefectKind::InconsistentOrientation;
          d.stage = "background";
          d.message = "background triangles " + std::to_string(a.triangle) + " and " +
                      std::to_string(b.triangle) + " overlap along edge (" + std::to_string(edge[0]) +
                      ", " + std::to_string(edge[1]) + ")";
          d.facets = {a.triangle, b.triangle};
          report_.add(std::move(d));
        } else {
          connect_edge(a.triangle, a.k, b.triangle, b.k);
        }
      }
      i = j;
    }
  }

  /// Every pair of parts of the two sides that overlap along a positive length.
  void connect_edge(std::uint32_t ta, int ka, std::uint32_t tb, int kb) {
    if (!is_cut_[ta] && !is_cut_[tb]) {
      out_.adjacencies.push_back({out_.first[ta], out_.first[tb], PatchId()});
      return;
    }
    const auto& va = background_.triangles[ta];
    const CGAL::Comparison_result dir = CGAL::compare_xy(points_[va[ka]], points_[va[(ka + 1) % 3]]);
    const auto before = [dir](const Point_2& x, const Point_2& y) { return CGAL::compare_xy(x, y) == dir; };
    std::vector<EdgeInterval> a = edge_intervals(ta, ka);
    std::vector<EdgeInterval> b = edge_intervals(tb, kb);
    for (EdgeInterval& y : b) std::swap(y.source, y.target);
    std::vector<LocalRegions::Adjacency> found;
    for (const EdgeInterval& x : a)
      for (const EdgeInterval& y : b) {
        const Point_2& start = before(x.source, y.source) ? y.source : x.source;
        const Point_2& end = before(x.target, y.target) ? x.target : y.target;
        if (!before(start, end)) continue;
        IMM_ASSERT(x.patch == y.patch, "the input runs along a background edge on one side only");
        if (!x.patch.is_valid()) {
          found.push_back({x.local_region, y.local_region, PatchId()});
        } else {
          IMM_ASSERT(x.inner != y.inner, "both sides of a background edge on one side of the input");
          found.push_back(x.inner ? LocalRegions::Adjacency{x.local_region, y.local_region, x.patch}
                                  : LocalRegions::Adjacency{y.local_region, x.local_region, x.patch});
        }
      }
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


  /// The region whose polygon set holds q in its interior. @pre q is off the input.
  RegionId locate(const Point_2& q) const {
    for (std::size_t r = 0; r < region_set_.size(); ++r)
      if (region_set_[r].oriented_side(q) == CGAL::ON_POSITIVE_SIDE) return RegionId(r);
    IMM_ASSERT(false, "a point off the input lies in no region");
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

  /// The background's boundary must not pass through a cell, and must enclose every input vertex.
  /// (A cut segment leaving the background crosses its boundary through a cell, so this also
  /// covers the segments.)
  void check_coverage() {
    for (const auto& [t, k] : boundary_edges_) {
      for (const EdgeInterval& part : edge_intervals(t, k)) {
        const RegionId inside = out_.region[part.local_region];
        RegionId outside = inside;
        if (part.patch.is_valid()) outside = complex_.complex.sides(part.patch).opposite(inside);
        if (complex_.complex.winding_number(outside) != 0) {
          const Point p = to_double(CGAL::midpoint(part.source, part.target));
          std::ostringstream msg;
          msg << "the background mesh does not cover the input: its boundary edge (" << p.x << ", "
              << p.y << ") has a region of winding number "
              << complex_.complex.winding_number(outside) << " outside";
          not_covered(msg.str(), {p.x, p.y});
          return;
        }
      }
    }
    for (std::size_t v = 0; v < out_.vertices.size(); ++v) {
      if (out_.vertices[v].local_region == kNone) {
        const Point p = to_double(cut_.input_points[v]);
        not_covered("the background mesh does not cover input vertex " + std::to_string(v), {p.x, p.y});
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
  std::vector<std::array<long, 2>> segment_vertex_;
  std::vector<PolygonSet> region_set_;
  std::vector<CGAL::Bbox_2> region_box_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> candidates_;
  std::vector<std::array<std::vector<EdgeInterval>, 3>> intervals_;
  std::vector<bool> is_cut_;  ///< local regions computed by the booleans
  std::vector<std::pair<std::uint32_t, int>> boundary_edges_;
  LocalRegions out_;
};

}  // namespace

LocalRegions compute_local_regions_csg(const Complex2& complex, const Background& background,
                                       bool record_pieces, ValidationReport& report) {
  IMM_ASSERT(complex.exact != nullptr, "complex without exact geometry");
  return CsgBuilder(complex, background, record_pieces, report).run();
}

}  // namespace imm::dim2::detail
