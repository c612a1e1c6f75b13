// The exact 2D cell complex (paper §4, d = 2) from a CGAL arrangement of all input segments.
//
// This is the only translation unit that includes the arrangement headers (it takes ~1 min to
// compile). Every decision is an exact predicate on Epeck points: vertex classification, winding
// numbers (edge direction vs segment direction), junction order (the arrangement's own cyclic
// order around a vertex). Doubles appear only in messages and display geometry.
#include <CGAL/Arr_extended_dcel.h>
#include <CGAL/Arr_segment_traits_2.h>
#include <CGAL/Arrangement_with_history_2.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <unordered_map>

#include "core/perturbation.h"
#include "core/exact_sum.h"
#include "dim2/complex2.h"
#include "dim2/cut_curve.h"
#include "dim2/kernel.h"

namespace imm::dim2 {
namespace {

/// Per-vertex data: whether the vertex is a crossing (an arc), and its arc once numbered.
struct VertexData {
  bool crossing = false;
  int arc = -1;
};
/// Per-halfedge data: the input segment it lies on (the first one for an overlap) and its patch.
struct HalfedgeData {
  std::size_t segment = 0;
  int patch = -1;
};

using Traits = CGAL::Arr_segment_traits_2<Kernel>;
// The extended DCEL keeps our bookkeeping in the arrangement itself (no pointer-keyed maps).
using Dcel = CGAL::Arr_extended_dcel<Traits, VertexData, HalfedgeData, int /* region, -1 = unset */>;
using Arrangement = CGAL::Arrangement_with_history_2<Traits, Dcel>;
using InputSegment = Traits::Curve_2;
using VertexHandle = Arrangement::Vertex_handle;
using HalfedgeHandle = Arrangement::Halfedge_handle;
using FaceHandle = Arrangement::Face_handle;

constexpr const char* kStage = "arrangement";

/// Global vertex / segment numbering of a curve set (segment s joins vertex s to next(s)).
struct InputLayout {
  std::vector<std::size_t> offset;  // per curve, plus the total at the end
  std::vector<std::size_t> curve;   // per vertex
  explicit InputLayout(const CurveSet& set) {
    offset.push_back(0);
    for (std::size_t c = 0; c < set.curves.size(); ++c) {
      for (std::size_t i = 0; i < set.curves[c].vertices.size(); ++i) curve.push_back(c);
      offset.push_back(offset.back() + set.curves[c].vertices.size());
    }
  }
  [[nodiscard]] std::size_t size() const { return offset.back(); }
  [[nodiscard]] std::size_t next(std::size_t v) const {
    const std::size_t c = curve[v];
    return v + 1 == offset[c + 1] ? offset[c] : v + 1;
  }
  [[nodiscard]] std::size_t prev(std::size_t v) const {
    const std::size_t c = curve[v];
    return v == offset[c] ? offset[c + 1] - 1 : v - 1;
  }
};

std::string point_text(const Point_2& p) { return format_point(to_double(p)); }
std::vector<double> point_coords(const Point_2& p) {
  const Point d = to_double(p);
  return {d.x, d.y};
}

/// "curve 1" or "curves 0 and 2" for a set of segments/vertices.
std::string curves_text(const InputLayout& layout, const std::vector<std::size_t>& items) {
  std::set<std::size_t> curves;
  for (std::size_t i : items) curves.insert(layout.curve[i]);
  std::ostringstream os;
  os << (curves.size() == 1 ? "curve " : "curves ");
  std::size_t k = 0;
  for (std::size_t c : curves) {
    if (k > 0) os << (k + 1 == curves.size() ? " and " : ", ");
    os << c;
    ++k;
  }
  return os.str();
}

/// "7 and 12" / "1, 5 and 9".
std::string list_text(const std::vector<std::size_t>& items) {
  std::ostringstream os;
  for (std::size_t k = 0; k < items.size(); ++k) {
    if (k > 0) os << (k + 1 == items.size() ? " and " : ", ");
    os << items[k];
  }
  return os.str();
}

std::vector<long> as_long(const std::vector<std::size_t>& v) { return {v.begin(), v.end()}; }

/// A point strictly inside a bounded face. The lexicographically smallest vertex q of the outer
/// boundary is strictly convex (an arrangement has no spikes); with its boundary neighbours p, r,
/// either no boundary vertex of the face lies in the closed triangle pqr (its centroid is inside)
/// or the one farthest from line pr, z, sees q through the face (the midpoint of qz is inside).
Point_2 interior_point(FaceHandle f) {
  auto first = f->outer_ccb();
  auto h = first;
  HalfedgeHandle lowest = h;
  do {
    if (CGAL::compare_xy(h->target()->point(), lowest->target()->point()) == CGAL::SMALLER) lowest = h;
  } while (++h != first);
  const Point_2& p = lowest->source()->point();
  const Point_2& q = lowest->target()->point();
  const Point_2& r = lowest->next()->target()->point();
  IMM_ASSERT(CGAL::orientation(p, q, r) == CGAL::LEFT_TURN, "lowest boundary vertex is not convex");
  std::optional<Point_2> best;
  auto consider = [&](HalfedgeHandle e) {
    const Point_2& z = e->target()->point();
    if (z == p || z == q || z == r) return;
    if (CGAL::orientation(p, q, z) == CGAL::RIGHT_TURN || CGAL::orientation(q, r, z) == CGAL::RIGHT_TURN ||
        CGAL::orientation(r, p, z) == CGAL::RIGHT_TURN) {
      return;
    }
    if (!best || CGAL::compare_signed_distance_to_line(r, p, z, *best) == CGAL::LARGER) best = z;
  };
  h = first;
  do consider(h);
  while (++h != first);
  for (auto hole = f->inner_ccbs_begin(); hole != f->inner_ccbs_end(); ++hole) {
    auto c = *hole;
    do consider(c);
    while (++c != *hole);
  }
  if (best) return CGAL::midpoint(q, *best);
  return CGAL::centroid(p, q, r);
}

struct ExactXY {
  Rational x, y;
};

}  // namespace

namespace {
/// One exact build of the given curves (no perturbation): defects for every contact.
BuildResult build_once(const CurveSet& input);

/// Where a direction from apex q lies against a vertex occurrence's corner (rays q->a to its next
/// vertex, q->b to its previous): +1 strictly inside the counter-clockwise arc from a to b (the
/// left of the occurrence's path), -1 strictly inside the other arc (its right), 0 on a ray or
/// undecided (a spike).
int corner_side(const Point_2& q, const Point_2& a, const Point_2& b, const Point_2& x) {
  const auto on_ray = [&](const Point_2& r) {
    return CGAL::orientation(q, r, x) == CGAL::COLLINEAR && CGAL::angle(r, q, x) == CGAL::ACUTE;
  };
  if (on_ray(a) || on_ray(b)) return 0;
  const CGAL::Orientation ab = CGAL::orientation(q, a, b);
  bool left = false;
  if (ab == CGAL::LEFT_TURN) {
    left = CGAL::orientation(q, a, x) == CGAL::LEFT_TURN && CGAL::orientation(q, x, b) == CGAL::LEFT_TURN;
  } else if (ab == CGAL::RIGHT_TURN) {
    left = !(CGAL::orientation(q, b, x) != CGAL::RIGHT_TURN && CGAL::orientation(q, x, a) != CGAL::RIGHT_TURN);
  } else if (CGAL::angle(a, q, b) == CGAL::ACUTE) {
    return 0;  // a spike: the curve runs back along itself
  } else {
    left = CGAL::orientation(q, a, x) == CGAL::LEFT_TURN;
  }
  return left ? 1 : -1;
}

/// Which way each vertex occurrence that shares its exact position with another occurrence moves:
/// +1 along the bisector of its left (the side its path turns around), -1 against it, NaN not at
/// all (only its pseudo-random part), 0 not decided here (the input's inward, as elsewhere).
///
/// At such a point every occurrence is a corner (two rays from the point); two corners whose rays
/// do not interleave need not cross, and they do not after the move when each is displaced into
/// the other's side of it: when every other corner lies in its right (corners touching from
/// outside, a convex corner in a notch) it moves into its left, when every other lies in its left
/// (a pinch of one curve: two reflex turns, each inside the other's left) it moves into its right.
/// One direction for both would move each corner across the other's rays (the pinch's two copies
/// swap sides and the curve crosses itself twice, leaving a region of winding -1). With corners on
/// both sides it stays and the others move. Interleaved corners cross however they move.
std::vector<double> coincident_sides(const CurveSet& input) {
  struct Occurrence {
    Point at, prev, next;
  };
  std::vector<Occurrence> occ;
  for (const Curve& c : input.curves) {
    const std::size_t m = c.vertices.size();
    for (std::size_t i = 0; i < m; ++i) occ.push_back({c.vertices[i], c.vertices[(i + m - 1) % m], c.vertices[(i + 1) % m]});
  }
  std::vector<std::size_t> order(occ.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return occ[a].at < occ[b].at || (occ[a].at == occ[b].at && a < b);
  });
  std::vector<double> side(occ.size(), 0.0);
  for (std::size_t lo = 0; lo < order.size();) {
    std::size_t hi = lo + 1;
    while (hi < order.size() && occ[order[hi]].at == occ[order[lo]].at) ++hi;
    if (hi - lo >= 2) {
      const Point_2 q = to_exact(occ[order[lo]].at);
      for (std::size_t k = lo; k < hi; ++k) {
        const Occurrence& o = occ[order[k]];
        const Point_2 a = to_exact(o.next), b = to_exact(o.prev);
        bool others_left = false, others_right = false;
        for (std::size_t j = lo; j < hi; ++j) {
          if (j == k) continue;
          const int s1 = corner_side(q, a, b, to_exact(occ[order[j]].prev));
          const int s2 = corner_side(q, a, b, to_exact(occ[order[j]].next));
          if (s1 >= 0 && s2 >= 0 && s1 + s2 > 0) others_left = true;
          if (s1 <= 0 && s2 <= 0 && s1 + s2 < 0) others_right = true;
        }
        if (others_left && others_right) side[order[k]] = std::nan("");
        else if (others_left) side[order[k]] = -1.0;
        else if (others_right) side[order[k]] = 1.0;
      }
    }
    lo = hi;
  }
  return side;
}
}  // namespace

BuildResult build_complex(const CurveSet& input, const BuildOptions2& options) {
  const auto start_time = std::chrono::steady_clock::now();
  BuildResult result = build_once(input);
  const bool contacts_only =
      !result.report.ok() && std::all_of(result.report.defects.begin(), result.report.defects.end(),
                                         [](const Defect& d) { return d.stage == kStage; });
  if (options.strict || !contacts_only) return result;
  // Exact contacts: the first perturbation under which every decision is generic (DESIGN §5).
  Contacts2 contacts;
  contacts.found = std::move(result.report);
  for (const Defect& d : contacts.found.defects) {
    auto it = std::find_if(contacts.counts.begin(), contacts.counts.end(),
                           [&](const auto& c) { return c.first == d.kind; });
    if (it == contacts.counts.end()) contacts.counts.emplace_back(d.kind, 1);
    else ++it->second;
  }
  // Inward: against the outward normals of a vertex's two segments (the right side of a
  // counter-clockwise curve; reversed when the whole input is clockwise). Keys mix a vertex's
  // coordinates with its two neighbours' (independent of the vertex order, but for identical copies).
  std::vector<std::array<double, 2>> start_points, inward, bisector;
  std::vector<std::uint64_t> keys;
  double twice_area = 0.0;
  for (const Curve& c : input.curves) {
    const std::size_t m = c.vertices.size();
    for (std::size_t i = 0; i < m; ++i) {
      const Point &p = c.vertices[(i + m - 1) % m], &q = c.vertices[i], &r = c.vertices[(i + 1) % m];
      start_points.push_back({q.x, q.y});
      twice_area += q.x * r.y - r.x * q.y;
      // The left normals of p->q and q->r, summed: toward the inside of a counter-clockwise curve.
      inward.push_back({-((q.y - p.y) + (r.y - q.y)), (q.x - p.x) + (r.x - q.x)});
      // The same with unit segments: the bisector of the corner's left (the sum above leans
      // toward the longer segment's normal, outside a sharp corner); used at coincident corners.
      const double lin = std::hypot(q.x - p.x, q.y - p.y), lout = std::hypot(r.x - q.x, r.y - q.y);
      bisector.push_back({-((q.y - p.y) / lin + (r.y - q.y) / lout), (q.x - p.x) / lin + (r.x - q.x) / lout});
      const std::uint64_t own = point_key(std::array<double, 2>{q.x, q.y});
      keys.push_back(mix64(own ^ mix64(mix64(point_key(std::array<double, 2>{p.x, p.y})) +
                                       mix64(point_key(std::array<double, 2>{r.x, r.y})))));
    }
  }
  distinguish_equal_keys(keys);  // identical copies of a curve get different offsets (they cross)
  const std::vector<double> side = coincident_sides(input);
  for (std::size_t v = 0; v < inward.size(); ++v) {
    auto& d = inward[v];
    if (side[v] != 0.0) d = bisector[v];
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1]);
    const double sign = side[v] != 0.0 ? side[v] : twice_area < 0.0 ? -1.0 : 1.0;
    for (double& x : d) x = len > 0.0 && std::isfinite(len) && !std::isnan(sign) ? sign * x / len : 0.0;
  }
  ValidationReport last;
  for (const PerturbationAttempt& attempt : perturbation_schedule()) {
    ++contacts.attempts;
    std::vector<std::array<double, 2>> points = start_points;
    PerturbationSummary summary = perturb_points(points, inward, keys, attempt);
    // Coincident corners: their directed parts must decide which side of each other they end on.
    // A corner with a side moves along its own bisector only, by a pseudo-random length in
    // [31/64, 33/64] of the amplitude, so that it stays in its own wedge: a random part across
    // the bisector, even 1/16 of the usual, pushed a corner nested in another one of under ~2
    // degrees across it (two new crossings, exit 0). A corner with others on both sides (no side)
    // keeps a small random part of both axes: it has no direction of its own.
    bool rescaled = false;
    for (std::size_t v = 0; v < points.size(); ++v) {
      if (side[v] == 0.0) continue;
      rescaled = true;
      const double along = 0.5 + perturbation_unit(attempt.seed, keys[v], 0) / 64;
      for (unsigned d = 0; d < 2; ++d) {
        const double u = perturbation_unit(attempt.seed, keys[v], d);
        points[v][d] = start_points[v][d] + summary.amplitude * (std::isnan(side[v]) ? u / 64 : along * inward[v][d]);
      }
    }
    if (rescaled) {
      summary.max_displacement = 0.0;
      summary.moved_vertices = 0;
      for (std::size_t v = 0; v < points.size(); ++v) {
        const double dx = points[v][0] - start_points[v][0], dy = points[v][1] - start_points[v][1];
        if (dx != 0.0 || dy != 0.0) ++summary.moved_vertices;
        summary.max_displacement = std::max(summary.max_displacement, std::hypot(dx, dy));
      }
    }
    CurveSet moved = input;
    std::size_t i = 0;
    for (Curve& c : moved.curves)
      for (Point& p : c.vertices) {
        p = {points[i][0], points[i][1]};
        ++i;
      }
    BuildResult again = build_once(moved);
    if (!again.report.ok()) {
      last = std::move(again.report);
      continue;
    }
    contacts.perturbation = summary;
    contacts.resolved = std::move(moved);
    again.contacts = std::move(contacts);
    again.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
    return again;
  }
  // The input's own contacts, in the user's coordinates (the perturbed ones would quote
  // coordinates that are in no file); the last attempt's defects are counted only.
  result.report = contacts.found;
  result.report.add(Defect{DefectKind::Touching, kStage,
                           "the input's exact contacts (above) were not resolved by " +
                               std::to_string(contacts.attempts) + " perturbations (the last one still had " +
                               std::to_string(last.total()) + " defects)",
                           {}, {}, {}});
  result.contacts = std::move(contacts);
  return result;
}

namespace {
BuildResult build_once(const CurveSet& input) {
  const auto start_time = std::chrono::steady_clock::now();
  BuildResult result;
  auto finish = [&]() -> BuildResult {
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
    return std::move(result);
  };
  // The arrangement's preconditions (no degenerate segment, finite coordinates) are checked first.
  result.report = validate_curves(input);
  if (!result.report.ok()) return finish();

  const InputLayout layout(input);
  const std::size_t n = layout.size();
  std::vector<Point_2> points;
  points.reserve(n);
  for (const Curve& c : input.curves) {
    for (const Point& p : c.vertices) points.push_back(to_exact(p));
  }
  // Segment direction, exactly (left-to-right in xy-lexicographic order).
  std::vector<bool> segment_right(n);
  std::vector<InputSegment> segments;
  segments.reserve(n);
  for (std::size_t s = 0; s < n; ++s) {
    const Point_2& a = points[s];
    const Point_2& b = points[layout.next(s)];
    segment_right[s] = CGAL::compare_xy(a, b) == CGAL::SMALLER;
    segments.emplace_back(a, b);
  }

  Arrangement arr;
  CGAL::insert(arr, segments.begin(), segments.end());  // aggregate (sweep-line) insertion

  // Curves of the history are kept in insertion order: curve k is input segment k.
  std::unordered_map<const void*, std::size_t> segment_of_curve;
  segment_of_curve.reserve(n);
  {
    std::size_t s = 0;
    for (auto c = arr.curves_begin(); c != arr.curves_end(); ++c, ++s) {
      segment_of_curve.emplace(static_cast<const void*>(&*c), s);
    }
    IMM_ASSERT(s == n, "the arrangement lost input segments");
  }
  // ---- genericity: every defect, found from exact arrangement facts -----------------------
  // Collinear overlaps: edges with two or more originating segments, merged per segment pair.
  std::map<std::pair<std::size_t, std::size_t>, std::pair<Point_2, Point_2>> overlaps;
  std::unordered_map<const void*, std::vector<std::size_t>> multi_origin;  // overlap edges only
  std::vector<std::size_t> o;
  for (auto e = arr.edges_begin(); e != arr.edges_end(); ++e) {
    const HalfedgeHandle h = e;
    o.clear();
    for (auto it = arr.originating_curves_begin(h); it != arr.originating_curves_end(h); ++it) {
      Arrangement::Curve_const_handle ch = it;
      o.push_back(segment_of_curve.at(static_cast<const void*>(&*ch)));
    }
    IMM_ASSERT(!o.empty(), "arrangement edge without an originating segment");
    std::sort(o.begin(), o.end());
    h->data().segment = o.front();
    h->twin()->data().segment = o.front();
    if (o.size() < 2) continue;
    multi_origin.emplace(&*h, o);
    multi_origin.emplace(&*h->twin(), o);
    Point_2 lo = h->source()->point(), hi = h->target()->point();
    if (CGAL::compare_xy(lo, hi) == CGAL::LARGER) std::swap(lo, hi);
    for (std::size_t i = 0; i < o.size(); ++i) {
      for (std::size_t j = i + 1; j < o.size(); ++j) {
        auto [it, inserted] = overlaps.try_emplace({o[i], o[j]}, lo, hi);
        if (inserted) continue;
        if (CGAL::compare_xy(lo, it->second.first) == CGAL::SMALLER) it->second.first = lo;
        if (CGAL::compare_xy(hi, it->second.second) == CGAL::LARGER) it->second.second = hi;
      }
    }
  }
  for (const auto& [pair, extent] : overlaps) {
    const std::vector<std::size_t> segs{pair.first, pair.second};
    result.report.add(Defect{DefectKind::CollinearOverlap, kStage,
                             curves_text(layout, segs) + ": segments " + list_text(segs) +
                                 " overlap collinearly from " + point_text(extent.first) + " to " +
                                 point_text(extent.second),
                             as_long(segs),
                             {static_cast<long>(pair.first), static_cast<long>(layout.next(pair.first)),
                              static_cast<long>(pair.second), static_cast<long>(layout.next(pair.second))},
                             {point_coords(extent.first), point_coords(extent.second)}});
  }

  // Input vertices by exact position (doubles compare exactly).
  std::vector<std::size_t> by_position(n);
  for (std::size_t i = 0; i < n; ++i) by_position[i] = i;
  std::sort(by_position.begin(), by_position.end(), [&](std::size_t a, std::size_t b) {
    const Point& pa = input.curves[layout.curve[a]].vertices[a - layout.offset[layout.curve[a]]];
    const Point& pb = input.curves[layout.curve[b]].vertices[b - layout.offset[layout.curve[b]]];
    return pa < pb || (pa == pb && a < b);
  });

  // Vertex classification. A valid vertex is either an input vertex of degree 2 carrying exactly
  // its own two segments, or a proper crossing of exactly two segments (degree 4).
  std::vector<std::size_t> here;     // input vertices at a point
  std::vector<std::size_t> through;  // segments through a point
  for (auto v = arr.vertices_begin(); v != arr.vertices_end(); ++v) {
    const Point_2& p = v->point();
    auto lo = std::lower_bound(by_position.begin(), by_position.end(), p, [&](std::size_t i, const Point_2& x) {
      return CGAL::compare_xy(points[i], x) == CGAL::SMALLER;
    });
    here.clear();
    for (auto it = lo; it != by_position.end() && points[*it] == p; ++it) here.push_back(*it);
    through.clear();
    auto circ = v->incident_halfedges();
    auto c = circ;
    do {
      if (auto m = multi_origin.find(&*c); m != multi_origin.end()) {
        through.insert(through.end(), m->second.begin(), m->second.end());
      } else {
        through.push_back(c->data().segment);
      }
    } while (++c != circ);
    std::sort(through.begin(), through.end());
    through.erase(std::unique(through.begin(), through.end()), through.end());
    const std::size_t degree = v->degree();

    v->data().crossing = here.empty();
    if (here.size() == 1 && degree == 2 && through.size() == 2) {
      const std::size_t i = here.front();
      const std::size_t a = std::min(i, layout.prev(i)), b = std::max(i, layout.prev(i));
      if (through[0] == a && through[1] == b) continue;
    }
    if (here.empty() && through.size() == 2 && degree == 4) continue;

    // A defect. It is already explained when every pair of segments meeting here is either the
    // two segments of one input vertex or a reported collinear overlap.
    std::set<std::pair<std::size_t, std::size_t>> own;
    for (std::size_t i : here) own.insert({std::min(i, layout.prev(i)), std::max(i, layout.prev(i))});
    bool explained = true;
    for (std::size_t x = 0; x < through.size() && explained; ++x) {
      for (std::size_t y = x + 1; y < through.size() && explained; ++y) {
        const std::pair<std::size_t, std::size_t> pr{through[x], through[y]};
        explained = own.count(pr) > 0 || overlaps.count(pr) > 0;
      }
    }
    if (explained) continue;

    Defect d{DefectKind::Touching, kStage, "", as_long(through), as_long(here), {point_coords(p)}};
    std::vector<std::size_t> others;  // segments through p that do not end at p
    for (std::size_t s : through) {
      const bool ends_here = std::any_of(here.begin(), here.end(), [&](std::size_t i) {
        return s == i || s == layout.prev(i);
      });
      if (!ends_here) others.push_back(s);
    }
    std::vector<std::size_t> all_items = here;
    all_items.insert(all_items.end(), through.begin(), through.end());
    if (here.size() >= 2) {
      d.message = curves_text(layout, here) + ": vertices " + list_text(here) + " coincide at " + point_text(p);
      if (!others.empty()) {
        d.message += " and segment" + std::string(others.size() > 1 ? "s " : " ") + list_text(others) +
                     (others.size() > 1 ? " pass" : " passes") + " through it";
      }
      std::set<std::size_t> curves;
      for (std::size_t i : all_items) curves.insert(layout.curve[i]);
      d.message += curves.size() > 1 ? " (the curves touch there)" : " (the curve touches itself there)";
    } else if (here.size() == 1) {
      d.message = curves_text(layout, all_items) + ": vertex " + std::to_string(here.front()) + " at " +
                  point_text(p) + " lies on segment" + (others.size() > 1 ? "s " : " ") + list_text(others) +
                  " (touching; crossings must be interior to two segments)";
    } else if (through.size() >= 3) {
      d.kind = DefectKind::TriplePoint;
      d.message = curves_text(layout, through) + ": segments " + list_text(through) + " all pass through " +
                  point_text(p) + " (" + std::to_string(through.size()) + " sheets meet at one point)";
    } else {
      d.message = curves_text(layout, through) + ": segments " + list_text(through) +
                  " meet at " + point_text(p) + " without crossing properly";
    }
    result.report.add(std::move(d));
  }
  if (!result.report.ok()) return finish();

  // ---- winding numbers: breadth-first from the unbounded face ---------------------------
  // The face left of a halfedge (h->face()) is the left of the segment when both run the same way;
  // the left of a curve has winding number one more than its right.
  auto same_direction = [&](HalfedgeHandle h) {
    return (h->direction() == CGAL::ARR_LEFT_TO_RIGHT) == static_cast<bool>(segment_right[h->data().segment]);
  };
  auto region_of = [](FaceHandle f) { return RegionId(f->data()); };
  std::vector<FaceHandle> faces;
  std::vector<int> winding;
  for (auto f = arr.faces_begin(); f != arr.faces_end(); ++f) f->set_data(-1);
  auto add_face = [&](FaceHandle f, int w) {
    f->set_data(static_cast<int>(faces.size()));
    faces.push_back(f);
    winding.push_back(w);
  };
  add_face(arr.unbounded_face(), 0);
  auto for_each_ccb_halfedge = [](FaceHandle f, auto&& fn) {
    if (!f->is_unbounded()) {
      auto first = f->outer_ccb();
      auto h = first;
      do fn(HalfedgeHandle(h));
      while (++h != first);
    }
    for (auto hole = f->inner_ccbs_begin(); hole != f->inner_ccbs_end(); ++hole) {
      auto h = *hole;
      do fn(HalfedgeHandle(h));
      while (++h != *hole);
    }
  };
  for (std::size_t next = 0; next < faces.size(); ++next) {
    const FaceHandle f = faces[next];
    const int wf = winding[next];
    for_each_ccb_halfedge(f, [&](HalfedgeHandle h) {
      const FaceHandle g = h->twin()->face();
      const int wg = same_direction(h) ? wf - 1 : wf + 1;
      if (g->data() < 0) {
        add_face(g, wg);
      } else {
        IMM_ASSERT(winding[static_cast<std::size_t>(g->data())] == wg, "inconsistent winding numbers across an edge");
      }
    });
  }
  IMM_ASSERT(faces.size() == arr.number_of_faces(), "winding search did not reach every face");

  const int min_winding = *std::min_element(winding.begin(), winding.end());
  const int max_winding = *std::max_element(winding.begin(), winding.end());
  bool reversed = false;
  if (min_winding < 0) {
    if (max_winding > 0) {
      std::size_t worst = 0;
      std::size_t negative_count = 0;
      for (std::size_t r = 0; r < winding.size(); ++r) {
        if (winding[r] < 0) ++negative_count;
        if (winding[r] < winding[worst]) worst = r;
      }
      Inversion inv;
      inv.region = RegionId(worst);
      inv.winding_number = winding[worst];
      inv.sample = to_double(interior_point(faces[worst]));
      std::ostringstream os;
      os << "region " << worst << " around " << format_point(inv.sample) << " has winding number "
         << inv.winding_number << " while other regions have winding numbers up to " << max_winding
         << ": the curves invert space there (paper §3, Fig. 8), so no immersion exists ("
         << negative_count << " region" << (negative_count > 1 ? "s" : "") << " with a negative winding number)";
      inv.message = os.str();
      result.inversion = std::move(inv);
      return finish();
    }
    // Everything is drawn clockwise: take the opposite orientation for every curve.
    reversed = true;
    for (int& w : winding) w = -w;
  }

  // ---- exact measures and display boundaries of the regions ---------------------------
  // Exact coordinates of every vertex, indexed through the vertex's `arc` slot until arcs are
  // numbered below (the slot is reset then).
  std::vector<ExactXY> exact_point;
  exact_point.reserve(arr.number_of_vertices());
  for (auto v = arr.vertices_begin(); v != arr.vertices_end(); ++v) {
    v->data().arc = static_cast<int>(exact_point.size());
    exact_point.push_back({to_rational(v->point().x()), to_rational(v->point().y())});
  }
  auto complex2 = std::make_shared<Complex2>();
  Complex2& out = *complex2;
  out.reversed = reversed;
  out.arrangement_vertices = arr.number_of_vertices();
  out.arrangement_edges = arr.number_of_edges();
  out.arrangement_faces = arr.number_of_faces();
  out.curves = input;
  if (reversed) {
    for (Curve& c : out.curves.curves) std::reverse(c.vertices.begin() + 1, c.vertices.end());
  }
  // Bounding box corner for a point of the unbounded region.
  Point low = input.curves.front().vertices.front();
  for (const Curve& c : input.curves) {
    for (const Point& p : c.vertices) low = {std::min(low.x, p.x), std::min(low.y, p.y)};
  }
  for (std::size_t r = 0; r < faces.size(); ++r) {
    const FaceHandle f = faces[r];
    std::vector<Rational> terms;  // shoelace terms of every boundary edge (holes run clockwise)
    std::vector<Loop> loops;
    auto add_ccb = [&](auto first) {
      Loop loop;
      auto h = first;
      do {
        const ExactXY& a = exact_point[static_cast<std::size_t>(h->source()->data().arc)];
        const ExactXY& b = exact_point[static_cast<std::size_t>(h->target()->data().arc)];
        terms.emplace_back(a.x * b.y - b.x * a.y);
        loop.push_back(to_double(h->source()->point()));
      } while (++h != first);
      loops.push_back(std::move(loop));
    };
    if (!f->is_unbounded()) {
      add_ccb(f->outer_ccb());
      for (auto hole = f->inner_ccbs_begin(); hole != f->inner_ccbs_end(); ++hole) add_ccb(*hole);
    }
    const Rational area = f->is_unbounded() ? Rational(0) : Rational(tree_sum(std::move(terms)) / 2);
    const bool simply_connected = f->is_unbounded() || f->number_of_inner_ccbs() == 0;
    out.complex.add_region(winding[r], area, simply_connected);
    out.region_boundary.push_back(std::move(loops));
    out.region_sample.push_back(f->is_unbounded() ? Point{low.x - 1.0, low.y - 1.0}
                                                  : to_double(interior_point(f)));
  }

  exact_point = {};
  for (auto v = arr.vertices_begin(); v != arr.vertices_end(); ++v) v->data().arc = -1;

  // ---- patches: maximal runs of cut edges along a curve between crossings ------------------
  // Pieces of every segment in segment direction, sorted along it.
  std::vector<std::vector<HalfedgeHandle>> pieces(n);
  {
    std::size_t s = 0;
    for (auto c = arr.curves_begin(); c != arr.curves_end(); ++c, ++s) {
      for (auto e = arr.induced_edges_begin(c); e != arr.induced_edges_end(c); ++e) {
        HalfedgeHandle h = *e;
        if (!same_direction(h)) h = h->twin();
        pieces[s].push_back(h);
      }
      const bool right = segment_right[s];
      std::sort(pieces[s].begin(), pieces[s].end(), [&](HalfedgeHandle a, HalfedgeHandle b) {
        return CGAL::compare_xy(a->source()->point(), b->source()->point()) ==
               (right ? CGAL::SMALLER : CGAL::LARGER);
      });
    }
  }
  auto exact = std::make_shared<CutCurve>();
  CutCurve& cut = *exact;
  cut.input_points = points;
  std::vector<VertexHandle> arc_vertices;
  for (std::size_t ci = 0; ci < input.curves.size(); ++ci) {
    // The curve as a cyclic sequence of halfedges in the direction the complex uses.
    std::vector<HalfedgeHandle> sequence;
    for (std::size_t s = layout.offset[ci]; s < layout.offset[ci + 1]; ++s) {
      sequence.insert(sequence.end(), pieces[s].begin(), pieces[s].end());
    }
    if (reversed) {
      std::reverse(sequence.begin(), sequence.end());
      for (HalfedgeHandle& h : sequence) h = h->twin();
    }
    for (std::size_t k = 0; k < sequence.size(); ++k) {
      IMM_ASSERT(sequence[k]->target() == sequence[(k + 1) % sequence.size()]->source(),
                 "cut pieces of a curve are not contiguous");
    }
    const auto first_crossing = std::find_if(sequence.begin(), sequence.end(), [&](HalfedgeHandle h) {
      return h->source()->data().crossing;
    });
    std::rotate(sequence.begin(), first_crossing == sequence.end() ? sequence.begin() : first_crossing,
                sequence.end());
    std::vector<std::vector<HalfedgeHandle>> runs;
    for (std::size_t k = 0; k < sequence.size(); ++k) {
      if (k == 0 || sequence[k]->source()->data().crossing) runs.emplace_back();
      runs.back().push_back(sequence[k]);
    }
    for (const auto& run : runs) {
      const FaceHandle left = run.front()->face();
      const FaceHandle right = run.front()->twin()->face();
      PatchSides sides{region_of(right), region_of(left)};
      const PatchId patch = out.complex.add_patch(sides);
      std::vector<Point> polyline;
      std::vector<std::size_t> patch_segments;
      for (HalfedgeHandle h : run) {
        IMM_ASSERT(h->face() == left && h->twin()->face() == right, "a patch changes faces at an input vertex");
        h->data().patch = patch.value();
        h->twin()->data().patch = patch.value();
        polyline.push_back(to_double(h->source()->point()));
        patch_segments.push_back(cut.segments.size());
        cut.segments.push_back({h->source()->point(), h->target()->point(), patch, h->data().segment});
      }
      polyline.push_back(to_double(run.back()->target()->point()));
      out.patch_polyline.push_back(std::move(polyline));
      cut.patch_segments.push_back(std::move(patch_segments));
      const VertexHandle start = run.front()->source();
      if (start->data().crossing && start->data().arc < 0) {
        start->data().arc = static_cast<int>(arc_vertices.size());
        arc_vertices.push_back(start);
      }
    }
  }
  cut.vertex_patch.resize(n);
  for (std::size_t i = 0; i < n; ++i) cut.vertex_patch[i] = PatchId(pieces[i].front()->data().patch);

  // ---- arcs: the four junctions in counter-clockwise order ------------------------------
  // CGAL circulates the halfedges *into* a vertex clockwise; reversing gives counter-clockwise
  // order. Wedge k is left of the outgoing twin of incoming halfedge k, i.e. between edges k, k+1.
  for (std::size_t a = 0; a < arc_vertices.size(); ++a) {
    const VertexHandle v = arc_vertices[a];
    std::vector<HalfedgeHandle> incoming;
    auto circ = v->incident_halfedges();
    auto c = circ;
    do incoming.push_back(c);
    while (++c != circ);
    IMM_ASSERT(incoming.size() == 4, "a crossing must have degree 4");
    std::reverse(incoming.begin(), incoming.end());
    ArcJunctions junctions;
    for (int k = 0; k < 4; ++k) {
      junctions.patch[k] = PatchId(incoming[k]->data().patch);
      junctions.wedge[k] = region_of(incoming[k]->twin()->face());
    }
    for (int k = 0; k < 2; ++k) {
      IMM_ASSERT(incoming[k]->data().segment == incoming[k + 2]->data().segment,
                 "opposite junctions of a crossing must lie on the same segment");
    }
    out.complex.add_arc(junctions);
    out.arc_point.push_back(to_double(v->point()));
    cut.arc_points.push_back(v->point());
  }
  out.complex.finalize();
  out.exact = std::move(exact);
  result.complex = std::move(complex2);
  return finish();
}

}  // namespace

}  // namespace imm::dim2
