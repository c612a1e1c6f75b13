// BM_Search2*: the immersion search (paper §6, Algorithm 1) on 2D cell complexes of growing size.
//
// The search is NP-complete (§6.1), so there is no complexity fit: each family sweeps the input
// size and the counters report the size of the complex (arcs, cells, patches, nodes = sum of
// winding numbers) and the work done (explored states = propagations to a fixpoint, branch points,
// dead ends, complete graphs dropped as isomorphic duplicates, independent groups). Read the time
// and `states` against `arcs`.
//
// The complex is built outside the timed loop; the timed region is one find_immersions call.
//  - BM_Search2Refute/turns/vertices: test_support::random_star_curve(seed, vertices, 10^6, backtrack 0,
//    turns) with turns = 2, 3. The angle is monotone, so the curve has turning number `turns` and
//    bounds no immersed surface (a connected immersed surface with one boundary curve has Euler
//    characteristic 1 - 2g = turning number <= 1): the search must prove NotImmersible.
//  - BM_Search2First/pitch/disks: bench::overlapping_disks(seed, disks, 24 vertices, pitch), star-
//    shaped disks on a grid of pitch `pitch`% of their radius, each crossing its neighbours several
//    times. Immersible by construction (the separate disks are an immersion); the smaller the
//    pitch, the deeper the overlaps (max_w) and the harder the search. First immersion.
//  - BM_Search2All/pitch/disks: the same inputs, every immersion (max_immersions = 0, `--all`).
//  - BM_Search2Generated/<shape>/k: the paper's curves from dim2/generators.h with a known number
//    of immersions, every immersion (max_immersions = 0): "doodle-chain K" (K two-lobed doodles
//    joined by thin bands, 6K crossings, 2^K immersions) and "doodle K" (K(K + 1) crossings,
//    Catalan(K) immersions). Budget kGeneratedBudget states.
// `probes` counts the trial propagations of branch options at branch points (they are included in
// `states`).
// Every family runs under a budget of kStateBudget states: `complete` = 0 with immersions = 0
// means the budget stopped the search before it found anything.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <string>
#include <utility>

#include "bench/bench_inputs.h"
#include "core/graph_search.h"
#include "dim2/generators.h"

namespace imm::bench {
namespace {

constexpr std::uint64_t kStarSeed = 11;
constexpr std::uint64_t kDiskSeed = 3;
constexpr std::size_t kDiskVertices = 24;
/// State budget of every search family, so that one iteration stays within seconds. A run that
/// reaches it reports complete = 0 (and immersible = 0 when it found nothing).
constexpr std::size_t kStateBudget = 20'000;
/// State budget of BM_Search2Generated: large enough that every size listed there finishes (the
/// number of immersions, hence of states, is exponential in K by construction).
constexpr std::size_t kGeneratedBudget = 2'000'000;

void report_counters(benchmark::State& state, const BuiltInput& input, const SearchResult& result) {
  const CellComplex<2>& complex = input.complex->complex;
  std::size_t nodes = 0;
  for (CellId c : ids<CellId>(complex.cell_count()))
    nodes += static_cast<std::size_t>(complex.winding_number(c));
  state.counters["vertices"] = static_cast<double>(input.curves.vertex_count());
  state.counters["arcs"] = static_cast<double>(complex.arc_count());
  state.counters["cells"] = static_cast<double>(complex.cell_count());
  state.counters["patches"] = static_cast<double>(complex.patch_count());
  state.counters["nodes"] = static_cast<double>(nodes);
  state.counters["max_w"] = static_cast<double>(complex.max_winding_number());
  state.counters["states"] = static_cast<double>(result.stats.states);
  state.counters["branches"] = static_cast<double>(result.stats.branches);
  state.counters["dead_ends"] = static_cast<double>(result.stats.dead_ends);
  state.counters["probes"] = static_cast<double>(result.stats.probes);
  state.counters["duplicates"] = static_cast<double>(result.stats.duplicates);
  state.counters["groups"] = static_cast<double>(result.stats.groups);
  state.counters["immersions"] = static_cast<double>(result.immersions.size());
  state.counters["complete"] = result.complete ? 1.0 : 0.0;
  state.counters["immersible"] = result.status == ImmersionStatus::Immersible ? 1.0 : 0.0;
  state.counters["seed"] = static_cast<double>(input.seed);
}

void run_search(benchmark::State& state, const BuiltInput& input, const SearchOptions& options) {
  if (!input.complex) {
    state.SkipWithError("no valid input in the seed range");
    return;
  }
  SearchResult result;
  for (auto _ : state) {
    result = find_immersions(input.complex->complex, options);
    benchmark::DoNotOptimize(result.immersions.data());
  }
  report_counters(state, input, result);
}

BuiltInput star_input(int turns, std::size_t vertices) {
  return first_valid(
      kStarSeed, 64,
      [&](std::uint64_t seed) {
        dim2::CurveSet curves;
        curves.curves.push_back(test_support::random_star_curve(seed, vertices, kDiskRadius, 0.0, turns));
        return curves;
      },
      [](const dim2::Complex2&) { return true; });
}

BuiltInput disks_input(int pitch, std::size_t disks) {
  return first_valid(
      kDiskSeed, 64,
      [&](std::uint64_t seed) { return overlapping_disks(seed, disks, kDiskVertices, pitch); },
      [](const dim2::Complex2&) { return true; });
}

void BM_Search2Refute(benchmark::State& state) {
  const BuiltInput input =
      star_input(static_cast<int>(state.range(0)), static_cast<std::size_t>(state.range(1)));
  SearchOptions options;
  options.max_states = kStateBudget;
  run_search(state, input, options);
}

void BM_Search2First(benchmark::State& state) {
  const BuiltInput input =
      disks_input(static_cast<int>(state.range(0)), static_cast<std::size_t>(state.range(1)));
  SearchOptions options;
  options.max_immersions = 1;
  options.max_states = kStateBudget;
  run_search(state, input, options);
}

void BM_Search2All(benchmark::State& state) {
  const BuiltInput input =
      disks_input(static_cast<int>(state.range(0)), static_cast<std::size_t>(state.range(1)));
  SearchOptions options;
  options.max_immersions = 0;
  options.max_states = kStateBudget;
  run_search(state, input, options);
}

/// `name` with the single parameter K = range(0), built once (no seed: the shapes are fixed).
BuiltInput generated_input(const std::string& name, long k) {
  return first_valid(
      0, 1,
      [&](std::uint64_t) {
        dim2::GenerateResult generated = dim2::generate(name, {std::to_string(k)});
        return generated.ok() ? std::move(generated.curves) : dim2::CurveSet{};
      },
      [](const dim2::Complex2&) { return true; });
}

void BM_Search2Generated(benchmark::State& state, const char* name) {
  const BuiltInput input = generated_input(name, static_cast<long>(state.range(0)));
  SearchOptions options;
  options.max_immersions = 0;
  options.max_states = kGeneratedBudget;
  run_search(state, input, options);
}

/// Sparse overlaps (pitch 110%) up to 256 disks; denser ones (90%, 70%) stop earlier because the
/// search reaches its state budget there.
void disk_sweep(benchmark::internal::Benchmark* family) {
  family->ArgNames({"pitch", "disks"});
  for (const auto& [pitch, max_disks] :
       {std::pair{110, 256}, std::pair{90, 64}, std::pair{70, 32}}) {
    for (int disks = 2; disks <= max_disks; disks *= 2) family->Args({pitch, disks});
  }
}

BENCHMARK(BM_Search2Refute)
    ->ArgNames({"turns", "vertices"})
    ->ArgsProduct({{2, 3}, benchmark::CreateRange(16, 4096, 4)})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(0.1);

BENCHMARK(BM_Search2First)->Apply(disk_sweep)->Unit(benchmark::kMillisecond)->MinTime(0.1);
BENCHMARK(BM_Search2All)->Apply(disk_sweep)->Unit(benchmark::kMillisecond)->MinTime(0.1);

/// doodle-chain K up to the largest K whose search stays under ~2 s per iteration on the machine
/// of BENCHMARKS.md; doodle K = 2..6 (Catalan(K) = 2 .. 132 immersions).
constexpr int kMaxChain = 13;
BENCHMARK_CAPTURE(BM_Search2Generated, doodle_chain, "doodle-chain")
    ->ArgName("k")
    ->DenseRange(1, kMaxChain)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(0.1);
BENCHMARK_CAPTURE(BM_Search2Generated, doodle, "doodle")
    ->ArgName("k")
    ->DenseRange(2, 6)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(0.1);

}  // namespace
}  // namespace imm::bench
