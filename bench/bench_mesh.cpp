// BM_Mesh2: meshing one immersion (paper §7 with d = 2) versus the size of the background mesh.
//
// A fixed curve with a known immersion is meshed at resolutions 16 .. 724 (background edges
// across the bounding-box diagonal), which sweeps the background from ~600 to ~9 * 10^5
// triangles. SetComplexityN = number of background triangles.
// The complex and the immersion are computed outside the timed loop; the timed region is one
// mesh_immersion call: background Delaunay mesh, virtual triangles (exact local regions of the
// cut triangles), element copies, fusion across graph edges, union-find vertex merging.
//
// Input: bench::overlapping_disks(seed, 4 disks, 32 vertices each, pitch 90%): four overlapping
// star-shaped disks (winding numbers up to 4), immersible by construction; the first seed from 5
// on that builds a valid complex, and its first immersion (seed reported as a counter).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>

#include "bench/bench_inputs.h"
#include "core/graph_search.h"
#include "core/unglue.h"
#include "dim2/mesh2.h"

namespace imm::bench {
namespace {

constexpr std::uint64_t kSeed = 5;

struct MeshInput {
  BuiltInput built;
  Immersion immersion;
};

/// Built once and shared by every resolution (the benchmark function runs once per size).
const std::optional<MeshInput>& mesh_input() {
  static const std::optional<MeshInput> input = []() -> std::optional<MeshInput> {
    std::optional<Immersion> immersion;
    BuiltInput built = first_valid(
        kSeed, 64,
        [](std::uint64_t seed) { return overlapping_disks(seed, 4, 32, /*pitch_percent=*/90); },
        [&](const dim2::Complex2& complex) {
          SearchResult found = find_immersions(complex.complex);
          if (found.status != ImmersionStatus::Immersible) return false;
          immersion = std::move(found.immersions.front());
          return true;
        });
    if (!built.complex) return std::nullopt;
    return MeshInput{std::move(built), std::move(*immersion)};
  }();
  return input;
}

void BM_Mesh2(benchmark::State& state) {
  const std::optional<MeshInput>& input = mesh_input();
  if (!input) {
    state.SkipWithError("no valid disk set in 64 seeds");
    return;
  }
  dim2::MeshOptions options;
  options.resolution = static_cast<int>(state.range(0));
  dim2::MeshStats stats;
  double background = 0.0, virtual_triangles = 0.0, assembly = 0.0;
  for (auto _ : state) {
    dim2::MeshResult result =
        dim2::mesh_immersion(*input->built.complex, input->immersion, options);
    if (!result.report.ok()) {
      state.SkipWithError("mesh_immersion reported a defect");
      return;
    }
    stats = result.stats;
    background += stats.seconds_background;
    virtual_triangles += stats.seconds_virtual;
    assembly += stats.seconds_assembly;
    benchmark::DoNotOptimize(result.mesh.triangles.data());
  }
  state.SetComplexityN(static_cast<benchmark::IterationCount>(stats.background_triangles));
  state.counters["background_triangles"] = static_cast<double>(stats.background_triangles);
  state.counters["cut_triangles"] = static_cast<double>(stats.cut_triangles);
  state.counters["output_triangles"] = static_cast<double>(stats.output_triangles);
  state.counters["output_vertices"] = static_cast<double>(stats.output_vertices);
  // Per-phase wall time in seconds, averaged over iterations (MeshStats' own timers).
  state.counters["s_background"] =
      benchmark::Counter(background, benchmark::Counter::kAvgIterations);
  state.counters["s_virtual"] =
      benchmark::Counter(virtual_triangles, benchmark::Counter::kAvgIterations);
  state.counters["s_assembly"] = benchmark::Counter(assembly, benchmark::Counter::kAvgIterations);
  state.counters["arcs"] = static_cast<double>(input->built.complex->complex.arc_count());
  state.counters["seed"] = static_cast<double>(input->built.seed);
}

/// Resolutions 16 * 2^(k/2), k = 0..11 (16 .. 724): ~600 to ~9 * 10^5 background triangles.
void resolution_sweep(benchmark::internal::Benchmark* family) {
  family->ArgName("resolution");
  for (int k = 0; k <= 11; ++k)
    family->Arg(static_cast<int>(std::lround(16.0 * std::exp2(0.5 * k))));
}

BENCHMARK(BM_Mesh2)
    ->Apply(resolution_sweep)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(0.2)
    ->Complexity();

/// BM_Mesh2Method/method/resolution: the paper's exact clipping (0) against the CSG baseline (1,
/// exact Polygon_set_2 booleans of every cut triangle with the regions near it) on the same input
/// and background; both give the same duplication (tests/dim2/csg_test.cpp).
void BM_Mesh2Method(benchmark::State& state) {
  const std::optional<MeshInput>& input = mesh_input();
  if (!input) {
    state.SkipWithError("no valid disk set in 64 seeds");
    return;
  }
  dim2::MeshOptions options;
  options.method = state.range(0) == 1 ? MeshMethod::Csg : MeshMethod::Clip;
  options.resolution = static_cast<int>(state.range(1));
  dim2::MeshStats stats;
  double virtual_triangles = 0.0;
  for (auto _ : state) {
    dim2::MeshResult result = dim2::mesh_immersion(*input->built.complex, input->immersion, options);
    if (!result.report.ok()) {
      state.SkipWithError("mesh_immersion reported a defect");
      return;
    }
    stats = result.stats;
    virtual_triangles += stats.seconds_virtual;
    benchmark::DoNotOptimize(result.mesh.triangles.data());
  }
  state.SetLabel(state.range(0) == 1 ? "csg" : "clip");
  state.counters["background_triangles"] = static_cast<double>(stats.background_triangles);
  state.counters["cut_triangles"] = static_cast<double>(stats.cut_triangles);
  state.counters["output_triangles"] = static_cast<double>(stats.output_triangles);
  state.counters["s_virtual"] = benchmark::Counter(virtual_triangles, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_Mesh2Method)
    ->ArgNames({"method", "resolution"})
    ->ArgsProduct({{0, 1}, {32, 128, 512}})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(0.2);

}  // namespace
}  // namespace imm::bench
