#include "support/random_curves.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

namespace imm::test_support {

using dim2::Curve;
using dim2::CurveSet;
using dim2::Point;

Curve random_polygon(std::uint64_t seed, std::size_t vertices, int range, int step) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> coord(0, range - 1);
  Curve c;
  while (c.vertices.size() < vertices) {
    const Point p{static_cast<double>(coord(rng) * step), static_cast<double>(coord(rng) * step)};
    if (!c.vertices.empty() && c.vertices.back() == p) continue;
    if (c.vertices.size() + 1 == vertices && c.vertices.front() == p) continue;
    c.vertices.push_back(p);
  }
  return c;
}

Curve random_star_curve(std::uint64_t seed, std::size_t vertices, int radius, double backtrack, int turns,
                        int step) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double mean_step = 2.0 * M_PI * turns / static_cast<double>(vertices);
  Curve c;
  for (std::size_t i = 0; i < vertices; ++i) {
    // Jitter wider than one step reorders neighbouring vertices: the curve runs backwards there.
    const double angle = mean_step * (static_cast<double>(i) + (1.0 + backtrack) * unit(rng));
    const double r = radius * (0.35 + 0.65 * unit(rng));
    const Point p{std::round(r * std::cos(angle)) * step, std::round(r * std::sin(angle)) * step};
    if (c.vertices.empty() || !(c.vertices.back() == p)) c.vertices.push_back(p);
  }
  if (c.vertices.size() > 1 && c.vertices.front() == c.vertices.back()) c.vertices.pop_back();
  return c;
}

Curve wobbly_circle(std::uint64_t seed, std::size_t vertices) {
  // Two counter-clockwise turns with a strictly increasing angle: the two passes interleave
  // radially and cross O(n) times, and every winding number lies in 0..2 (no inversion).
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double radius = 1.0e7;
  const double mean_step = 4.0 * M_PI / static_cast<double>(vertices);
  Curve c;
  for (std::size_t i = 0; i < vertices; ++i) {
    const double angle = mean_step * (static_cast<double>(i) + 0.5 * unit(rng));
    const double r = radius * (1.0 + 0.02 * unit(rng));
    const Point p{std::round(r * std::cos(angle)), std::round(r * std::sin(angle))};
    if (c.vertices.empty() || !(c.vertices.back() == p)) c.vertices.push_back(p);
  }
  return c;
}

namespace {

struct QPoint {
  Rational x, y;
};

QPoint exact(const Point& p) { return {Rational(p.x), Rational(p.y)}; }

int orientation(const QPoint& a, const QPoint& b, const QPoint& c) {
  return sgn(Rational((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)));
}

bool equal(const QPoint& a, const QPoint& b) { return a.x == b.x && a.y == b.y; }

/// p on the closed segment ab (exactly).
bool on_segment(const QPoint& a, const QPoint& b, const QPoint& p) {
  if (orientation(a, b, p) != 0) return false;
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
         p.y <= std::max(a.y, b.y);
}

struct Flat {
  std::vector<QPoint> points;
  std::vector<Point> raw;
  std::vector<std::size_t> next, curve;
};

Flat flatten(const CurveSet& set) {
  Flat f;
  for (std::size_t c = 0; c < set.curves.size(); ++c) {
    const std::size_t base = f.points.size();
    const std::size_t n = set.curves[c].vertices.size();
    for (std::size_t i = 0; i < n; ++i) {
      f.points.push_back(exact(set.curves[c].vertices[i]));
      f.raw.push_back(set.curves[c].vertices[i]);
      f.next.push_back(base + (i + 1) % n);
      f.curve.push_back(c);
    }
  }
  return f;
}

}  // namespace

Rational signed_area(const CurveSet& curves) {
  const Flat f = flatten(curves);
  Rational twice = 0;
  for (std::size_t s = 0; s < f.points.size(); ++s) {
    const QPoint& a = f.points[s];
    const QPoint& b = f.points[f.next[s]];
    twice += a.x * b.y - b.x * a.y;
  }
  return twice / 2;
}

CrossingFacts crossing_facts(const CurveSet& curves) {
  const Flat f = flatten(curves);
  const std::size_t n = f.points.size();
  CrossingFacts facts;
  facts.crossings_per_curve.assign(curves.curves.size(), 0);
  std::vector<QPoint> crossing_points;
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      if (equal(f.points[i], f.points[j])) ++facts.coincident_vertices;
    }
  }
  for (std::size_t v = 0; v < n; ++v) {
    for (std::size_t s = 0; s < n; ++s) {
      if (s == v || f.next[s] == v) continue;
      if (on_segment(f.points[s], f.points[f.next[s]], f.points[v])) ++facts.vertex_on_segment;
    }
  }
  for (std::size_t s = 0; s < n; ++s) {
    const QPoint& a = f.points[s];
    const QPoint& b = f.points[f.next[s]];
    for (std::size_t t = s + 1; t < n; ++t) {
      const QPoint& c = f.points[t];
      const QPoint& d = f.points[f.next[t]];
      // Cheap rejection on bounding boxes (exact: the raw values are the exact coordinates).
      const Point &ra = f.raw[s], &rb = f.raw[f.next[s]], &rc = f.raw[t], &rd = f.raw[f.next[t]];
      if (std::max(ra.x, rb.x) < std::min(rc.x, rd.x) || std::max(rc.x, rd.x) < std::min(ra.x, rb.x) ||
          std::max(ra.y, rb.y) < std::min(rc.y, rd.y) || std::max(rc.y, rd.y) < std::min(ra.y, rb.y)) {
        continue;
      }
      const int o1 = orientation(a, b, c), o2 = orientation(a, b, d);
      const int o3 = orientation(c, d, a), o4 = orientation(c, d, b);
      if (o1 * o2 < 0 && o3 * o4 < 0) {
        ++facts.proper_crossings;
        ++facts.crossings_per_curve[f.curve[s]];
        ++facts.crossings_per_curve[f.curve[t]];
        // a + t (b - a), t = cross(c - a, d - c) / cross(b - a, d - c)
        const Rational num = (c.x - a.x) * (d.y - c.y) - (c.y - a.y) * (d.x - c.x);
        const Rational den = (b.x - a.x) * (d.y - c.y) - (b.y - a.y) * (d.x - c.x);
        const Rational param = num / den;
        crossing_points.push_back({a.x + param * (b.x - a.x), a.y + param * (b.y - a.y)});
        const std::size_t ci = std::min(f.curve[s], f.curve[t]), cj = std::max(f.curve[s], f.curve[t]);
        if (ci != cj) facts.crossing_curves.emplace_back(ci, cj);
      }
    }
  }
  std::sort(crossing_points.begin(), crossing_points.end(), [](const QPoint& p, const QPoint& q) {
    return p.x < q.x || (p.x == q.x && p.y < q.y);
  });
  for (std::size_t k = 0; k + 1 < crossing_points.size(); ++k) {
    if (equal(crossing_points[k], crossing_points[k + 1])) ++facts.triple_points;
  }
  std::sort(facts.crossing_curves.begin(), facts.crossing_curves.end());
  facts.crossing_curves.erase(std::unique(facts.crossing_curves.begin(), facts.crossing_curves.end()),
                              facts.crossing_curves.end());
  facts.generic = facts.coincident_vertices == 0 && facts.vertex_on_segment == 0 && facts.triple_points == 0;
  return facts;
}

bool on_curves(const CurveSet& curves, const Point& p) {
  const Flat f = flatten(curves);
  const QPoint q = exact(p);
  for (std::size_t s = 0; s < f.points.size(); ++s) {
    if (on_segment(f.points[s], f.points[f.next[s]], q)) return true;
  }
  return false;
}

int winding_number(const CurveSet& curves, const Point& p) {
  // Sunday's crossing rule with exact orientation tests.
  const Flat f = flatten(curves);
  const QPoint q = exact(p);
  int w = 0;
  for (std::size_t s = 0; s < f.points.size(); ++s) {
    const QPoint& a = f.points[s];
    const QPoint& b = f.points[f.next[s]];
    if (a.y <= q.y) {
      if (b.y > q.y && orientation(a, b, q) > 0) ++w;
    } else if (b.y <= q.y && orientation(a, b, q) < 0) {
      --w;
    }
  }
  return w;
}

std::size_t curve_components(const CurveSet& curves, const CrossingFacts& facts) {
  std::vector<std::size_t> parent(curves.curves.size());
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  auto find = [&](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::size_t components = curves.curves.size();
  for (const auto& [a, b] : facts.crossing_curves) {
    const std::size_t ra = find(a), rb = find(b);
    if (ra != rb) {
      parent[ra] = rb;
      --components;
    }
  }
  return components;
}

}  // namespace imm::test_support
