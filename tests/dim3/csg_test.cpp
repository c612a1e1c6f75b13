// The CSG baseline (dim3/virtual_tets_csg.cpp: exact Nef booleans per tet, Sifakis et al. 2007)
// and the clipping path (dim3/virtual_tets.cpp) compute the same duplication of a generated grid
// background: per tet the same local regions with the same regions, and the same fusions,
// face adjacencies and input-vertex locations, up to the numbering of local regions within a
// tet, and the same cut triangles embedded on the same sides. The two share no code beyond the
// cut mesh, so agreement checks both. The CSG path costs seconds where clipping costs
// milliseconds (both times are printed), so the inputs and grids are small. Every meshable
// generator is here except the quintuple torus, which the Nef baseline cannot finish (see
// BENCHMARKS.md), plus the real comb; the CSG's own thread counts are compared field for field.
//
// Local regions are compared by colour refinement run on both results at once: a local region
// starts with the colour (tet, region); each round adds the sorted colours of its fusion partners
// (with the patch and side) and adjacency partners (with the face). Then the multisets of
// colours, fusions, adjacencies and embedded pieces, in colours, must be equal.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "dim3/generators3.h"
#include "dim3/mesh3_detail.h"
#include "dim3/self_connecting.h"
#include "dim3/surface.h"
#include "dim3/tet_mesh.h"

namespace imm::dim3 {
namespace {

using detail::LocalRegions;

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Canonical colours of the local regions of both results (same colour space).
struct Colours {
  std::vector<std::uint32_t> a, b;
};

Colours refine(const LocalRegions& x, const LocalRegions& y, const TetMesh& background, int rounds) {
  using Signature = std::vector<std::int64_t>;
  const auto initial = [](const LocalRegions& r, std::map<Signature, std::uint32_t>& ids) {
    std::vector<std::uint32_t> c(r.region.size());
    for (std::size_t i = 0; i < c.size(); ++i)
      c[i] = ids.emplace(Signature{r.element[i], r.region[i].value()}, static_cast<std::uint32_t>(ids.size())).first->second;
    return c;
  };
  std::map<Signature, std::uint32_t> ids;
  Colours c{initial(x, ids), initial(y, ids)};
  const auto step = [&background](const LocalRegions& r, const std::vector<std::uint32_t>& colour,
                       std::map<Signature, std::uint32_t>& next) {
    std::vector<std::vector<std::array<std::int64_t, 5>>> around(r.region.size());
    for (const auto& f : r.fusions) {
      around[f.inner].push_back({0, f.patch.value(), colour[f.outer], 0, 0});
      around[f.outer].push_back({1, f.patch.value(), colour[f.inner], 0, 0});
    }
    for (const auto& a : r.adjacencies) {
      const std::array<int, 3> face = r.face(a, background.tets);
      around[a.first].push_back({2, face[0], face[1], face[2], colour[a.second]});
      around[a.second].push_back({2, face[0], face[1], face[2], colour[a.first]});
    }
    std::vector<std::uint32_t> out(r.region.size());
    for (std::size_t i = 0; i < out.size(); ++i) {
      std::sort(around[i].begin(), around[i].end());
      Signature s{colour[i]};
      for (const auto& e : around[i]) s.insert(s.end(), e.begin(), e.end());
      out[i] = next.emplace(std::move(s), static_cast<std::uint32_t>(next.size())).first->second;
    }
    return out;
  };
  for (int k = 0; k < rounds; ++k) {
    std::map<Signature, std::uint32_t> next;
    c = {step(x, c.a, next), step(y, c.b, next)};
  }
  return c;
}

using Fusions = std::vector<std::tuple<std::uint32_t, std::uint32_t, std::int64_t>>;
using Adjacencies = std::vector<std::tuple<std::array<int, 3>, std::uint32_t, std::uint32_t>>;

Fusions fusions_in(const LocalRegions& r, const std::vector<std::uint32_t>& colour) {
  Fusions out;
  for (const auto& f : r.fusions) out.emplace_back(colour[f.inner], colour[f.outer], f.patch.value());
  std::sort(out.begin(), out.end());
  return out;
}

Adjacencies adjacencies_in(const LocalRegions& r, const TetMesh& background, const std::vector<std::uint32_t>& colour) {
  Adjacencies out;
  for (const auto& a : r.adjacencies) {
    // Ordered by tet: both paths put the smaller tet first, but do not rely on it.
    std::uint32_t p = a.first, q = a.second;
    if (r.element[p] > r.element[q]) std::swap(p, q);
    out.emplace_back(r.face(a, background.tets), colour[p], colour[q]);
  }
  std::sort(out.begin(), out.end());
  return out;
}

struct Case {
  const char* name;
  std::vector<std::string> args;
  int resolution;
};

/// Both methods on `surface` over a generated grid of `resolution` cubes give the same
/// duplication (see the file comment).
void expect_same_duplication(const Surface& surface, const std::string& name, int resolution) {
  ImmerseOptions options;
  options.build.exact_volumes = false;
  const Immersed im = immerse_surface(surface, options);
  ASSERT_TRUE(im.build.report.ok()) << im.build.report.summary();
  ASSERT_TRUE(im.build.complex != nullptr);
  ASSERT_FALSE(im.search.immersions.empty());
  const Complex& complex = *im.build.complex;
  const TetMesh background = make_grid_background(bounding_box(complex.surface), resolution, 0);

  ValidationReport clip_report, csg_report;
  bool clip_non_generic = false, csg_non_generic = false;
  auto start = std::chrono::steady_clock::now();
  const LocalRegions clip = detail::compute_local_regions(complex, background, {0, 0, 0}, /*record_embedded=*/true,
                                                            /*threads=*/1, /*interval_filter=*/true, clip_report,
                                                            clip_non_generic);
  const double clip_seconds = seconds_since(start);
  start = std::chrono::steady_clock::now();
  const LocalRegions csg =
      detail::compute_local_regions_csg(complex, background, /*record_embedded=*/true, /*threads=*/0, {}, csg_report,
                                         csg_non_generic);
  const double csg_seconds = seconds_since(start);
  std::printf("[ timing ] %s res %d: %zu tets, %zu cut tets, %zu local regions; clipping %.3f s, CSG %.3f s\n",
              name.c_str(), resolution, background.tets.size(), clip.cut_elements, clip.region.size(), clip_seconds,
              csg_seconds);
  ASSERT_TRUE(clip_report.ok()) << clip_report.summary();
  ASSERT_FALSE(clip_non_generic);
  ASSERT_TRUE(csg_report.ok()) << csg_report.summary();
  ASSERT_FALSE(csg_non_generic);
  ASSERT_GT(clip.cut_elements, 0u);

  // Per tet: the same number of local regions, lying in the same regions.
  ASSERT_EQ(csg.first.size(), clip.first.size());
  for (std::size_t t = 0; t + 1 < clip.first.size(); ++t) {
    std::vector<std::int32_t> a, b;
    for (std::uint32_t i = clip.first[t]; i < clip.first[t + 1]; ++i) a.push_back(clip.region[i].value());
    for (std::uint32_t i = csg.first[t]; i < csg.first[t + 1]; ++i) b.push_back(csg.region[i].value());
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    ASSERT_EQ(a, b) << "tet " << t;
  }
  EXPECT_EQ(csg.cut_elements, clip.cut_elements);
  EXPECT_EQ(csg.fusions.size(), clip.fusions.size());
  EXPECT_EQ(csg.adjacencies.size(), clip.adjacencies.size());
  EXPECT_EQ(csg.embedded.size(), clip.embedded.size());

  // The same connections, up to renumbering within tets.
  const Colours colour = refine(clip, csg, background, 4);
  std::vector<std::uint32_t> a = colour.a, b = colour.b;
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  EXPECT_EQ(a, b);
  EXPECT_EQ(fusions_in(clip, colour.a), fusions_in(csg, colour.b));
  EXPECT_EQ(adjacencies_in(clip, background, colour.a), adjacencies_in(csg, background, colour.b));
  const auto embedded_in = [](const LocalRegions& r, const std::vector<std::uint32_t>& colours) {
    std::vector<std::tuple<std::uint32_t, std::uint32_t, bool>> out;
    for (const auto& e : r.embedded) out.emplace_back(colours[e.local_region], e.cut_triangle, e.inner);
    std::sort(out.begin(), out.end());
    return out;
  };
  EXPECT_EQ(embedded_in(clip, colour.a), embedded_in(csg, colour.b));

  // Input vertices: the same tet, region, patch and weights.
  ASSERT_EQ(csg.vertices.size(), clip.vertices.size());
  for (std::size_t v = 0; v < clip.vertices.size(); ++v) {
    const auto& p = clip.vertices[v];
    const auto& q = csg.vertices[v];
    ASSERT_NE(p.local_region, LocalRegions::kNone) << "vertex " << v;
    ASSERT_NE(q.local_region, LocalRegions::kNone) << "vertex " << v;
    EXPECT_EQ(clip.element[p.local_region], csg.element[q.local_region]) << "vertex " << v;
    EXPECT_EQ(colour.a[p.local_region], colour.b[q.local_region]) << "vertex " << v;
    EXPECT_EQ(p.patch, q.patch) << "vertex " << v;
    EXPECT_EQ(p.weights, q.weights) << "vertex " << v;
  }
}

class CsgBaseline : public testing::TestWithParam<Case> {};

TEST_P(CsgBaseline, SameDuplicationAsClipping) {
  const Case& c = GetParam();
  const SurfaceGenerateResult g = generate_surface(c.name, c.args);
  ASSERT_TRUE(g.ok()) << g.error;
  expect_same_duplication(g.surface, c.name, c.resolution);
}

// The real comb (Vega's, 1/64 gaps between the teeth): the nearly touching case in a real file.
TEST(CsgBaselineReal, Comb) {
  const std::string path = std::string(IMM_SHARED_DATA_DIR) + "/3d/comb.obj";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not present";
  const SurfaceReadResult read = read_surface(path);
  ASSERT_TRUE(read.report.ok()) << read.report.summary();
  expect_same_duplication(read.surface, "comb.obj", 5);
}

// Tets run on threads and are merged in tet order: the result is the same, field for field.
TEST(CsgBaselineThreads, TheThreadCountDoesNotChangeTheResult) {
  const SurfaceGenerateResult g = generate_surface("comb", {"2"});
  ASSERT_TRUE(g.ok()) << g.error;
  ImmerseOptions options;
  options.build.exact_volumes = false;
  const Immersed im = immerse_surface(g.surface, options);
  ASSERT_TRUE(im.build.complex != nullptr);
  const Complex& complex = *im.build.complex;
  const TetMesh background = make_grid_background(bounding_box(complex.surface), 5, 0);  // 5 blocks of tets
  std::vector<LocalRegions> results;
  for (unsigned threads : {1u, 2u, 3u}) {
    ValidationReport report;
    bool non_generic = false;
    results.push_back(detail::compute_local_regions_csg(complex, background, /*record_embedded=*/true, threads, {},
                                                         report, non_generic));
    ASSERT_TRUE(report.ok()) << report.summary();
  }
  const LocalRegions& one = results.front();
  ASSERT_GT(one.cut_elements, 0u);
  for (const LocalRegions& r : results) {
    EXPECT_EQ(r.first, one.first);
    EXPECT_EQ(r.region, one.region);
    EXPECT_EQ(r.element, one.element);
    ASSERT_EQ(r.fusions.size(), one.fusions.size());
    for (std::size_t i = 0; i < r.fusions.size(); ++i)
      EXPECT_TRUE(r.fusions[i].inner == one.fusions[i].inner && r.fusions[i].outer == one.fusions[i].outer &&
                  r.fusions[i].patch == one.fusions[i].patch)
          << "fusion " << i;
    ASSERT_EQ(r.adjacencies.size(), one.adjacencies.size());
    for (std::size_t i = 0; i < r.adjacencies.size(); ++i)
      EXPECT_TRUE(r.adjacencies[i].first == one.adjacencies[i].first &&
                  r.adjacencies[i].second == one.adjacencies[i].second && r.adjacencies[i].patch == one.adjacencies[i].patch)
          << "adjacency " << i;
    ASSERT_EQ(r.embedded.size(), one.embedded.size());
    for (std::size_t i = 0; i < r.embedded.size(); ++i)
      EXPECT_TRUE(r.embedded[i].local_region == one.embedded[i].local_region &&
                  r.embedded[i].cut_triangle == one.embedded[i].cut_triangle && r.embedded[i].inner == one.embedded[i].inner)
          << "embedded " << i;
    ASSERT_EQ(r.vertices.size(), one.vertices.size());
    for (std::size_t v = 0; v < r.vertices.size(); ++v)
      EXPECT_TRUE(r.vertices[v].local_region == one.vertices[v].local_region && r.vertices[v].patch == one.vertices[v].patch &&
                  r.vertices[v].weights == one.vertices[v].weights)
          << "vertex " << v;
  }
}

// A background touching the input (a unit cube on the lattice of a grid of step 0.5): the CSG
// baseline takes no translation, so it reports the contact, naming the first tet in tet order
// whatever the thread count, and stops.
TEST(CsgBaselineTouching, TheFirstContactInTetOrderIsReported) {
  ImmerseOptions options;
  options.build.exact_volumes = false;
  const Immersed im = immerse_surface(box_surface(Box3{{0, 0, 0}, {1, 1, 1}}), options);
  ASSERT_TRUE(im.build.complex != nullptr);
  TetMesh grid = make_grid_background(Box3{{-1, -1, -1}, {2, 2, 2}}, 6, 0);
  for (Point3& v : grid.vertices)
    for (double& x : v) x = -1 + 0.5 * std::round((x + 1) / 0.5);  // onto the lattice
  std::vector<std::string> messages;
  for (unsigned threads : {1u, 3u}) {
    ValidationReport report;
    bool non_generic = false;
    detail::compute_local_regions_csg(*im.build.complex, grid, false, threads, {}, report, non_generic);
    EXPECT_TRUE(non_generic);
    ASSERT_EQ(report.defects.size(), 1u);
    EXPECT_EQ(report.defects.front().kind, DefectKind::Touching);
    EXPECT_NE(report.defects.front().message.find("meets the input non-generically"), std::string::npos)
        << report.defects.front().message;
    messages.push_back(report.defects.front().message);
  }
  EXPECT_EQ(messages[0], messages[1]);
}

// Exact contacts (DESIGN §5): the CSG baseline takes the same perturbed input as clipping (the
// complex's surface), so it accepts the same files and duplicates the same way. Two cubes sharing
// a face (coincident vertices), one resting on another's edge, one on another with overlapping
// coplanar faces, and a tetrahedron's corner on a cube's face.
TEST(CsgBaselineContacts, SameDuplicationAsClipping) {
  const Surface a = box_surface(Box3{{0, 0, 0}, {1, 1, 1}});
  Surface corner;  // a tetrahedron with its corner (1, 0.5, 0.5) on the face x = 1
  corner.vertices = {{1, 0.5, 0.5}, {1.5, 0, 0}, {1.5, 1, 0}, {1.5, 0.5, 1}};
  corner.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  if (signed_volume(corner) < 0)
    for (Triangle& t : corner.triangles) std::swap(t[1], t[2]);
  corner.source_face = {0, 1, 2, 3};
  const std::vector<std::pair<const char*, Surface>> cases = {
      {"shared_face", merge(a, box_surface(Box3{{1, 0, 0}, {2, 1, 1}}))},
      {"on_edge", merge(a, box_surface(Box3{{1, 1, 0.25}, {2, 2, 0.75}}))},
      {"coplanar_overlap", merge(a, box_surface(Box3{{0.5, 0.5, 1}, {1.5, 1.5, 2}}))},
      {"corner_on_face", merge(a, corner)},
  };
  for (const auto& [name, surface] : cases) {
    SCOPED_TRACE(name);
    BuildOptions strict;
    strict.strict = true;
    strict.exact_volumes = false;
    EXPECT_FALSE(build_complex(surface, strict).report.ok()) << "not a contact";
    expect_same_duplication(surface, name, 4);
  }
}

INSTANTIATE_TEST_SUITE_P(Generated, CsgBaseline,
                         testing::Values(Case{"sphere", {"6"}, 5}, Case{"two-spheres", {"6"}, 5},
                                         Case{"tube-overlap", {"6"}, 5}, Case{"comb", {"2"}, 5},
                                         Case{"mouth", {"16"}, 5}, Case{"random-blobs", {"2", "5", "4"}, 5},
                                         Case{"head", {"16"}, 5}, Case{"helix", {"1", "6"}, 5},
                                         Case{"tree", {"4"}, 5}, Case{"torus", {"12"}, 5},
                                         Case{"perturbed-torus", {"12", "1"}, 5}, Case{"two-tori", {"4"}, 4},
                                         Case{"sacht-torus", {"12"}, 4}, Case{"double-loop-torus", {"12"}, 4}),
                         [](const testing::TestParamInfo<Case>& info) {
                           std::string name = info.param.name;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

}  // namespace
}  // namespace imm::dim3
