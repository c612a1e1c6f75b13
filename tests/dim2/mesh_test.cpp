// 2D meshing (paper §7 with d = 2): DESIGN §4 invariants 5–8, checked on the output data with
// exact rational geometry written here, independently of dim2/virtual_triangles.cpp.
//  5 coverage: a background triangle strictly inside a cell of winding w appears exactly w times;
//  6 embedding: every input vertex is reproduced from its .emb weights and lies in its element;
//  7 unglued: element copies never join pieces the immersion keeps apart;
//  8 manifold (conforming meshes): a 2-manifold with boundary on the input, Euler characteristic
//    = turning number for one curve (1 for an immersed disk).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <sstream>
#include <tuple>

#include "core/graph_search.h"
#include "core/rational.h"
#include "core/union_find.h"
#include "dim2/complex2.h"
#include "dim2/mesh2.h"
#include "support/random_curves.h"

namespace imm::dim2 {

// dim2/generators.h (not included: its exact turning_number would clash with this file's).
CurveSet circles_pile(int count, std::uint64_t seed, int samples);

namespace {

// ---- exact geometry on doubles (every double is a rational) ----------------------------------

struct Q {
  Rational x, y;
};
Q exact(const Point& p) { return {Rational(p.x), Rational(p.y)}; }

int orient(const Q& a, const Q& b, const Q& c) {
  const Rational d = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  return sgn(d);
}

bool on_closed_segment(const Q& a, const Q& b, const Q& p) {
  return orient(a, b, p) == 0 && std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) &&
         std::min(a.y, b.y) <= p.y && p.y <= std::max(a.y, b.y);
}

bool closed_segments_meet(const Q& a, const Q& b, const Q& c, const Q& d) {
  const int o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  return on_closed_segment(a, b, c) || on_closed_segment(a, b, d) || on_closed_segment(c, d, a) ||
         on_closed_segment(c, d, b);
}

bool proper_crossing(const Q& a, const Q& b, const Q& c, const Q& d) {
  return orient(a, b, c) * orient(a, b, d) < 0 && orient(c, d, a) * orient(c, d, b) < 0;
}

/// @pre t counter-clockwise.
bool in_closed_triangle(const std::array<Q, 3>& t, const Q& p) {
  return orient(t[0], t[1], p) >= 0 && orient(t[1], t[2], p) >= 0 && orient(t[2], t[0], p) >= 0;
}

struct Segment {
  Point a, b;
};

/// Global input segments in input order: segment i joins vertex i and the next of its curve.
std::vector<Segment> input_segments(const CurveSet& curves) {
  std::vector<Segment> out;
  for (const Curve& c : curves.curves)
    for (std::size_t i = 0; i < c.vertices.size(); ++i)
      out.push_back({c.vertices[i], c.vertices[(i + 1) % c.vertices.size()]});
  return out;
}

std::vector<Point> input_points(const CurveSet& curves) {
  std::vector<Point> out;
  for (const Curve& c : curves.curves) out.insert(out.end(), c.vertices.begin(), c.vertices.end());
  return out;
}

double diagonal(const CurveSet& curves) {
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (const Point& p : input_points(curves)) {
    x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
  }
  return std::hypot(x1 - x0, y1 - y0);
}

/// Closed triangle (doubles, exact) meets the input, decided exactly (bounding boxes first).
bool meets_input(const std::array<Point, 3>& t, const std::vector<Segment>& segments) {
  const double tx0 = std::min({t[0].x, t[1].x, t[2].x}), tx1 = std::max({t[0].x, t[1].x, t[2].x});
  const double ty0 = std::min({t[0].y, t[1].y, t[2].y}), ty1 = std::max({t[0].y, t[1].y, t[2].y});
  const std::array<Q, 3> q = {exact(t[0]), exact(t[1]), exact(t[2])};
  for (const Segment& s : segments) {
    if (std::max(s.a.x, s.b.x) < tx0 || std::min(s.a.x, s.b.x) > tx1 ||
        std::max(s.a.y, s.b.y) < ty0 || std::min(s.a.y, s.b.y) > ty1)
      continue;
    const Q a = exact(s.a), b = exact(s.b);
    if (in_closed_triangle(q, a) || in_closed_triangle(q, b)) return true;
    for (int k = 0; k < 3; ++k)
      if (closed_segments_meet(a, b, q[k], q[(k + 1) % 3])) return true;
  }
  return false;
}

/// Turning number of one closed polygon (sum of exterior angles / 2 pi; angles are far from pi).
int turning_number(const Curve& c) {
  double total = 0.0;
  const std::size_t n = c.vertices.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Point& a = c.vertices[i];
    const Point& b = c.vertices[(i + 1) % n];
    const Point& d = c.vertices[(i + 2) % n];
    const double ux = b.x - a.x, uy = b.y - a.y, vx = d.x - b.x, vy = d.y - b.y;
    total += std::atan2(ux * vy - uy * vx, ux * vx + uy * vy);
  }
  return static_cast<int>(std::lround(total / (2 * std::numbers::pi)));
}

// ---- running the pipeline --------------------------------------------------------------------

struct Prepared {
  CurveSet curves;
  BuildResult built;
  SearchResult search;
};

Prepared prepare(const CurveSet& curves) {
  Prepared p{curves, build_complex(curves), {}};
  if (p.built.report.ok() && p.built.complex && !p.built.inversion) {
    SearchOptions options;
    options.max_immersions = 0;
    p.search = find_immersions(p.built.complex->complex, options);
  }
  return p;
}

MeshResult mesh(const Prepared& p, const Immersion& immersion, int resolution, bool conforming) {
  MeshOptions options;
  options.resolution = resolution;
  options.conforming = conforming;
  options.record_contents = true;
  return mesh_immersion(*p.built.complex, immersion, options);
}

// ---- invariant checks ------------------------------------------------------------------------

/// Every output triangle is counter-clockwise (exact orientation of its rounded vertices).
void expect_counter_clockwise(const TriangleMesh& mesh) {
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const auto& t = mesh.triangles[i];
    ASSERT_GT(orient(exact(mesh.vertices[t[0]]), exact(mesh.vertices[t[1]]),
                     exact(mesh.vertices[t[2]])),
              0)
        << "output triangle " << i;
  }
}

/// Invariant 5. @pre the background vertices are exact (not a conforming mesh).
void expect_coverage(const Prepared& p, const Immersion& immersion, const MeshResult& r) {
  const auto segments = input_segments(p.curves);
  const CellComplex<2>& cc = p.built.complex->complex;
  std::vector<std::vector<int>> copies(r.background.triangles.size());
  for (std::size_t i = 0; i < r.background_triangle.size(); ++i)
    copies[r.background_triangle[i]].push_back(r.mesh.reference[i]);
  std::size_t uncut_in_cells = 0;
  for (std::size_t t = 0; t < r.background.triangles.size(); ++t) {
    const auto& v = r.background.triangles[t];
    const std::array<Point, 3> tri = {r.background.vertices[v[0]], r.background.vertices[v[1]],
                                      r.background.vertices[v[2]]};
    // Triangles meeting the input hold local regions of several cells (or touch the input from
    // outside only): the other invariants check them.
    if (meets_input(tri, segments)) continue;
    // Closed triangle off the input: its vertex has the winding number of its interior.
    const int w = std::abs(test_support::winding_number(p.curves, tri[0]));
    ASSERT_EQ(copies[t].size(), static_cast<std::size_t>(w)) << "background triangle " << t;
    std::set<int> nodes(copies[t].begin(), copies[t].end());
    EXPECT_EQ(nodes.size(), copies[t].size()) << "two copies of one node in triangle " << t;
    for (int n : nodes) EXPECT_EQ(cc.winding_number(immersion.layout.cell(NodeId(n))), w);
    if (w > 0) ++uncut_in_cells;
  }
  EXPECT_GT(uncut_in_cells, 0u);
}

/// Invariant 6.
void expect_embedding(const Prepared& p, const MeshResult& r) {
  const auto points = input_points(p.curves);
  const double tolerance = 1e-9 * diagonal(p.curves);
  ASSERT_EQ(r.embedding.size(), points.size());
  for (std::size_t v = 0; v < points.size(); ++v) {
    const EmbeddedVertex& e = r.embedding[v];
    ASSERT_GE(e.element, 0) << "vertex " << v;
    ASSERT_LT(static_cast<std::size_t>(e.element), r.mesh.triangles.size());
    double x = 0.0, y = 0.0, sum = 0.0;
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(e.weights[k], 0.0) << "vertex " << v << " outside its element";
      const Point& q = r.mesh.vertices[r.mesh.triangles[e.element][k]];
      x += e.weights[k] * q.x;
      y += e.weights[k] * q.y;
      sum += e.weights[k];
    }
    EXPECT_NEAR(sum, 1.0, 1e-12);
    EXPECT_LE(std::hypot(x - points[v].x, y - points[v].y), tolerance) << "vertex " << v;
  }
}

/// Invariant 7, on the recorded copy contents:
///  - a copy's atoms belong to their nodes' cells, and are joined only through graph edges:
///    the atoms of a copy are connected by "different nodes glued by an immersion edge";
///    two atoms of one node are never merged directly;
///  - the input segments a copy embeds as boundary never cross each other (exact).
void expect_unglued(const Prepared& p, const Immersion& immersion, const MeshResult& r) {
  const CellComplex<2>& cc = p.built.complex->complex;
  const auto segments = input_segments(p.curves);
  std::set<std::pair<int, int>> glued;
  for (const ImmersionEdge& e : immersion.edges) {
    glued.insert({e.inner.value(), e.outer.value()});
    glued.insert({e.outer.value(), e.inner.value()});
  }
  ASSERT_EQ(r.contents.size(), r.mesh.triangles.size());
  for (std::size_t c = 0; c < r.contents.size(); ++c) {
    const auto& atoms = r.contents[c].atoms;
    ASSERT_FALSE(atoms.empty());
    int smallest = atoms[0].node.value();
    for (const auto& atom : atoms) {
      EXPECT_EQ(immersion.layout.cell(atom.node), cc.cell_of(atom.region)) << "copy " << c;
      smallest = std::min(smallest, atom.node.value());
    }
    EXPECT_EQ(r.mesh.reference[c], smallest);
    UnionFind connected(atoms.size());
    for (std::size_t i = 0; i < atoms.size(); ++i)
      for (std::size_t j = i + 1; j < atoms.size(); ++j)
        if (glued.count({atoms[i].node.value(), atoms[j].node.value()}))
          connected.unite(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j));
    for (std::size_t i = 1; i < atoms.size(); ++i)
      EXPECT_TRUE(connected.same(0, static_cast<std::uint32_t>(i)))
          << "copy " << c << " joins atoms not glued through the graph";
    const auto& owned = r.contents[c].owned_segments;
    for (std::size_t i = 0; i < owned.size(); ++i)
      for (std::size_t j = i + 1; j < owned.size(); ++j) {
        const Segment& a = segments[owned[i]];
        const Segment& b = segments[owned[j]];
        EXPECT_FALSE(proper_crossing(exact(a.a), exact(a.b), exact(b.a), exact(b.b)))
            << "copy " << c << " embeds crossing segments " << owned[i] << " and " << owned[j];
      }
  }
}

double distance_to_segment(const Point& p, const Segment& s) {
  const double dx = s.b.x - s.a.x, dy = s.b.y - s.a.y;
  const double t = std::clamp(((p.x - s.a.x) * dx + (p.y - s.a.y) * dy) / (dx * dx + dy * dy), 0.0, 1.0);
  return std::hypot(p.x - s.a.x - t * dx, p.y - s.a.y - t * dy);
}

struct Topology {
  long euler = 0;
  std::size_t components = 0;
};

/// Invariant 8: the glued mesh is an oriented 2-manifold with boundary lying on the input, the
/// boundary covering the input once. @return its Euler characteristic and component count.
Topology expect_manifold_on_input(const Prepared& p, const MeshResult& r) {
  const TriangleMesh& m = r.mesh;
  std::map<std::pair<int, int>, std::vector<std::pair<std::size_t, bool>>> edges;
  std::set<int> used;
  for (std::size_t i = 0; i < m.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const int a = m.triangles[i][k], b = m.triangles[i][(k + 1) % 3];
      used.insert(a);
      edges[{std::min(a, b), std::max(a, b)}].push_back({i, a < b});
    }
  const auto segments = input_segments(p.curves);
  const double tolerance = 1e-9 * diagonal(p.curves);
  double boundary_length = 0.0, curve_length = 0.0;
  for (const Segment& s : segments) curve_length += std::hypot(s.b.x - s.a.x, s.b.y - s.a.y);
  const auto near_curve = [&](const Point& q) {
    double best = 1e300;
    for (const Segment& s : segments) best = std::min(best, distance_to_segment(q, s));
    return best <= tolerance;
  };
  UnionFind components(m.triangles.size());
  for (const auto& [key, uses] : edges) {
    EXPECT_LE(uses.size(), 2u) << "non-manifold edge";
    if (uses.size() == 2) {
      EXPECT_NE(uses[0].second, uses[1].second) << "inconsistently oriented edge";
      components.unite(static_cast<std::uint32_t>(uses[0].first),
                       static_cast<std::uint32_t>(uses[1].first));
    } else if (uses.size() == 1) {
      const Point& a = m.vertices[key.first];
      const Point& b = m.vertices[key.second];
      EXPECT_TRUE(near_curve(a) && near_curve(b) && near_curve({(a.x + b.x) / 2, (a.y + b.y) / 2}))
          << "boundary edge off the input at (" << a.x << ", " << a.y << ")";
      boundary_length += std::hypot(b.x - a.x, b.y - a.y);
    }
  }
  EXPECT_NEAR(boundary_length, curve_length, 1e-9 * curve_length);
  // Vertex manifoldness: the triangles around each vertex form one fan.
  std::vector<std::vector<std::size_t>> around(m.vertices.size());
  for (std::size_t i = 0; i < m.triangles.size(); ++i)
    for (int v : m.triangles[i]) around[v].push_back(i);
  for (int v : used) {
    const auto& fan = around[v];
    UnionFind joined(fan.size());
    for (std::size_t i = 0; i < fan.size(); ++i)
      for (std::size_t j = i + 1; j < fan.size(); ++j) {
        int shared = 0;
        for (int a : m.triangles[fan[i]])
          for (int b : m.triangles[fan[j]]) shared += (a == b);
        if (shared == 2) joined.unite(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j));
      }
    for (std::size_t i = 1; i < fan.size(); ++i)
      EXPECT_TRUE(joined.same(0, static_cast<std::uint32_t>(i))) << "non-manifold vertex " << v;
  }
  Topology topology;
  topology.euler = static_cast<long>(used.size()) - static_cast<long>(edges.size()) +
                   static_cast<long>(m.triangles.size());
  std::set<std::uint32_t> roots;
  for (std::uint32_t i = 0; i < m.triangles.size(); ++i) roots.insert(components.find(i));
  topology.components = roots.size();
  return topology;
}

/// Connected components of a triangle mesh (triangles sharing an edge).
std::size_t edge_components(const TriangleMesh& m) {
  std::map<std::pair<int, int>, std::uint32_t> first_use;
  UnionFind components(m.triangles.size());
  for (std::uint32_t i = 0; i < m.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const int a = m.triangles[i][k], b = m.triangles[i][(k + 1) % 3];
      const auto [it, fresh] = first_use.insert({{std::min(a, b), std::max(a, b)}, i});
      if (!fresh) components.unite(it->second, i);
    }
  std::set<std::uint32_t> roots;
  for (std::uint32_t i = 0; i < m.triangles.size(); ++i) roots.insert(components.find(i));
  return roots.size();
}

/// Invariants 5, 6, 7 on a non-conforming mesh and 6, 8 on a conforming one, for every immersion.
void check_all(const Prepared& p, int resolution, std::optional<long> euler) {
  ASSERT_TRUE(p.built.report.ok()) << p.built.report.summary();
  ASSERT_EQ(p.search.status, ImmersionStatus::Immersible);
  for (std::size_t k = 0; k < p.search.immersions.size(); ++k) {
    SCOPED_TRACE(testing::Message() << "immersion " << k);
    const Immersion& immersion = p.search.immersions[k];
    const MeshResult r = mesh(p, immersion, resolution, false);
    ASSERT_TRUE(r.report.ok()) << r.report.summary();
    expect_counter_clockwise(r.mesh);
    expect_coverage(p, immersion, r);
    expect_embedding(p, r);
    expect_unglued(p, immersion, r);
    // One connected mesh per connected immersed surface (gluing not lost).
    EXPECT_EQ(edge_components(r.mesh), immersion.components().size());
    const MeshResult c = mesh(p, immersion, resolution, true);
    ASSERT_TRUE(c.report.ok()) << c.report.summary();
    EXPECT_EQ(c.stats.cut_triangles, 0u) << "a conforming mesh is never split by the input";
    expect_counter_clockwise(c.mesh);
    expect_embedding(p, c);
    expect_unglued(p, immersion, c);
    const Topology topology = expect_manifold_on_input(p, c);
    EXPECT_EQ(topology.components, immersion.components().size());
    if (euler) {
      EXPECT_EQ(topology.euler, *euler);
    }
  }
}

// ---- shapes ----------------------------------------------------------------------------------

CurveSet one(std::vector<Point> points) {
  CurveSet s;
  s.curves.push_back({std::move(points)});
  return s;
}

CurveSet square() { return one({{0, 0}, {1, 0}, {1, 1}, {0, 1}}); }

/// Two counter-clockwise squares, one inside the other: winding number 2 in the core.
CurveSet nested_squares() {
  CurveSet s = one({{0, 0}, {4, 0}, {4, 4}, {0, 4}});
  s.curves.push_back({{{1, 1}, {3, 1}, {3, 3}, {1, 3}}});
  return s;
}

/// A thick spiral band that overlaps itself over its last half radian: one curve, turning number
/// 1, a cell of winding number 2, two crossings.
CurveSet curl() {
  const double r_inner = 1.0, r_outer = 1.6, growth = 0.05, total = 2 * std::numbers::pi + 0.5;
  const int steps = 70;
  std::vector<Point> pts;
  for (int k = 0; k <= steps; ++k) {
    const double phi = total * k / steps;
    const double r = r_outer + growth * phi;
    pts.push_back({r * std::cos(phi), r * std::sin(phi)});
  }
  for (int k = steps; k >= 0; --k) {
    const double phi = total * k / steps;
    const double r = r_inner + growth * phi;
    pts.push_back({r * std::cos(phi), r * std::sin(phi)});
  }
  return one(std::move(pts));
}

/// A U: two fingers [0,2]x[0,10] and [2+gap,4+gap]x[0,10] on a base [0,4+gap]x[0,2].
CurveSet u_shape(double gap) {
  return one({{0, 0}, {4 + gap, 0}, {4 + gap, 10}, {2 + gap, 10}, {2 + gap, 2}, {2, 2}, {2, 10}, {0, 10}});
}

// ---- tests -----------------------------------------------------------------------------------

TEST(Mesh2, SquareInvariants) {
  const Prepared p = prepare(square());
  check_all(p, 24, 1);
  check_all(p, 5, 1);
}

TEST(Mesh2, NestedSquaresWindingTwo) {
  const Prepared p = prepare(nested_squares());
  ASSERT_EQ(p.built.complex->complex.max_winding_number(), 2);
  check_all(p, 20, 2);  // a disk with an annulus glued on, and a second disk
  const MeshResult r = mesh(p, p.search.immersions[0], 20, true);
  EXPECT_EQ(expect_manifold_on_input(p, r).components, 2u);
}

TEST(Mesh2, CurlIsAnImmersedDisk) {
  const Prepared p = prepare(curl());
  ASSERT_TRUE(p.built.report.ok()) << p.built.report.summary();
  ASSERT_EQ(p.built.complex->complex.max_winding_number(), 2);
  ASSERT_EQ(p.search.immersions.size(), 1u);
  ASSERT_EQ(turning_number(p.curves.curves[0]), 1);
  check_all(p, 20, 1);
  check_all(p, 6, 1);   // coarse: triangles span both sheets of the overlap
  check_all(p, 60, 1);  // fine: most cut triangles are crossed by single chords
}

/// k counter-clockwise circles (40-gons) around a common centre, overlapping like a Venn diagram:
/// winding numbers up to k, k components, one immersion (k disks).
CurveSet venn(int k, double spread) {
  CurveSet s;
  for (int c = 0; c < k; ++c) {
    const double angle = 2 * std::numbers::pi * c / k + 0.1;
    const double cx = spread * std::cos(angle), cy = spread * std::sin(angle);
    std::vector<Point> pts;
    for (int i = 0; i < 40; ++i) {
      const double t = 2 * std::numbers::pi * (i + 0.13 * c) / 40;
      pts.push_back({cx + std::cos(t), cy + std::sin(t)});
    }
    s.curves.push_back({std::move(pts)});
  }
  return s;
}

TEST(Mesh2, OverlappingDisksStaySeparateSheets) {
  for (int k : {3, 4}) {
    SCOPED_TRACE(testing::Message() << k << " circles");
    const Prepared p = prepare(venn(k, 0.6));
    ASSERT_TRUE(p.built.report.ok()) << p.built.report.summary();
    ASSERT_EQ(p.built.complex->complex.max_winding_number(), k);
    check_all(p, 16, k);  // k disjoint disks once unglued
  }
}

// Exact contacts (DESIGN §5): curves touching at a vertex, along a segment, a vertex on a
// segment. The complex describes a perturbed copy within 2^-30 of the diagonal; the mesh of it
// passes the same checks against the user's curves (coverage, embedding, unglued), with one
// mesh component per touching shape: they come apart, they are not glued. (Background meshes
// only: a conforming mesh would have to resolve the 2^-40 gap itself.)
CurveSet touching(std::vector<std::vector<Point>> curves) {
  CurveSet s;
  for (auto& c : curves) s.curves.push_back({std::move(c)});
  return s;
}

/// The input has exact contacts, which the perturbation resolves into one immersion of `parts`
/// components; its mesh passes the checks against the user's curves and has `parts` components.
void expect_contact_meshes_in_parts(const CurveSet& curves, std::size_t parts) {
  const Prepared p = prepare(curves);
  ASSERT_TRUE(p.built.contacts && p.built.contacts->perturbation) << "not a contact: " << p.built.report.summary();
  ASSERT_FALSE(p.built.inversion.has_value()) << p.built.inversion->message;
  ASSERT_EQ(p.search.immersions.size(), 1u);
  const Immersion& immersion = p.search.immersions.front();
  EXPECT_EQ(immersion.components().size(), parts);
  const MeshResult r = mesh(p, immersion, 8, false);
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  expect_counter_clockwise(r.mesh);
  expect_coverage(p, immersion, r);
  expect_embedding(p, r);
  expect_unglued(p, immersion, r);
  EXPECT_EQ(edge_components(r.mesh), parts);
}

TEST(Mesh2Contacts, TouchingCurvesMeshApart) {
  const std::vector<Point> a{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const std::vector<std::pair<const char*, CurveSet>> cases = {
      {"shared_edge", touching({a, {{1, 0}, {2, 0}, {2, 1}, {1, 1}}})},
      {"shared_corner", touching({a, {{1, 1}, {2, 1}, {2, 2}, {1, 2}}})},
      {"collinear_overlap", touching({a, {{1, 0.25}, {2, 0.25}, {2, 0.75}, {1, 0.75}}})},
      {"vertex_on_segment", touching({a, {{0.5, 0}, {0.25, -0.5}, {0.75, -0.5}}})},
  };
  for (const auto& [name, curves] : cases) {
    SCOPED_TRACE(name);
    expect_contact_meshes_in_parts(curves, 2);
  }
}

// A curve pinched at a vertex meshes as one immersed disk (the perturbation opens the pinch into
// a thin neck without crossing the curve); the same square twice meshes as two unglued copies
// (two mesh components, every triangle where they overlap present twice).
TEST(Mesh2Contacts, PinchAndIdenticalCopiesMesh) {
  const std::vector<Point> a{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const std::vector<std::tuple<const char*, CurveSet, std::size_t>> cases = {
      {"pinch", touching({{{0, 0}, {1, 0}, {1, 1}, {2, 1}, {2, 2}, {1, 2}, {1, 1}, {0, 1}}}), 1},
      {"twin", touching({a, a}), 2},
  };
  for (const auto& [name, curves, parts] : cases) {
    SCOPED_TRACE(name);
    expect_contact_meshes_in_parts(curves, parts);
  }
}

// A conforming mesh of touching squares would have to grade down to the 2^-40 gap the
// perturbation leaves along their shared side (~1e12 triangles): refused with a message once
// the refinement passes its vertex budget (about a second), instead of running out of memory.
TEST(Mesh2Contacts, ConformingMeshOfTouchingCurvesIsRefusedNotRunAway) {
  const Prepared p = prepare(touching({{{0, 0}, {1, 0}, {1, 1}, {0, 1}}, {{1, 0}, {2, 0}, {2, 1}, {1, 1}}}));
  ASSERT_EQ(p.search.immersions.size(), 1u);
  const MeshResult r = mesh(p, p.search.immersions.front(), 8, true);
  ASSERT_FALSE(r.report.ok());
  EXPECT_EQ(r.report.defects.front().kind, DefectKind::OutOfRange);
  EXPECT_NE(r.report.defects.front().message.find("mesh on a background instead"), std::string::npos)
      << r.report.defects.front().message;
  EXPECT_TRUE(r.mesh.triangles.empty());
}

TEST(Mesh2, ClockwiseInputIsMeshedInItsOwnVertexOrder) {
  // All winding numbers <= 0: the complex reverses the curve; embedding ids stay the file's.
  CurveSet curves = curl();
  std::reverse(curves.curves[0].vertices.begin(), curves.curves[0].vertices.end());
  const Prepared p = prepare(curves);
  ASSERT_TRUE(p.built.report.ok()) << p.built.report.summary();
  ASSERT_TRUE(p.built.complex->reversed);
  check_all(p, 12, 1);
}

// The measured embedding error (the JSON's "embedding_error", the CLI's warning) compares the
// .emb, in file order, with the file's vertices, not with the reversed curves of the complex: a
// clockwise square is reproduced exactly (its .emb lands on its own corners), on a background and
// on a conforming mesh.
TEST(Mesh2, ClockwiseInputHasNoEmbeddingError) {
  const CurveSet cw = touching({{{0, 0}, {0, 1}, {1, 1}, {1, 0}}});
  const Prepared p = prepare(cw);
  ASSERT_TRUE(p.built.report.ok()) << p.built.report.summary();
  ASSERT_TRUE(p.built.complex->reversed);
  ASSERT_EQ(p.search.immersions.size(), 1u);
  for (const bool conforming : {false, true}) {
    SCOPED_TRACE(conforming ? "conforming" : "background");
    const MeshResult r = mesh(p, p.search.immersions.front(), 8, conforming);
    ASSERT_TRUE(r.report.ok()) << r.report.summary();
    expect_embedding(p, r);
    EXPECT_LE(r.stats.embedding_error, 1e-12);
  }
}

/// Exact area of a triangle clipped to a box, > 0?
bool overlaps_box(const std::array<Point, 3>& t, double x0, double y0, double x1, double y1) {
  std::vector<Q> poly = {exact(t[0]), exact(t[1]), exact(t[2])};
  const Rational bounds[4] = {Rational(x0), Rational(y0), Rational(x1), Rational(y1)};
  for (int side = 0; side < 4; ++side) {
    const auto inside = [&](const Q& q) {
      switch (side) {
        case 0: return q.x >= bounds[0];
        case 1: return q.y >= bounds[1];
        case 2: return q.x <= bounds[2];
        default: return q.y <= bounds[3];
      }
    };
    std::vector<Q> next;
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Q& a = poly[i];
      const Q& b = poly[(i + 1) % poly.size()];
      if (inside(a)) next.push_back(a);
      if (inside(a) != inside(b)) {
        const bool vertical = side % 2 == 0;
        const Rational& c = bounds[side];
        const Rational s = vertical ? (c - a.x) / (b.x - a.x) : (c - a.y) / (b.y - a.y);
        next.push_back({a.x + s * (b.x - a.x), a.y + s * (b.y - a.y)});
      }
    }
    poly = std::move(next);
    if (poly.size() < 3) return false;
  }
  Rational area = 0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Q& a = poly[i];
    const Q& b = poly[(i + 1) % poly.size()];
    area += a.x * b.y - a.y * b.x;
  }
  return sgn(area) > 0;
}

TEST(Mesh2, NearSelfIntersectionKeepsFingersApart) {
  // The gap (0.05) is far smaller than a background triangle (~1.3): triangles span both fingers.
  const double gap = 0.05;
  const Prepared p = prepare(u_shape(gap));
  ASSERT_EQ(p.search.immersions.size(), 1u);
  const MeshResult r = mesh(p, p.search.immersions[0], 8, false);
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  std::vector<int> copies(r.background.triangles.size(), 0);
  for (int t : r.background_triangle) ++copies[t];
  // Expected copies = connected components of (open triangle) ∩ (open U), computed from the three
  // overlapping open rectangles: two meet inside the triangle iff triangle ∩ both has area > 0.
  const std::array<std::array<double, 4>, 3> boxes = {
      {{0, 0, 2, 10}, {2 + gap, 0, 4 + gap, 10}, {0, 0, 4 + gap, 2}}};
  std::size_t spanning = 0;
  for (std::size_t t = 0; t < r.background.triangles.size(); ++t) {
    const auto& v = r.background.triangles[t];
    const std::array<Point, 3> tri = {r.background.vertices[v[0]], r.background.vertices[v[1]],
                                      r.background.vertices[v[2]]};
    std::vector<int> present;
    for (int i = 0; i < 3; ++i)
      if (overlaps_box(tri, boxes[i][0], boxes[i][1], boxes[i][2], boxes[i][3])) present.push_back(i);
    UnionFind parts(3);
    for (int i : present)
      for (int j : present) {
        if (i >= j) continue;
        const double x0 = std::max(boxes[i][0], boxes[j][0]), y0 = std::max(boxes[i][1], boxes[j][1]);
        const double x1 = std::min(boxes[i][2], boxes[j][2]), y1 = std::min(boxes[i][3], boxes[j][3]);
        if (x0 < x1 && y0 < y1 && overlaps_box(tri, x0, y0, x1, y1)) parts.unite(i, j);
      }
    std::set<std::uint32_t> roots;
    for (int i : present) roots.insert(parts.find(i));
    EXPECT_EQ(copies[t], static_cast<int>(roots.size())) << "background triangle " << t;
    if (roots.size() == 2) ++spanning;
  }
  EXPECT_GT(spanning, 0u) << "no triangle spans the gap: the test would prove nothing";
  expect_embedding(p, r);
  expect_unglued(p, p.search.immersions[0], r);
}

/// A random thick spiral band {(rho, phi): |rho - r(phi)| <= half_width, 0 <= phi <= total}: the
/// image of a rectangle under an immersion, so its boundary bounds an immersed disk (turning
/// number 1), with winding numbers up to 3 where the laps overlap.
CurveSet random_band(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double half_width = 0.35 + 0.3 * u(rng);
  const double growth = (0.2 + 0.6 * u(rng)) * half_width / std::numbers::pi;  // laps overlap
  const double total = 2 * std::numbers::pi * (1.1 + 1.3 * u(rng));
  const double amplitude = 0.15 * u(rng), frequency = 2 + 3 * u(rng), phase = 6 * u(rng);
  const double rotation = 6.3 * u(rng);
  const int steps = static_cast<int>(total / (2 * std::numbers::pi) * (18 + 10 * u(rng)));
  const auto at = [&](double phi, double offset) {
    const double r = 3.0 + growth * phi + amplitude * std::sin(frequency * phi + phase) + offset;
    return Point{r * std::cos(phi + rotation), r * std::sin(phi + rotation)};
  };
  std::vector<Point> pts;
  for (int k = 0; k <= steps; ++k) pts.push_back(at(total * k / steps, half_width));
  for (int k = steps; k >= 0; --k) pts.push_back(at(total * k / steps, -half_width));
  return one(std::move(pts));
}

/// Issue 19: the first immersion of a pile of mutually overlapping circles (default search,
/// not an enumeration) meshes with every invariant.
TEST(Mesh2, CirclesPileFirstImmersion) {
  for (std::uint64_t seed : {1u, 2u}) {
    SCOPED_TRACE(testing::Message() << "circles-pile 6 seed " << seed);
    Prepared p{circles_pile(6, seed, 16), {}, {}};
    p.built = build_complex(p.curves);
    ASSERT_TRUE(p.built.report.ok()) << p.built.report.summary();
    p.search = find_immersions(p.built.complex->complex);
    ASSERT_EQ(p.search.immersions.size(), 1u);
    check_all(p, 24, std::nullopt);
  }
}

TEST(Mesh2, RandomBands) {
  int meshed = 0;
  int max_winding = 0;
  for (std::uint64_t seed = 0; seed < 12; ++seed) {
    SCOPED_TRACE(testing::Message() << "seed=" << seed);
    const Prepared p = prepare(random_band(seed));
    if (!p.built.report.ok()) continue;  // a non-generic draw (vanishingly rare)
    ASSERT_EQ(p.search.status, ImmersionStatus::Immersible);
    ASSERT_EQ(turning_number(p.curves.curves[0]), 1);
    max_winding = std::max(max_winding, p.built.complex->complex.max_winding_number());
    ++meshed;
    check_all(p, 14, 1);
  }
  EXPECT_GE(meshed, 10);
  EXPECT_GE(max_winding, 3);
}

TEST(Mesh2, RandomStarCurves) {
  // Simple and self-overlapping star-shaped curves (most are simple polygons: a sanity sweep).
  int meshed = 0;
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    SCOPED_TRACE(testing::Message() << "seed=" << seed);
    CurveSet curves;
    curves.curves.push_back(test_support::random_star_curve(seed, 14, 1000, 0.8));
    const Prepared p = prepare(curves);
    if (!p.built.report.ok() || p.built.inversion || p.search.status != ImmersionStatus::Immersible)
      continue;
    ++meshed;
    check_all(p, 12, turning_number(p.curves.curves[0]));
  }
  EXPECT_GE(meshed, 5);
}

TEST(Mesh2, RealCurves) {
  // ../shared/data/real/2d: among them jax_test_1, a self-overlapping curve with two immersions
  // (winding number 3, the situation of the paper's Fig. 6): both are meshed and checked.
  const std::filesystem::path dir = std::filesystem::path(IMM_SHARED_DATA_DIR) / "2d";
  if (!std::filesystem::is_directory(dir)) GTEST_SKIP() << "no real data at " << dir;
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    if (entry.path().extension() == ".txt") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  std::size_t immersions = 0, most = 0;
  for (const auto& file : files) {
    SCOPED_TRACE(file.filename().string());
    const ReadResult read = read_curves(file.string());
    if (!read.report.ok()) continue;
    const Prepared p = prepare(read.curves);
    if (!p.built.report.ok() || p.built.inversion || p.search.status != ImmersionStatus::Immersible)
      continue;
    immersions += p.search.immersions.size();
    most = std::max(most, p.search.immersions.size());
    std::optional<long> euler;
    // Turning number of the curve as the complex orients it (clockwise files are reversed).
    if (p.curves.curves.size() == 1)
      euler = (p.built.complex->reversed ? -1 : 1) * turning_number(p.curves.curves[0]);
    check_all(p, 20, euler);
  }
  EXPECT_GE(immersions, 4u);
  EXPECT_GE(most, 2u);
}

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          (name + "_" + std::to_string(::getpid()) + ".mesh"))
      .string();
}

void write_file(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

TEST(Mesh2, MeditRoundTrip) {
  const Prepared p = prepare(curl());
  const MeshResult r = mesh(p, p.search.immersions[0], 10, false);
  const std::string path = temp_path("imm_mesh_roundtrip");
  write_file(path, format_medit_2d(r.mesh));
  ValidationReport report;
  const TriangleMesh back = read_medit_2d(path, report);
  std::remove(path.c_str());
  ASSERT_TRUE(report.ok()) << report.summary();
  EXPECT_EQ(back.vertices, r.mesh.vertices);
  EXPECT_EQ(back.triangles, r.mesh.triangles);
  EXPECT_EQ(back.reference, r.mesh.reference);
}

TEST(Mesh2, GivenBackgroundGivesTheSameMesh) {
  const Prepared p = prepare(curl());
  const MeshResult generated = mesh(p, p.search.immersions[0], 10, false);
  const std::string path = temp_path("imm_mesh_background");
  write_file(path, format_medit_2d(generated.background));
  MeshOptions options;
  options.background_path = path;
  const MeshResult read = mesh_immersion(*p.built.complex, p.search.immersions[0], options);
  std::remove(path.c_str());
  ASSERT_TRUE(read.report.ok()) << read.report.summary();
  EXPECT_EQ(read.mesh.triangles, generated.mesh.triangles);
  EXPECT_EQ(read.mesh.vertices, generated.mesh.vertices);
}

TEST(Mesh2, BackgroundNotCoveringIsADefect) {
  const Prepared p = prepare(square());
  const std::string path = temp_path("imm_mesh_partial");
  // Covers only the lower-left half of the square.
  write_file(path, "MeshVersionFormatted 1\nDimension 2\nVertices\n3\n-1 -1 0\n2 -1 0\n-1 2 0\n"
                   "Triangles\n1\n1 2 3 0\nEnd\n");
  MeshOptions options;
  options.background_path = path;
  const MeshResult r = mesh_immersion(*p.built.complex, p.search.immersions[0], options);
  std::remove(path.c_str());
  ASSERT_FALSE(r.report.ok());
  EXPECT_EQ(r.report.defects[0].kind, DefectKind::NotCovered);
}

TEST(Mesh2, BadBackgroundFilesAreDefects) {
  const std::string path = temp_path("imm_mesh_bad");
  const std::pair<const char*, DefectKind> cases[] = {
      {"MeshVersionFormatted 1\nDimension 3\nVertices\n0\nEnd\n", DefectKind::Unreadable},
      {"MeshVersionFormatted 1\nDimension 2\nVertices\n3\n0 0 0\n1 0 0\n0 1 0\nTriangles\n1\n1 2 4 0\n",
       DefectKind::Unreadable},
      {"MeshVersionFormatted 1\nDimension 2\nVertices\n3\n0 0 0\n1 1 0\n2 2 0\nTriangles\n1\n1 2 3 0\n",
       DefectKind::DegenerateFacet},
      {"MeshVersionFormatted 1\nDimension 2\nVertices\n0\nEnd\n", DefectKind::Empty},
  };
  for (const auto& [text, kind] : cases) {
    write_file(path, text);
    ValidationReport report;
    read_medit_2d(path, report);
    ASSERT_FALSE(report.ok()) << text;
    EXPECT_EQ(report.defects[0].kind, kind) << text;
  }
  std::remove(path.c_str());
  ValidationReport report;
  read_medit_2d(path + ".missing", report);
  EXPECT_FALSE(report.ok());
}

/// A unit grid background over [-2, 6]^2 (clockwise triangles on purpose: the reader turns them).
std::string grid_background() {
  std::ostringstream os;
  const int n = 9;
  os << "MeshVersionFormatted 1\nDimension 2\nVertices\n" << n * n << '\n';
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) os << i - 2 << ' ' << j - 2 << " 0\n";
  os << "Triangles\n" << 2 * (n - 1) * (n - 1) << '\n';
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i + 1, b = a + 1, c = a + n, d = c + 1;
      os << a << ' ' << c << ' ' << b << " 0\n" << b << ' ' << c << ' ' << d << " 0\n";
    }
  os << "End\n";
  return os.str();
}

TEST(Mesh2, DegenerateContactsWithTheBackground) {
  // Curves along grid edges, through grid vertices, and with vertices on grid edges; the nested
  // curve makes a winding-2 cell. Every contact is degenerate for the background triangles.
  CurveSet curves = one({{0, 0}, {4, 0}, {4, 4}, {2, 4.5}, {0, 4}});
  curves.curves.push_back({{{1, 1}, {3, 1}, {3.5, 2}, {2, 3}, {1, 2.5}}});
  const Prepared p = prepare(curves);
  ASSERT_TRUE(p.built.report.ok()) << p.built.report.summary();
  const std::string path = temp_path("imm_mesh_grid");
  write_file(path, grid_background());
  for (const Immersion& immersion : p.search.immersions) {
    MeshOptions options;
    options.background_path = path;
    options.record_contents = true;
    const MeshResult r = mesh_immersion(*p.built.complex, immersion, options);
    ASSERT_TRUE(r.report.ok()) << r.report.summary();
    expect_counter_clockwise(r.mesh);
    expect_coverage(p, immersion, r);
    expect_embedding(p, r);
    expect_unglued(p, immersion, r);
  }
  std::remove(path.c_str());
}

/// The grid background plus separate triangles (1-based vertex triples over `extra` vertices).
std::string grid_with_islands(const std::vector<Point>& extra,
                              const std::vector<std::array<int, 3>>& islands) {
  const std::string grid = grid_background();
  const std::size_t vertices_at = grid.find("81\n");
  const std::size_t triangles_at = grid.find("Triangles");
  std::ostringstream os;
  os << grid.substr(0, vertices_at) << 81 + extra.size() << '\n'
     << grid.substr(vertices_at + 3, triangles_at - vertices_at - 3);
  for (const Point& q : extra) os << q.x << ' ' << q.y << " 0\n";
  const std::string body = grid.substr(grid.find('\n', triangles_at + 10) + 1);
  os << "Triangles\n" << 128 + islands.size() << '\n' << body.substr(0, body.find("End"));
  for (const auto& t : islands) os << t[0] << ' ' << t[1] << ' ' << t[2] << " 0\n";
  os << "End\n";
  return os.str();
}

TEST(Mesh2, DisconnectedBackgroundPartsAreLocatedExactly) {
  // An annulus (outer square counter-clockwise, inner one clockwise) on the grid, plus two
  // triangles not connected to the grid: one just off its corner, one far outside. Their regions
  // come from exact ray shooting; both have winding number 0 and get no copy. (A triangle over
  // the grid, even in the annulus' hole, would cover space twice: refused below.)
  CurveSet curves = one({{-1.5, -1.5}, {5.5, -1.5}, {5.5, 5.5}, {-1.5, 5.5}});
  curves.curves.push_back({{{1.5, 1.5}, {1.5, 2.5}, {2.5, 2.5}, {2.5, 1.5}}});
  const Prepared p = prepare(curves);
  ASSERT_EQ(p.search.immersions.size(), 1u);
  const std::vector<Point> extra = {{-2.9, -2.9}, {-2.1, -2.9}, {-2.5, -2.1}, {20, 20},
                                    {21, 20},   {20, 21},   {0.2, 0.2}, {0.4, 0.2}, {0.3, 0.4}};
  const std::string path = temp_path("imm_mesh_islands");
  write_file(path, grid_with_islands(extra, {{82, 83, 84}, {85, 86, 87}}));
  MeshOptions options;
  options.background_path = path;
  options.record_contents = true;
  const MeshResult r = mesh_immersion(*p.built.complex, p.search.immersions[0], options);
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  ASSERT_EQ(r.background.triangles.size(), 130u);
  for (int t : r.background_triangle) EXPECT_LT(t, 128);
  expect_coverage(p, p.search.immersions[0], r);
  expect_embedding(p, r);
  expect_unglued(p, p.search.immersions[0], r);
  // A third, lying over the grid inside the annulus: that space would be meshed twice, so the
  // background is refused, naming the island (triangle 130) and the grid triangle under it.
  write_file(path, grid_with_islands(extra, {{82, 83, 84}, {85, 86, 87}, {88, 89, 90}}));
  const MeshResult bad = mesh_immersion(*p.built.complex, p.search.immersions[0], options);
  std::remove(path.c_str());
  ASSERT_FALSE(bad.report.ok());
  ASSERT_EQ(bad.report.defects.size(), 1u) << bad.report.summary();
  const Defect& d = bad.report.defects[0];
  EXPECT_EQ(d.kind, DefectKind::InconsistentOrientation);
  EXPECT_NE(d.message.find("background triangles overlap"), std::string::npos) << d.message;
  ASSERT_EQ(d.facets.size(), 2u);
  EXPECT_LT(d.facets[0], 128);
  EXPECT_EQ(d.facets[1], 130);
  // The grid triangle named is one of the two of the unit square [0, 1]^2 under the island.
  ASSERT_EQ(d.points.size(), 1u);
  EXPECT_TRUE(d.points[0][0] >= 0 && d.points[0][0] <= 1 && d.points[0][1] >= 0 && d.points[0][1] <= 1);
}

/// The grid background's text with every vertex moved by (dx, dy) and its vertex numbers after
/// `offset` others; its vertex and triangle lines only.
std::pair<std::string, std::string> grid_lines(double dx, double dy, int offset) {
  std::ostringstream vertices, triangles;
  const int n = 9;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) vertices << i - 2 + dx << ' ' << j - 2 + dy << " 0\n";
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = offset + j * n + i + 1, b = a + 1, c = a + n, d = c + 1;
      triangles << a << ' ' << b << ' ' << c << " 0\n" << b << ' ' << d << ' ' << c << " 0\n";
    }
  return {vertices.str(), triangles.str()};
}

/// Grids moved by each of `shifts` in one background file.
std::string grids(const std::vector<Point>& shifts) {
  std::string v, t;
  for (std::size_t k = 0; k < shifts.size(); ++k) {
    const auto [vertices, triangles] = grid_lines(shifts[k].x, shifts[k].y, static_cast<int>(81 * k));
    v += vertices;
    t += triangles;
  }
  return "MeshVersionFormatted 1\nDimension 2\nVertices\n" + std::to_string(81 * shifts.size()) + "\n" + v +
         "Triangles\n" + std::to_string(128 * shifts.size()) + "\n" + t + "End\n";
}

// A background covering space twice would mesh it twice: pieces (triangles joined across edges)
// that overlap are refused, naming a triangle of each; pieces that only touch are meshed.
TEST(Mesh2, OverlappingBackgroundPiecesAreRefused) {
  const Prepared p = prepare(square());
  const std::string path = temp_path("imm_mesh_pieces");
  MeshOptions options;
  options.background_path = path;
  write_file(path, grids({{0, 0}}));
  const MeshResult plain = mesh_immersion(*p.built.complex, p.search.immersions[0], options);
  ASSERT_TRUE(plain.report.ok()) << plain.report.summary();
  // Crossing boundaries (a grid and the same grid moved by (0.25, 0.375)), and a grid wholly
  // inside another's triangles (a small one: no boundary crosses).
  const std::string small = "MeshVersionFormatted 1\nDimension 2\nVertices\n84\n" + grid_lines(0, 0, 0).first +
                            "3.1 3.1 0\n3.6 3.2 0\n3.3 3.7 0\nTriangles\n129\n" + grid_lines(0, 0, 0).second +
                            "82 83 84 0\nEnd\n";
  for (const std::string& text : {grids({{0, 0}, {0.25, 0.375}}), small}) {
    write_file(path, text);
    const MeshResult r = mesh_immersion(*p.built.complex, p.search.immersions[0], options);
    ASSERT_FALSE(r.report.ok());
    ASSERT_EQ(r.report.defects.size(), 1u) << r.report.summary();
    const Defect& d = r.report.defects[0];
    EXPECT_NE(d.message.find("background triangles overlap"), std::string::npos) << d.message;
    EXPECT_NE(d.message.find("different pieces"), std::string::npos) << d.message;
    ASSERT_EQ(d.facets.size(), 2u);
    EXPECT_LT(d.facets[0], 128);
    EXPECT_GE(d.facets[1], 128);
  }
  // Touching along x = 6 (coincident vertices of their own) and at the corner (6, 6): meshed as
  // the grid alone.
  write_file(path, grids({{0, 0}, {8, 0}, {8, 8}}));
  const MeshResult touching = mesh_immersion(*p.built.complex, p.search.immersions[0], options);
  std::remove(path.c_str());
  ASSERT_TRUE(touching.report.ok()) << touching.report.summary();
  EXPECT_EQ(touching.mesh.triangles, plain.mesh.triangles);
  EXPECT_EQ(touching.mesh.vertices, plain.mesh.vertices);
}

TEST(Mesh2, OutputFormats) {
  const Prepared p = prepare(curl());
  const MeshResult r = mesh(p, p.search.immersions[0], 8, false);
  const std::string emb = format_embedding(r.embedding);
  std::istringstream in(emb);
  std::size_t n = 0;
  in >> n;
  EXPECT_EQ(n, input_points(p.curves).size());
  int element = -1;
  double w[3];
  in >> element >> w[0] >> w[1] >> w[2];
  EXPECT_EQ(element, r.embedding[0].element);
  EXPECT_EQ(w[0], r.embedding[0].weights[0]);
  const std::string svg = format_mesh_svg(*p.built.complex, p.search.immersions[0], r);
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  // One panel per sheet layer: a title and a faint copy of every curve, then one polygon per
  // output triangle, one legend line per node, and the three lines of the frame.
  std::size_t layers = 0;
  for (std::size_t at = svg.find(">layer "); at != std::string::npos; at = svg.find(">layer ", at + 1)) ++layers;
  EXPECT_GE(layers, 1u);
  EXPECT_EQ(static_cast<std::size_t>(std::count(svg.begin(), svg.end(), '\n')),
            r.mesh.triangles.size() + layers * (1 + p.curves.curves.size()) +
                p.search.immersions[0].layout.node_count() + 3);
}

}  // namespace
}  // namespace imm::dim2
