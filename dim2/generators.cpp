#include "dim2/generators.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <functional>
#include <numbers>
#include <numeric>
#include <random>

#include "core/diagnostics.h"
#include "core/rational.h"

namespace imm::dim2 {
namespace {

constexpr double kPi = std::numbers::pi;

// ---- building blocks ----------------------------------------------------------------------

/// Rounds to integers at `scale` and drops consecutive duplicates (also across the wrap).
Curve rounded_curve(const std::vector<Point>& points, double scale) {
  Curve c;
  for (const Point& p : points) {
    const Point q{std::round(p.x * scale), std::round(p.y * scale)};
    if (c.vertices.empty() || !(c.vertices.back() == q)) c.vertices.push_back(q);
  }
  while (c.vertices.size() > 1 && c.vertices.front() == c.vertices.back()) c.vertices.pop_back();
  for (Point& p : c.vertices) {  // no negative zeros in the output text
    if (p.x == 0.0) p.x = 0.0;
    if (p.y == 0.0) p.y = 0.0;
  }
  return c;
}

CurveSet single(Curve c) {
  CurveSet set;
  set.curves.push_back(std::move(c));
  return set;
}

CurveSet integer_polygon(std::initializer_list<std::pair<int, int>> points, int scale = 1) {
  Curve c;
  for (const auto& [x, y] : points) c.vertices.push_back({double(x * scale), double(y * scale)});
  return single(std::move(c));
}

/// A point on a smooth core curve and its (not necessarily unit) tangent.
struct CorePose {
  Point position;
  Point tangent;
};

/// The boundary of a band of constant `width` around a core polyline with tangents: the right
/// offset forward, then the left offset backward (so the band lies on the left: counter-
/// clockwise), both ends closed by straight caps. @pre |curvature| * width / 2 < 1 everywhere.
std::vector<Point> band_boundary(const std::vector<CorePose>& core, double width) {
  std::vector<Point> right, left;
  for (const CorePose& pose : core) {
    const double length = std::hypot(pose.tangent.x, pose.tangent.y);
    const double nx = -pose.tangent.y / length, ny = pose.tangent.x / length;  // left normal
    right.push_back({pose.position.x - 0.5 * width * nx, pose.position.y - 0.5 * width * ny});
    left.push_back({pose.position.x + 0.5 * width * nx, pose.position.y + 0.5 * width * ny});
  }
  std::vector<Point> boundary = right;
  boundary.insert(boundary.end(), left.rbegin(), left.rend());
  return boundary;
}

/// Samples a parametric core on [t0, t1] at `steps` + 1 points (both ends included).
std::vector<CorePose> sample_core(const std::function<CorePose(double)>& curve, double t0,
                                  double t1, int steps) {
  std::vector<CorePose> out;
  for (int i = 0; i <= steps; ++i) out.push_back(curve(t0 + (t1 - t0) * i / steps));
  return out;
}

// Seifert circles and joins (see generators.h).
struct SeifertCircle {
  double cx = 0.0, cy = 0.0, radius = 1.0;
  int orientation = 1;  ///< +1 counter-clockwise, -1 clockwise
};
struct SeifertJoin {
  int first = 0;
  double first_angle = 0.0;  ///< radians, on circle `first`
  int second = 0;
  double second_angle = 0.0;
};

/// Traces the curves obtained by joining the circles: at every join the strand arriving on one
/// circle leaves on the other. The strands are cut `gap` radians before and after the join
/// angle; every full turn of a circle is sampled with `samples_per_turn` points.
CurveSet trace_seifert(const std::vector<SeifertCircle>& circles,
                       const std::vector<SeifertJoin>& joins, int samples_per_turn, double scale,
                       double gap) {
  struct Event {
    double angle;
    int join;
    int side;  // 0 = first, 1 = second
  };
  std::vector<std::vector<Event>> events(circles.size());
  for (int j = 0; j < static_cast<int>(joins.size()); ++j) {
    auto normalized = [](double a) {
      a = std::fmod(a, 2 * kPi);
      return a < 0 ? a + 2 * kPi : a;
    };
    events[joins[j].first].push_back({normalized(joins[j].first_angle), j, 0});
    events[joins[j].second].push_back({normalized(joins[j].second_angle), j, 1});
  }
  // arc_from[join][side]: the samples of the arc that starts at that event, and the event at
  // which it ends.
  struct Arc {
    std::vector<Point> points;
    int end_join = -1, end_side = -1;
  };
  std::vector<std::array<Arc, 2>> arcs(joins.size());
  for (std::size_t c = 0; c < circles.size(); ++c) {
    const SeifertCircle& circle = circles[c];
    const int o = circle.orientation;
    std::vector<Event>& e = events[c];
    IMM_ASSERT(!e.empty(), "a Seifert circle without join");
    std::sort(e.begin(), e.end(),
              [&](const Event& a, const Event& b) { return o * a.angle < o * b.angle; });
    for (std::size_t i = 0; i < e.size(); ++i) {
      const Event& from = e[i];
      const Event& to = e[(i + 1) % e.size()];
      const double a0 = from.angle + o * gap;
      double a1 = to.angle - o * gap;
      if (o > 0) {
        while (a1 <= a0) a1 += 2 * kPi;
      } else {
        while (a1 >= a0) a1 -= 2 * kPi;
      }
      const int k = std::max(2, static_cast<int>(std::abs(a1 - a0) / (2 * kPi) * samples_per_turn));
      Arc& arc = arcs[from.join][from.side];
      for (int s = 0; s <= k; ++s) {
        const double a = a0 + (a1 - a0) * s / k;
        arc.points.push_back(
            {circle.cx + circle.radius * std::cos(a), circle.cy + circle.radius * std::sin(a)});
      }
      arc.end_join = to.join;
      arc.end_side = to.side;
    }
  }
  CurveSet out;
  std::vector<std::array<bool, 2>> used(joins.size(), {false, false});
  for (int j = 0; j < static_cast<int>(joins.size()); ++j) {
    for (int side = 0; side < 2; ++side) {
      if (used[j][side]) continue;
      std::vector<Point> points;
      int cj = j, cs = side;
      while (!used[cj][cs]) {
        used[cj][cs] = true;
        const Arc& arc = arcs[cj][cs];
        points.insert(points.end(), arc.points.begin(), arc.points.end());
        cj = arc.end_join;
        cs = 1 - arc.end_side;  // arrive on one circle, leave on the other
      }
      out.curves.push_back(rounded_curve(points, scale));
    }
  }
  return out;
}

constexpr int kSeifertSamples = 96;      ///< samples per full turn of a Seifert circle
constexpr double kSeifertScale = 100.0;  ///< integer grid: 1/100 of the circle units
constexpr double kSeifertGap = 0.06;     ///< strand cut around a join, radians

/// The strand cut around a join of doodle(K): 0.06 rad, smaller for many lobes so that the cuts
/// of neighbouring joins (0.125 sector apart on the innermost circle) never overlap.
double doodle_gap(int lobes) { return std::min(0.06, 0.04 * 2 * kPi / lobes); }

/// Integer grid of doodle(K): finer for many lobes, where kinks and cuts get small.
double doodle_scale(int lobes) { return kSeifertScale * std::max(1.0, lobes / 6.0); }

/// The circles and joins of doodle(K), centred at (cx, 0), appended to the given lists.
/// @return the index of the outer circle.
int add_doodle(std::vector<SeifertCircle>& circles, std::vector<SeifertJoin>& joins, int lobes,
               double cx) {
  const int k = lobes;
  const int first = static_cast<int>(circles.size());
  std::vector<double> radius(k + 1);
  for (int i = 0; i <= k; ++i) {
    radius[i] = 3.0 * (k + 1 - i) + 1.0;
    circles.push_back({cx, 0.0, radius[i], 1});
  }
  const double sector = 2 * kPi / k;
  for (int i = 0; i < k; ++i) {
    // Alternate the join angles between levels so that no strand is joined twice at one angle.
    const double phase = sector * (i % 2 == 0 ? 0.125 : 0.375);
    for (int j = 0; j < k; ++j) {
      const double a = phase + sector * j;
      joins.push_back({first + i, a, first + i + 1, a});
    }
  }
  // The kinks sit on the middle of the second-innermost annulus; their radius is kept small
  // enough that the nearest join of that annulus (0.125 sector away, cut `gap` wide) misses them.
  const double kink_orbit = 0.5 * (radius[k - 1] + radius[k]);
  const double kink_radius = std::min(0.25 * (radius[k - 1] - radius[k]),
                                      0.6 * kink_orbit * (0.125 * sector - doodle_gap(k)));
  for (int j = 0; j < k; ++j) {
    const double a = sector * j;
    const int kink = static_cast<int>(circles.size());
    circles.push_back({cx + kink_orbit * std::cos(a), kink_orbit * std::sin(a), kink_radius, -1});
    joins.push_back({first + k, a, kink, a + kPi});
  }
  return first;
}

// ---- exact predicates for check_generic ---------------------------------------------------------

bool all_small_integers(const CurveSet& curves) {
  for (const Curve& c : curves.curves) {
    for (const Point& p : c.vertices) {
      for (const double v : {p.x, p.y}) {
        if (!(std::abs(v) <= 1099511627776.0) || std::trunc(v) != v) return false;  // 2^40
      }
    }
  }
  return true;
}

struct ExactSegment {
  Point a, b;
  std::size_t first_vertex, second_vertex;  // global vertex ids
};

int sign_of(__int128 v) { return (v > 0) - (v < 0); }

}  // namespace

// ---- check_generic / turning_number ------------------------------------------------------------

GenericityReport check_generic(const CurveSet& curves) {
  GenericityReport report;
  const bool integers = all_small_integers(curves);
  auto orient = [&](const Point& a, const Point& b, const Point& c) -> int {
    if (integers) {
      const auto ax = static_cast<__int128>(a.x), ay = static_cast<__int128>(a.y);
      const auto det = (static_cast<__int128>(b.x) - ax) * (static_cast<__int128>(c.y) - ay) -
                       (static_cast<__int128>(b.y) - ay) * (static_cast<__int128>(c.x) - ax);
      return sign_of(det);
    }
    const Rational det = (Rational(b.x) - a.x) * (Rational(c.y) - a.y) -
                         (Rational(b.y) - a.y) * (Rational(c.x) - a.x);
    return sgn(det);
  };
  std::vector<ExactSegment> segments;
  std::size_t offset = 0;
  for (const Curve& c : curves.curves) {
    const std::size_t n = c.vertices.size();
    for (std::size_t i = 0; i < n; ++i) {
      segments.push_back(
          {c.vertices[i], c.vertices[(i + 1) % n], offset + i, offset + (i + 1) % n});
      if (c.vertices[i] == c.vertices[(i + 1) % n] && report.generic) {
        report.generic = false;
        report.problem = "zero-length segment at vertex " + std::to_string(offset + i);
      }
    }
    offset += n;
  }
  auto fail = [&](const std::string& what, std::size_t i, std::size_t j) {
    if (!report.generic) return;
    report.generic = false;
    report.problem = what + " between segments " + std::to_string(i) + " and " + std::to_string(j);
  };
  // Projections along the dominant axis, for collinear pairs.
  auto overlap_1d = [](const ExactSegment& s, const ExactSegment& t, bool strict) {
    const bool use_x = s.a.x != s.b.x;
    double s0 = use_x ? s.a.x : s.a.y, s1 = use_x ? s.b.x : s.b.y;
    double t0 = use_x ? t.a.x : t.a.y, t1 = use_x ? t.b.x : t.b.y;
    if (s0 > s1) std::swap(s0, s1);
    if (t0 > t1) std::swap(t0, t1);
    return strict ? std::min(s1, t1) > std::max(s0, t0) : std::min(s1, t1) >= std::max(s0, t0);
  };
  // Crossing points: exact fractions (x_num / den, y_num / den), den > 0. With integer
  // coordinates |c| <= 2^20 they fit in __int128 (numerators <= 2^65, den <= 2^43, products
  // <= 2^108); otherwise GMP rationals.
  const bool small = integers && [&] {
    for (const ExactSegment& seg : segments) {
      for (const double v : {seg.a.x, seg.a.y}) {
        if (std::abs(v) > 1048576.0) return false;
      }
    }
    return true;
  }();
  struct FastCrossing {
    __int128 x, y, den;
    std::size_t i, j;
  };
  struct Crossing {
    Rational x, y;
    std::size_t i, j;
  };
  std::vector<FastCrossing> fast_crossings;
  std::vector<Crossing> crossings;
  // Candidate pairs by a sweep over x: segments sorted by their smallest x, each paired with
  // the following ones that start before it ends (bounding boxes compared exactly, as doubles).
  std::vector<std::size_t> order(segments.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  auto x_low = [&](std::size_t k) { return std::min(segments[k].a.x, segments[k].b.x); };
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return x_low(a) < x_low(b); });
  for (std::size_t oi = 0; oi < order.size(); ++oi) {
    const double sweep_end = std::max(segments[order[oi]].a.x, segments[order[oi]].b.x);
    for (std::size_t oj = oi + 1; oj < order.size() && x_low(order[oj]) <= sweep_end; ++oj) {
      const std::size_t i = std::min(order[oi], order[oj]), j = std::max(order[oi], order[oj]);
      const ExactSegment& s = segments[i];
      const ExactSegment& t = segments[j];
      if (std::max(t.a.y, t.b.y) < std::min(s.a.y, s.b.y) ||
          std::min(t.a.y, t.b.y) > std::max(s.a.y, s.b.y)) {
        continue;
      }
      const bool adjacent = s.second_vertex == t.first_vertex || t.second_vertex == s.first_vertex;
      const int o1 = orient(s.a, s.b, t.a), o2 = orient(s.a, s.b, t.b);
      if (adjacent) {
        // Neighbours share one vertex; they must not fold back onto each other. (A triangle's
        // segments are all pairwise adjacent; the check is the same.)
        if (o1 == 0 && o2 == 0 && overlap_1d(s, t, /*strict=*/true))
          fail("collinear overlap", i, j);
        continue;
      }
      if (o1 == 0 && o2 == 0) {
        if (overlap_1d(s, t, /*strict=*/false)) fail("collinear overlap or touching", i, j);
        continue;
      }
      const int o3 = orient(t.a, t.b, s.a), o4 = orient(t.a, t.b, s.b);
      if (o1 * o2 > 0 || o3 * o4 > 0) continue;
      if (o1 == 0 || o2 == 0 || o3 == 0 || o4 == 0) {
        fail("a vertex touches a segment", i, j);
        continue;
      }
      // Proper crossing: p = s.a + u (s.b - s.a), u = cross(t.a - s.a, t.b - t.a) / cross(s.b -
      // s.a, t.b - t.a).
      if (small) {
        const auto ax = static_cast<__int128>(s.a.x), ay = static_cast<__int128>(s.a.y);
        const __int128 dx = static_cast<__int128>(s.b.x) - ax,
                       dy = static_cast<__int128>(s.b.y) - ay;
        const __int128 ex = static_cast<__int128>(t.b.x) - static_cast<__int128>(t.a.x);
        const __int128 ey = static_cast<__int128>(t.b.y) - static_cast<__int128>(t.a.y);
        __int128 den = dx * ey - dy * ex;
        __int128 u =
            (static_cast<__int128>(t.a.x) - ax) * ey - (static_cast<__int128>(t.a.y) - ay) * ex;
        if (den < 0) {
          den = -den;
          u = -u;
        }
        fast_crossings.push_back({ax * den + u * dx, ay * den + u * dy, den, i, j});
        continue;
      }
      const Rational dx = Rational(s.b.x) - s.a.x, dy = Rational(s.b.y) - s.a.y;
      const Rational ex = Rational(t.b.x) - t.a.x, ey = Rational(t.b.y) - t.a.y;
      const Rational u =
          ((Rational(t.a.x) - s.a.x) * ey - (Rational(t.a.y) - s.a.y) * ex) / (dx * ey - dy * ex);
      crossings.push_back({Rational(s.a.x) + u * dx, Rational(s.a.y) + u * dy, i, j});
    }
  }
  report.crossings = crossings.size() + fast_crossings.size();
  auto triple = [&](std::size_t i0, std::size_t j0, std::size_t i1, std::size_t j1) {
    fail("a triple point (segments " + std::to_string(i0) + ", " + std::to_string(j0) + ")", i1,
         j1);
  };
  std::sort(fast_crossings.begin(), fast_crossings.end(),
            [](const FastCrossing& a, const FastCrossing& b) {
              const __int128 ax = a.x * b.den, bx = b.x * a.den;
              return ax != bx ? ax < bx : a.y * b.den < b.y * a.den;
            });
  for (std::size_t k = 1; k < fast_crossings.size(); ++k) {
    const FastCrossing& a = fast_crossings[k - 1];
    const FastCrossing& b = fast_crossings[k];
    if (a.x * b.den == b.x * a.den && a.y * b.den == b.y * a.den) triple(a.i, a.j, b.i, b.j);
  }
  std::sort(crossings.begin(), crossings.end(), [](const Crossing& a, const Crossing& b) {
    return a.x != b.x ? a.x < b.x : a.y < b.y;
  });
  for (std::size_t k = 1; k < crossings.size(); ++k) {
    if (crossings[k].x == crossings[k - 1].x && crossings[k].y == crossings[k - 1].y) {
      triple(crossings[k - 1].i, crossings[k - 1].j, crossings[k].i, crossings[k].j);
    }
  }
  return report;
}

int turning_number(const Curve& curve) {
  // The edge directions d_0..d_{n-1} form a closed polygon around the origin whose edges turn the
  // short way (the turn between consecutive directions is < pi in a generic curve); its winding
  // number around the origin is the turning number.
  const std::size_t n = curve.vertices.size();
  std::vector<std::pair<Rational, Rational>> d(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Point& a = curve.vertices[i];
    const Point& b = curve.vertices[(i + 1) % n];
    d[i] = {Rational(b.x) - a.x, Rational(b.y) - a.y};
  }
  int winding = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& [px, py] = d[i];
    const auto& [qx, qy] = d[(i + 1) % n];
    const int side = sgn(px * qy - py * qx);  // orientation of (origin, p, q)
    if (py <= 0 && qy > 0 && side > 0) ++winding;
    if (qy <= 0 && py > 0 && side < 0) --winding;
  }
  return winding;
}

// ---- the paper's figures
// -------------------------------------------------------------------------

CurveSet fig5() {
  // A band of width 3 around three sides of a square hole; its fourth leg runs down across the
  // band's own start (which ends inside it), so the two crossings sit on the left edge x = 3.
  return integer_polygon(
      {{2, 0}, {10, 0}, {10, 10}, {0, 10}, {0, -1}, {3, -1}, {3, 7}, {7, 7}, {7, 3}, {2, 3}}, 10);
}

CurveSet fig6() { return doodle(2); }

CurveSet fig7() {
  // The core: an egg (wider on the right); component A is a wide band around its right part,
  // component B a narrower band around its left part. Their ends overlap near the top and the
  // bottom: A's caps cross B's two edges, B's caps end inside A.
  auto egg = [](double t) {
    const double x = 7.0 * std::cos(t), y = 5.0 * std::sin(t) * (1.0 + 0.15 * std::cos(t));
    const double dx = -7.0 * std::sin(t);
    const double dy =
        5.0 * std::cos(t) * (1.0 + 0.15 * std::cos(t)) - 5.0 * std::sin(t) * 0.15 * std::sin(t);
    return CorePose{{x, y}, {dx, dy}};
  };
  const double deg = kPi / 180.0;
  CurveSet set;
  set.curves.push_back(
      rounded_curve(band_boundary(sample_core(egg, -115 * deg, 115 * deg, 92), 2.0), 100.0));
  set.curves.push_back(
      rounded_curve(band_boundary(sample_core(egg, 75 * deg, 285 * deg, 84), 1.4), 100.0));
  return set;
}

CurveSet fig8() {
  // r = 10 (1 + 0.3 cos(theta / 2)) for theta in [0, 4 pi): twice around the origin, the two
  // passes crossing once near (-10, 0).
  std::vector<Point> points;
  const int n = 20;
  for (int i = 0; i < n; ++i) {
    const double t = 4 * kPi * (i + 0.5) / n;
    const double r = 10.0 * (1.0 + 0.3 * std::cos(t / 2));
    points.push_back({r * std::cos(t), r * std::sin(t)});
  }
  return single(rounded_curve(points, 10.0));
}

CurveSet fig9() {
  // Diamond (winding 2) with corners at the crossings (0,4), (-4,0), (4,0), (0,-4); an arch over
  // the top (cell of winding 1, self-touching at (0,4)); two lenses below; a clockwise kink above
  // the top corner (a hole of winding 0).
  return integer_polygon({{-1, 5},
                          {-2, 7},
                          {0, 8},
                          {2, 7},
                          {1, 5},
                          {-6, -2},
                          {-5, -5},
                          {-2, -6},
                          {6, 2},
                          {5, 10},
                          {-5, 10},
                          {-6, 2},
                          {2, -6},
                          {5, -5},
                          {6, -2}},
                         10);
}

CurveSet fig12_simple() {
  // Half of the core: from the origin east, a 270 degree counter-clockwise turn, then south so that
  // the tip ends inside the middle of the band; the other half is its half-turn image.
  const double a = 3.4, radius = 3.0, tail = 3.6;
  std::vector<CorePose> half;
  const int straight_steps = 8, arc_steps = 54, tail_steps = 8;
  for (int i = 0; i <= straight_steps; ++i)
    half.push_back({{a * i / straight_steps, 0.0}, {1.0, 0.0}});
  for (int i = 1; i <= arc_steps; ++i) {
    const double t = -kPi / 2 + 1.5 * kPi * i / arc_steps;
    half.push_back(
        {{a + radius * std::cos(t), radius + radius * std::sin(t)}, {-std::sin(t), std::cos(t)}});
  }
  const Point corner = half.back().position;
  for (int i = 1; i <= tail_steps; ++i)
    half.push_back({{corner.x, corner.y - tail * i / tail_steps}, {0.0, -1.0}});
  std::vector<CorePose> core;
  for (std::size_t i = half.size(); i-- > 1;)
    core.push_back({{-half[i].position.x, -half[i].position.y}, half[i].tangent});
  core.insert(core.end(), half.begin(), half.end());
  return single(rounded_curve(band_boundary(core, 2.0), 100.0));
}

CurveSet fig12_ring() {
  // Each component goes around the origin twice: r = R (1 + 0.15 cos(theta / 2)); the inner one is
  // clockwise (the inner boundary of the annulus) and turned by 90 degrees.
  auto double_loop = [](double radius, double rotation, bool clockwise) {
    std::vector<Point> points;
    const int n = 96;
    for (int i = 0; i < n; ++i) {
      const double t = 4 * kPi * (i + 0.5) / n;
      const double r = radius * (1.0 + 0.15 * std::cos(t / 2));
      const double a = (clockwise ? -t : t) + rotation;
      points.push_back({r * std::cos(a), r * std::sin(a)});
    }
    return rounded_curve(points, 100.0);
  };
  CurveSet set;
  set.curves.push_back(double_loop(10.0, 0.0, false));
  set.curves.push_back(double_loop(5.0, kPi / 2, true));
  return set;
}

CurveSet fig15() {
  const double deg = kPi / 180.0;
  const std::vector<SeifertCircle> circles = {
      {0, 0, 10, 1}, {0, 0, 7, 1}, {0, 0, 4, 1}, {5.5, 0, 0.8, -1}, {-8.5, 0, 0.8, -1}};
  const std::vector<SeifertJoin> joins = {
      {0, 90 * deg, 1, 90 * deg}, {1, 270 * deg, 2, 270 * deg}, {2, 0, 3, kPi}, {1, kPi, 4, 0}};
  CurveSet set = trace_seifert(circles, joins, kSeifertSamples, kSeifertScale, kSeifertGap);
  IMM_ASSERT(set.curves.size() == 1, "fig15 must be one curve");
  return set;
}

// ---- known answers
// ---------------------------------------------------------------------------------

CurveSet convex_polygon(int vertices) {
  IMM_ASSERT(vertices >= 3, "a convex polygon needs at least 3 vertices");
  // Radius large enough that rounding to integers keeps every vertex strictly convex: the
  // sagitta 2 pi^2 R / n^2 must exceed the rounding error (< 1.5).
  const double radius = std::max(1000.0, 4.0 * vertices * vertices);
  std::vector<Point> points;
  for (int i = 0; i < vertices; ++i) {
    const double t = 2 * kPi * i / vertices + 0.1;
    points.push_back({radius * std::cos(t), radius * std::sin(t)});
  }
  return single(rounded_curve(points, 1.0));
}

CurveSet figure_eight(int samples) {
  IMM_ASSERT(samples >= 8 && samples % 2 == 0, "figure_eight needs an even number >= 8 of samples");
  // Lemniscate of Gerono, sampled symmetrically so that the crossing (the origin) is the midpoint
  // of two segments, never a vertex.
  std::vector<Point> points;
  for (int i = 0; i < samples; ++i) {
    const double t = 2 * kPi * (i + 0.5) / samples;
    points.push_back({std::sin(t), std::sin(t) * std::cos(t)});
  }
  return single(rounded_curve(points, 1000.0));
}

CurveSet limacon(int samples) {
  IMM_ASSERT(samples >= 12, "limacon needs at least 12 samples");
  std::vector<Point> points;
  for (int i = 0; i < samples; ++i) {
    const double t = 2 * kPi * (i + 0.5) / samples;
    const double r = 1.0 + 2.0 * std::cos(t);
    points.push_back({r * std::cos(t), r * std::sin(t)});
  }
  return single(rounded_curve(points, 1000.0));
}

CurveSet curl() { return spiral(1); }

CurveSet spiral(int turns) {
  IMM_ASSERT(turns >= 1, "spiral needs at least one turn");
  // Core r(theta) = r0 + pitch theta / (2 pi); band width 4 and pitch 4 / (turns + 1): every turn
  // overlaps all the others near the start, so the windings reach turns + 1.
  const double width = 4.0, pitch = width / (turns + 1), r0 = 8.0;
  const double end = 2 * kPi * turns + kPi / 3;
  auto core = [&](double t) {
    const double r = r0 + pitch * t / (2 * kPi);
    const double dr = pitch / (2 * kPi);
    return CorePose{{r * std::cos(t), r * std::sin(t)},
                    {dr * std::cos(t) - r * std::sin(t), dr * std::sin(t) + r * std::cos(t)}};
  };
  const int steps = 40 * turns + 7;  // odd offsets keep the caps away from sample angles
  // The integer grid keeps about 20 grid steps per pitch.
  const double scale = std::max(100.0, 20.0 * (turns + 1));
  return single(rounded_curve(band_boundary(sample_core(core, 0.0, end, steps), width), scale));
}

CurveSet doodle(int lobes) {
  IMM_ASSERT(lobes >= 1, "a doodle needs at least one lobe");
  std::vector<SeifertCircle> circles;
  std::vector<SeifertJoin> joins;
  add_doodle(circles, joins, lobes, 0.0);
  CurveSet set =
      trace_seifert(circles, joins, kSeifertSamples, doodle_scale(lobes), doodle_gap(lobes));
  IMM_ASSERT(set.curves.size() == 1, "the doodle's Seifert joins must give one curve");
  return set;
}

CurveSet doodle_chain(int count, int lobes) {
  IMM_ASSERT(count >= 1 && lobes >= 1, "doodle_chain needs count >= 1 and lobes >= 1");
  std::vector<SeifertCircle> circles;
  std::vector<SeifertJoin> joins;
  const double outer = 3.0 * (lobes + 1) + 1.0;
  int previous = -1;
  for (int i = 0; i < count; ++i) {
    const int first = add_doodle(circles, joins, lobes, i * (2.0 * outer + 3.0));
    // Opposite strands (right side of one outer circle going up, left side of the next going
    // down): the join is a thin band, not a crossing.
    if (previous >= 0) joins.push_back({previous, 0.0, first, kPi});
    previous = first;
  }
  CurveSet set =
      trace_seifert(circles, joins, kSeifertSamples, doodle_scale(lobes), doodle_gap(lobes));
  IMM_ASSERT(set.curves.size() == 1, "a doodle chain must be one curve");
  return set;
}

// ---- random ------------------------------------------------------------------------------------

namespace {

constexpr int kRandomRadius = 1 << 20;
constexpr int kMaxRedraws = 1000;

template <class Draw>
CurveSet first_generic(std::uint64_t seed, Draw&& draw) {
  std::mt19937_64 rng(seed);
  for (int attempt = 0; attempt < kMaxRedraws; ++attempt) {
    CurveSet set = draw(rng);
    if (check_generic(set).generic) return set;
  }
  IMM_ASSERT(false, "no generic random curve after many draws (seed " + std::to_string(seed) + ")");
  return {};
}

Curve random_star(std::mt19937_64& rng, int vertices, double cx, double cy, double radius) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> angles(vertices);
  for (int i = 0; i < vertices; ++i) angles[i] = 2 * kPi * (i + 0.8 * unit(rng)) / vertices;
  std::vector<Point> points;
  for (int i = 0; i < vertices; ++i) {
    const double r = radius * (0.55 + 0.45 * unit(rng));
    points.push_back({cx + r * std::cos(angles[i]), cy + r * std::sin(angles[i])});
  }
  return rounded_curve(points, 1.0);
}

}  // namespace

CurveSet random_polygon(int vertices, std::uint64_t seed) {
  IMM_ASSERT(vertices >= 3, "a polygon needs at least 3 vertices");
  return first_generic(seed, [&](std::mt19937_64& rng) {
    std::uniform_int_distribution<int> coordinate(-kRandomRadius, kRandomRadius);
    Curve c;
    while (static_cast<int>(c.vertices.size()) < vertices) {
      const Point p{double(coordinate(rng)), double(coordinate(rng))};
      if (p.x * p.x + p.y * p.y > double(kRandomRadius) * kRandomRadius) continue;
      if (!c.vertices.empty() && c.vertices.back() == p) continue;
      c.vertices.push_back(p);
    }
    return single(std::move(c));
  });
}

CurveSet random_multi(int components, int vertices, std::uint64_t seed) {
  IMM_ASSERT(components >= 1 && vertices >= 3,
             "random_multi needs components >= 1 and vertices >= 3");
  return first_generic(seed, [&](std::mt19937_64& rng) {
    // Centres on a jittered grid with pitch 1.3 radius, so neighbouring stars overlap.
    std::uniform_real_distribution<double> jitter(-0.25, 0.25);
    const double radius = kRandomRadius / 4.0;
    int columns = 1;
    while (columns * columns < components) ++columns;
    CurveSet set;
    for (int k = 0; k < components; ++k) {
      const double cx = ((k % columns) * 1.3 + jitter(rng)) * radius;
      const double cy = ((k / columns) * 1.3 + jitter(rng)) * radius;
      set.curves.push_back(random_star(rng, vertices, cx, cy, radius));
    }
    return set;
  });
}

CurveSet circles_pile(int count, std::uint64_t seed, int samples) {
  IMM_ASSERT(count >= 1 && samples >= 8, "circles_pile needs count >= 1 and samples >= 8");
  return first_generic(seed, [&](std::mt19937_64& rng) {
    constexpr double kRadius = 1 << 18;
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    CurveSet set;
    for (int k = 0; k < count; ++k) {
      const double cx = 0.8 * kRadius * unit(rng), cy = 0.8 * kRadius * unit(rng);
      const double phase = 2 * kPi * unit(rng);
      std::vector<Point> points;
      for (int i = 0; i < samples; ++i) {
        const double a = phase + 2 * kPi * i / samples;
        points.push_back({cx + kRadius * std::cos(a), cy + kRadius * std::sin(a)});
      }
      set.curves.push_back(rounded_curve(points, 1.0));
    }
    return set;
  });
}

}  // namespace imm::dim2
