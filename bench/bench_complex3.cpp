// The exact 3D cell complex (paper §4, d = 3) and the search on it.
//
//  BM_Complex3_Helix/loops        helix(loops, 20): triangles grow with loops, intersecting pairs
//                                 grow in proportion (Fig. 1; 100 loops = 200,280 triangles).
//  BM_Complex3_Tree/branches      tree(branches): 120 triangles per branch (Fig. 3).
//  BM_Complex3_Density/k          a fixed 2 x 20,000-triangle pair of spheres, the second moved so
//                                 that the number of intersecting triangle pairs grows with k:
//                                 the complex's cost in the number of intersecting pairs.
//  BM_Complex3_QuintupleTorus     ../shared/data/real/3d/quintupleTorus.obj (paper Table 1, Fig.
//                                 22), complex without exact volumes, and complex + search; with
//                                 exact volumes as a separate family. Skipped when ../shared is
//                                 absent.
//  BM_Complex3_QuintupleTorusThreads/threads:T   the same complex (volumes in doubles) on T
//                                 threads, wall time (the cut triangulations, the pair
//                                 classification and the candidate grid run on the threads)
//  BM_Complex3_CandidatePairs/threads:T   the candidate triangle pairs alone (the grid of
//                                 dim3/triangle_pairs.h) on the same surface, T threads
// Inputs are generated outside the timed loop; each iteration is one build_complex call
// (validation included) and, where named, the search. Counters: triangles, intersecting pairs,
// cells, patches, arcs, triple points.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "core/graph_search.h"
#include "dim3/complex3.h"
#include "dim3/generators3.h"
#include "dim3/triangle_pairs.h"

namespace imm::bench {
namespace {

void set_counters(benchmark::State& state, const dim3::Surface& s, const dim3::Complex& c3) {
  state.counters["triangles"] = static_cast<double>(s.triangle_count());
  state.counters["pairs"] = static_cast<double>(c3.intersecting_pairs);
  state.counters["cells"] = static_cast<double>(c3.complex.cell_count());
  state.counters["patches"] = static_cast<double>(c3.complex.patch_count());
  state.counters["arcs"] = static_cast<double>(c3.complex.arc_count());
  state.counters["triple_points"] = static_cast<double>(c3.triple_points);
}

void run_complex(benchmark::State& state, const dim3::Surface& s, bool search, bool exact_volumes = false,
                 benchmark::IterationCount complexity_n = 0, unsigned threads = 0) {
  dim3::BuildOptions options;
  options.exact_volumes = exact_volumes;
  options.threads = threads;
  std::shared_ptr<dim3::Complex> last;
  for (auto _ : state) {
    dim3::BuildResult r = dim3::build_complex(s, options);
    if (!r.complex) {
      state.SkipWithError("input is not valid or not immersible");
      return;
    }
    if (search) {
      SearchResult sr = find_immersions(r.complex->complex);
      benchmark::DoNotOptimize(sr.immersions.data());
    }
    last = std::move(r.complex);
  }
  set_counters(state, s, *last);
  state.SetComplexityN(complexity_n ? complexity_n : static_cast<benchmark::IterationCount>(s.triangle_count()));
}

void BM_Complex3_Helix(benchmark::State& state) {
  const dim3::Surface s = dim3::helix(static_cast<int>(state.range(0)), 20);
  run_complex(state, s, false);
}
BENCHMARK(BM_Complex3_Helix)->RangeMultiplier(4)->Range(1, 100)->Arg(100)->Unit(benchmark::kMillisecond)->Complexity();

void BM_Complex3_Tree(benchmark::State& state) {
  const dim3::SurfaceGenerateResult g = dim3::generate_surface("tree", {std::to_string(state.range(0))});
  if (!g.error.empty()) {
    state.SkipWithError(g.error.c_str());
    return;
  }
  run_complex(state, g.surface, false);
}
BENCHMARK(BM_Complex3_Tree)->RangeMultiplier(4)->Range(16, 2500)->Arg(2500)->Unit(benchmark::kMillisecond)->Complexity();

void BM_Complex3_Density(benchmark::State& state) {
  // Two spheres of 2 x 100 x 99 x 2 triangles; the second one's centre distance shrinks with k,
  // so the intersection loop (and the number of crossing pairs) grows while the triangle count
  // stays fixed.
  const dim3::Surface a = dim3::sphere(100);
  dim3::Surface b = dim3::sphere(100);
  const double shift = 2.0 - 0.18 * static_cast<double>(state.range(0));
  for (dim3::Point3& p : b.vertices) {
    p = {0.9731 * p[0] + shift, 0.9731 * p[1] + 0.0123, 0.9731 * p[2] - 0.0311};
  }
  run_complex(state, dim3::merge(a, b), false, false, state.range(0));
}
BENCHMARK(BM_Complex3_Density)->DenseRange(1, 9, 2)->Unit(benchmark::kMillisecond);

std::optional<dim3::Surface> quintuple_torus() {
  const std::string path = std::string(IMM_SHARED_DATA_DIR) + "/3d/quintupleTorus.obj";
  if (!std::filesystem::exists(path)) return std::nullopt;
  dim3::SurfaceReadResult r = dim3::read_surface(path);
  if (!r.report.ok()) return std::nullopt;
  return std::move(r.surface);
}

void BM_Complex3_QuintupleTorus(benchmark::State& state) {
  static const std::optional<dim3::Surface> s = quintuple_torus();
  if (!s) {
    state.SkipWithError("../shared/data/real/3d/quintupleTorus.obj absent");
    return;
  }
  run_complex(state, *s, state.range(0) == 1, state.range(1) == 1);
  state.SetLabel(std::string(state.range(0) ? "complex+search" : "complex") +
                 (state.range(1) ? ", exact volumes" : ", volumes in doubles"));
}
BENCHMARK(BM_Complex3_QuintupleTorus)->Args({0, 0})->Args({1, 0})->Args({0, 1})->Unit(benchmark::kMillisecond);

void BM_Complex3_QuintupleTorusThreads(benchmark::State& state) {
  static const std::optional<dim3::Surface> s = quintuple_torus();
  if (!s) {
    state.SkipWithError("../shared/data/real/3d/quintupleTorus.obj absent");
    return;
  }
  run_complex(state, *s, false, false, 0, static_cast<unsigned>(state.range(0)));
}
BENCHMARK(BM_Complex3_QuintupleTorusThreads)->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

void BM_Complex3_CandidatePairs(benchmark::State& state) {
  static const std::optional<dim3::Surface> s = quintuple_torus();
  if (!s) {
    state.SkipWithError("../shared/data/real/3d/quintupleTorus.obj absent");
    return;
  }
  std::size_t pairs = 0;
  for (auto _ : state) pairs = dim3::overlapping_triangle_pairs(*s, static_cast<unsigned>(state.range(0))).size();
  state.counters["pairs"] = static_cast<double>(pairs);
}
BENCHMARK(BM_Complex3_CandidatePairs)->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

/// Reading and validating the largest real surfaces (quintuple torus, armadillo): the parse
/// and the exact validity checks before any complex is built.
void BM_Surface3_ReadValidate(benchmark::State& state) {
  const char* name = state.range(0) == 0 ? "quintupleTorus.obj" : "armadillo.obj";
  const std::string path = std::string(IMM_SHARED_DATA_DIR) + "/3d/" + name;
  if (!std::filesystem::exists(path)) {
    state.SkipWithError((path + " absent").c_str());
    return;
  }
  std::size_t triangles = 0;
  for (auto _ : state) {
    const dim3::SurfaceReadResult r = dim3::read_surface(path);
    const ValidationReport report = dim3::validate_surface(r.surface);
    if (!r.report.ok() || !report.ok()) {
      state.SkipWithError("not valid");
      return;
    }
    triangles = r.surface.triangle_count();
  }
  state.SetLabel(std::string(name) + ", " + std::to_string(triangles) + " triangles");
}
BENCHMARK(BM_Surface3_ReadValidate)->DenseRange(0, 1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace imm::bench
