// The 3D inputs at the paper's sizes: how long generating and validating them takes (these were
// timing assertions in tests/dim3/generators3_test.cpp and tests/dim3/surface_test.cpp; the
// tests now check only what is generated, the times are measured here).
//
//  BM_Generate3_Helix/loops       helix(loops, 20): 5 * 20^2 * loops + 280 triangles (Fig. 1;
//                                 100 loops = 200,280, the paper's 200,036).
//  BM_Generate3_Tree/branches     tree(branches): 120 triangles per branch (Fig. 3; 2,500 =
//                                 300,000, the paper's 328k).
//  BM_ValidateSurface_Torus/n     validate_surface on torus(n): 2 n (n / 2) triangles (548 =
//                                 300,304); the checks that need no intersection test, expected
//                                 linear-ish in the triangles.
// Counters: triangles.
#include <benchmark/benchmark.h>

#include "dim3/generators3.h"
#include "dim3/surface.h"

namespace imm::bench {
namespace {

void BM_Generate3_Helix(benchmark::State& state) {
  std::size_t triangles = 0;
  for (auto _ : state) {
    const dim3::Surface s = dim3::helix(static_cast<int>(state.range(0)), 20);
    triangles = s.triangle_count();
    benchmark::DoNotOptimize(s.vertices.data());
  }
  state.counters["triangles"] = static_cast<double>(triangles);
}
BENCHMARK(BM_Generate3_Helix)->Arg(10)->Arg(100)->Unit(benchmark::kMillisecond);

void BM_Generate3_Tree(benchmark::State& state) {
  std::size_t triangles = 0;
  for (auto _ : state) {
    const dim3::Surface s = dim3::tree(static_cast<int>(state.range(0)));
    triangles = s.triangle_count();
    benchmark::DoNotOptimize(s.vertices.data());
  }
  state.counters["triangles"] = static_cast<double>(triangles);
}
BENCHMARK(BM_Generate3_Tree)->Arg(250)->Arg(2500)->Unit(benchmark::kMillisecond);

void BM_ValidateSurface_Torus(benchmark::State& state) {
  const dim3::Surface s = dim3::torus(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const ValidationReport report = dim3::validate_surface(s);
    if (!report.ok()) {
      state.SkipWithError("the torus does not validate");
      return;
    }
    benchmark::DoNotOptimize(report.defects.data());
  }
  state.counters["triangles"] = static_cast<double>(s.triangle_count());
}
BENCHMARK(BM_ValidateSurface_Torus)->Arg(100)->Arg(548)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace imm::bench
