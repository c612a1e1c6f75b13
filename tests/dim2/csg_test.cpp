// The CSG baseline (dim2/virtual_triangles_csg.cpp: exact Polygon_set_2 booleans of each region
// with each triangle) against the clipping path (dim2/virtual_triangles.cpp: Sutherland–Hodgman
// clipping and local arrangements). The two compute detail::LocalRegions independently; on every
// input they must give the same duplication: per triangle the same multiset of local-region
// regions and the same fusions (as region pairs per patch), per background edge the same
// adjacencies (as region pairs per patch), the same input-vertex placements, the same counts.
// Local-region indices may differ (the order of faces is not part of the contract), so every
// comparison is made on RegionIds. Timings of both paths are printed.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <algorithm>
#include <array>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "dim2/complex2.h"
#include "dim2/generators.h"
#include "dim2/mesh2.h"
#include "dim2/mesh2_detail.h"

namespace imm::dim2 {
namespace {

using detail::LocalRegions;

/// A comb of `teeth` teeth 1 wide with gaps `gap`, crossed by a horizontal band: many nearly
/// touching parallel pieces (and crossings) in one background triangle.
CurveSet comb(int teeth, double gap) {
  Curve c;
  const double width = 1.0, base = 1.0, height = 6.0;
  const double length = teeth * width + (teeth - 1) * gap;
  c.vertices.push_back({0.0, 0.0});
  c.vertices.push_back({length, 0.0});
  for (int i = teeth - 1; i >= 0; --i) {
    const double x0 = i * (width + gap), x1 = x0 + width;
    c.vertices.push_back({x1, height});
    c.vertices.push_back({x0, height});
    if (i > 0) {
      c.vertices.push_back({x0, base});
      c.vertices.push_back({x0 - gap, base});
    }
  }
  // The last push is (0, height): the curve closes down to (0, 0).
  Curve band;
  band.vertices = {{-1.0, 2.5}, {length + 1.0, 2.25}, {length + 1.0, 3.5}, {-1.0, 3.25}};
  CurveSet set;
  set.curves = {c, band};
  return set;
}

struct Case {
  std::string name;
  CurveSet curves;
  int resolution;
  bool conforming;
};

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// What a LocalRegions says, independent of local-region numbering.
struct Summary {
  std::vector<std::multiset<int>> triangle_regions;  ///< per triangle
  std::multiset<std::tuple<std::uint32_t, int, int, int>> fusions;  ///< triangle, inner, outer region, patch
  std::map<std::pair<int, int>, std::multiset<std::tuple<int, int, int>>> adjacencies;  ///< per edge
  std::vector<std::tuple<std::uint32_t, int, int>> vertices;  ///< triangle, region, patch
  std::size_t cut_triangles = 0;
};

Summary summarize(const LocalRegions& lr, const std::vector<std::array<int, 3>>& background) {
  const std::size_t triangles = background.size();
  Summary s;
  EXPECT_EQ(lr.first.size(), triangles + 1);
  EXPECT_EQ(lr.region.size(), lr.element.size());
  s.triangle_regions.resize(triangles);
  for (std::uint32_t t = 0; t < triangles; ++t)
    for (std::uint32_t i = lr.first[t]; i < lr.first[t + 1]; ++i) {
      EXPECT_EQ(lr.element[i], t);
      EXPECT_TRUE(lr.region[i].is_valid()) << "local region " << i << " without a region";
      s.triangle_regions[t].insert(lr.region[i].value());
    }
  for (const auto& f : lr.fusions) {
    EXPECT_EQ(lr.element[f.inner], lr.element[f.outer]);
    s.fusions.insert({lr.element[f.inner], lr.region[f.inner].value(), lr.region[f.outer].value(),
                      f.patch.value()});
  }
  for (const auto& a : lr.adjacencies) {
    // Free adjacencies are unordered: sort their regions.
    int x = lr.region[a.first].value(), y = lr.region[a.second].value();
    if (!a.patch.is_valid() && x > y) std::swap(x, y);
    const std::array<int, 2> edge = lr.face(a, background);
    s.adjacencies[{edge[0], edge[1]}].insert(
        {x, y, a.patch.value()});
  }
  for (const auto& v : lr.vertices) {
    if (v.local_region == UINT32_MAX) {
      s.vertices.emplace_back(UINT32_MAX, -1, v.patch.value());
    } else {
      s.vertices.emplace_back(lr.element[v.local_region], lr.region[v.local_region].value(),
                              v.patch.value());
    }
  }
  s.cut_triangles = lr.cut_elements;
  return s;
}

std::string regions_text(const std::multiset<int>& regions) {
  std::string text = "{";
  for (int r : regions) text += (text.size() > 1 ? ", " : "") + std::to_string(r);
  return text + "}";
}

std::vector<Case> cases() {
  std::vector<Case> out;
  const auto add = [&](std::string name, std::vector<std::string> args, int resolution, bool conforming) {
    GenerateResult g = generate(name, args);
    EXPECT_TRUE(g.ok()) << name << ": " << g.error;
    for (const auto& a : args) name += " " + a;
    if (conforming) name += " (conforming)";
    out.push_back({name + " @" + std::to_string(resolution), std::move(g.curves), resolution, conforming});
  };
  add("fig5", {}, 10, false);
  add("fig6", {}, 10, false);
  add("fig7", {}, 10, false);
  add("fig9", {}, 10, false);
  add("fig12-simple", {}, 10, false);
  add("fig12-ring", {}, 10, false);
  add("fig15", {}, 12, false);
  add("doodle", {"2"}, 8, false);
  add("doodle", {"3"}, 12, false);
  add("spiral", {"3"}, 10, false);
  add("random-multi", {"3", "8", "7"}, 10, false);
  // Coarse backgrounds: whole loops and several crossings inside one triangle (local regions
  // with holes, regions touching themselves at a crossing inside a triangle).
  add("fig6", {}, 3, false);
  add("fig12-ring", {}, 3, false);
  add("doodle", {"3"}, 4, false);
  add("fig6", {}, 8, true);
  add("doodle", {"2"}, 8, true);
  // Exact contacts (DESIGN §5): both paths run on the same perturbed copy.
  const auto curves = [](std::vector<std::vector<Point>> list) {
    CurveSet s;
    for (auto& c : list) s.curves.push_back({std::move(c)});
    return s;
  };
  const std::vector<Point> square{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  out.push_back({"contact shared edge @6", curves({square, {{1, 0}, {2, 0}, {2, 1}, {1, 1}}}), 6, false});
  out.push_back({"contact collinear overlap @6", curves({square, {{1, 0.25}, {2, 0.25}, {2, 0.75}, {1, 0.75}}}), 6, false});
  out.push_back({"contact vertex on segment @6", curves({square, {{0.5, 0}, {0.25, -0.5}, {0.75, -0.5}}}), 6, false});
  out.push_back({"comb 6 gap 1e-3 @8", comb(6, 1e-3), 8, false});
  out.push_back({"comb 5 gap 1e-9 @12", comb(5, 1e-9), 12, false});
  return out;
}

TEST(Csg, SameLocalRegionsAsClipping) {
  double total_clip = 0.0, total_csg = 0.0;
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const BuildResult built = build_complex(c.curves);
    ASSERT_TRUE(built.report.ok()) << c.name;
    ASSERT_TRUE(built.complex) << c.name;
    const Complex2& complex = *built.complex;
    MeshOptions options;
    options.resolution = c.resolution;
    options.conforming = c.conforming;
    ValidationReport bg_report;
    const detail::Background background = detail::make_background(complex, options, bg_report);
    ASSERT_TRUE(bg_report.ok());

    ValidationReport clip_report, csg_report;
    auto start = std::chrono::steady_clock::now();
    const LocalRegions clip = detail::compute_local_regions(complex, background, true, clip_report);
    const double t_clip = seconds_since(start);
    start = std::chrono::steady_clock::now();
    const LocalRegions csg = detail::compute_local_regions_csg(complex, background, true, csg_report);
    const double t_csg = seconds_since(start);
    total_clip += t_clip;
    total_csg += t_csg;
    std::printf("  %-32s %5zu triangles %4zu cut  clip %8.2f ms  csg %9.2f ms  (x%.0f)\n",
                c.name.c_str(), background.triangles.size(), clip.cut_elements, 1e3 * t_clip,
                1e3 * t_csg, t_csg / t_clip);
    ASSERT_TRUE(clip_report.ok());
    ASSERT_TRUE(csg_report.ok());

    const std::size_t n = background.triangles.size();
    const Summary a = summarize(clip, background.triangles);
    const Summary b = summarize(csg, background.triangles);
    if (c.conforming) {
      // No triangle is cut; the input runs along background edges instead.
      EXPECT_EQ(a.cut_triangles, 0u);
      std::size_t on_input = 0;
      for (const auto& adjacency : csg.adjacencies) on_input += adjacency.patch.is_valid() ? 1 : 0;
      EXPECT_GT(on_input, 0u);
    } else {
      EXPECT_GT(a.cut_triangles, 0u);
    }
    EXPECT_EQ(a.cut_triangles, b.cut_triangles);
    EXPECT_EQ(clip.region.size(), csg.region.size());
    std::size_t mismatched = 0;
    for (std::size_t t = 0; t < n; ++t)
      if (a.triangle_regions[t] != b.triangle_regions[t] && ++mismatched <= 5)
        ADD_FAILURE() << "triangle " << t << ": local regions " << regions_text(a.triangle_regions[t])
                      << " (clipping) vs " << regions_text(b.triangle_regions[t]) << " (CSG)";
    EXPECT_EQ(mismatched, 0u);
    EXPECT_EQ(clip.fusions.size(), csg.fusions.size());
    EXPECT_TRUE(a.fusions == b.fusions);
    EXPECT_EQ(clip.adjacencies.size(), csg.adjacencies.size());
    EXPECT_EQ(a.adjacencies.size(), b.adjacencies.size());
    mismatched = 0;
    for (const auto& [edge, list] : a.adjacencies) {
      const auto it = b.adjacencies.find(edge);
      if ((it == b.adjacencies.end() || it->second != list) && ++mismatched <= 5)
        ADD_FAILURE() << "edge (" << edge.first << ", " << edge.second << "): different adjacencies";
    }
    EXPECT_EQ(mismatched, 0u);
    EXPECT_EQ(a.vertices, b.vertices);
    // The vertex weights reproduce the same triangle: equal up to rounding of exact values.
    for (std::size_t v = 0; v < clip.vertices.size(); ++v)
      for (int k = 0; k < 3; ++k)
        EXPECT_EQ(clip.vertices[v].weights[k], csg.vertices[v].weights[k]) << "vertex " << v;
  }
  std::printf("  total: clip %.1f ms, csg %.1f ms\n", 1e3 * total_clip, 1e3 * total_csg);
}

/// A background that misses part of the input: both paths report NotCovered.
TEST(Csg, ReportsUncoveredInput) {
  GenerateResult g = generate("fig6", {});
  ASSERT_TRUE(g.ok());
  const BuildResult built = build_complex(g.curves);
  ASSERT_TRUE(built.complex);
  MeshOptions options;
  options.resolution = 8;
  ValidationReport bg_report;
  detail::Background background = detail::make_background(*built.complex, options, bg_report);
  ASSERT_TRUE(bg_report.ok());
  // Keep only the triangles left of the median centroid.
  std::vector<double> xs;
  for (const auto& t : background.triangles)
    xs.push_back(background.vertices[t[0]].x + background.vertices[t[1]].x + background.vertices[t[2]].x);
  std::vector<double> sorted = xs;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double median = sorted[sorted.size() / 2];
  std::vector<std::array<int, 3>> kept;
  for (std::size_t i = 0; i < xs.size(); ++i)
    if (xs[i] < median) kept.push_back(background.triangles[i]);
  background.triangles = kept;
  ValidationReport clip_report, csg_report;
  (void)detail::compute_local_regions(*built.complex, background, false, clip_report);
  (void)detail::compute_local_regions_csg(*built.complex, background, false, csg_report);
  EXPECT_FALSE(clip_report.ok());
  EXPECT_FALSE(csg_report.ok());
}

}  // namespace
}  // namespace imm::dim2
