// BM_BuildComplex2: the exact 2D cell complex (arrangement, genericity checks, regions, winding
// numbers, patches, arcs and junction order; paper §4.1–4.3) versus the number of input
// vertices.
//
// Input: test_support::wobbly_circle(seed, n), two counter-clockwise turns around a circle with radial
// noise, so the number of crossings (arcs) grows linearly with n. Built outside the timed loop.
// The timed region is one build_complex call including the destruction of its result. The
// first seed from kSeed on that gives a generic curve is used (reported as the `seed` counter).
#include <benchmark/benchmark.h>

#include <cstdint>

#include "bench/bench_inputs.h"

namespace imm::bench {
namespace {

constexpr std::uint64_t kSeed = 7;

void BM_BuildComplex2(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const BuiltInput input = first_valid(
      kSeed, 32,
      [n](std::uint64_t seed) {
        dim2::CurveSet curves;
        curves.curves.push_back(test_support::wobbly_circle(seed, n));
        return curves;
      },
      [](const dim2::Complex2&) { return true; });
  if (!input.complex) {
    state.SkipWithError("no generic wobbly circle in 32 seeds");
    return;
  }
  for (auto _ : state) {
    dim2::BuildResult built = dim2::build_complex(input.curves);
    benchmark::DoNotOptimize(built.complex.get());
  }
  const CellComplex<2>& complex = input.complex->complex;
  state.SetComplexityN(static_cast<benchmark::IterationCount>(n));
  state.counters["vertices"] = static_cast<double>(input.curves.vertex_count());
  state.counters["arcs"] = static_cast<double>(complex.arc_count());
  state.counters["patches"] = static_cast<double>(complex.patch_count());
  state.counters["cells"] = static_cast<double>(complex.cell_count());
  state.counters["regions"] = static_cast<double>(complex.region_count());
  state.counters["seed"] = static_cast<double>(input.seed);
}

BENCHMARK(BM_BuildComplex2)
    ->RangeMultiplier(2)
    ->Range(64, 128 << 10)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(0.2)
    ->Complexity();

}  // namespace
}  // namespace imm::bench
