// BM_SearchPile*: the first immersion of piles of mutually overlapping parts (issue 19), per size
// and per seed, so that BENCHMARKS.md can report the worst seed and not only the median.
//  - BM_SearchPile2/k/seed: dim2::circles_pile(k, seed, 32): k circles whose centres lie in a
//    square of side 0.8 radius (every two overlap; winding numbers up to about k).
//  - BM_SearchPile3/k/seed: dim3::spheres_pile(k, seed, 8): k spheres of radius 0.5 whose centres
//    lie in a cube of side 0.6.
//  - BM_SearchPile2Classic/k/seed and BM_SearchPile3Classic/k/seed: the same inputs with the
//    search order before issue 19 (SearchOptions::sheets_first and continue_sheets off), for
//    the sizes where it still finishes within its time budget.
//  - BM_SearchPile2Scan/k/seed and BM_SearchPile3Scan/k/seed: the default order with the rescan
//    of every open variable per state instead of the incremental choice
//    (SearchOptions::incremental_choice off): the same states, only the cost of choosing differs.
// The complex is built outside the timed loop (one iteration: the 3D builds take seconds); the
// timed region is one find_immersions call with the default first-immersion options and a
// time limit of kTimeLimit seconds (kClassicTimeLimit for the old order). Counters: the size of the complex (cells, patches, arcs,
// nodes = sum of winding numbers, max_w) and the work (states, branches, dead_ends, probes);
// found = 0 means the time limit stopped the search.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <map>
#include <memory>
#include <tuple>

#include "core/graph_search.h"
#include "dim2/complex2.h"
#include "dim2/generators.h"
#include "dim3/complex3.h"
#include "dim3/generators3.h"

namespace imm::bench {
namespace {

constexpr double kTimeLimit = 60.0;
/// The old order loses itself on some seeds: a shorter limit keeps the comparison affordable.
constexpr double kClassicTimeLimit = 20.0;

template <int D>
void report(benchmark::State& state, const CellComplex<D>& complex, const SearchResult& result) {
  std::size_t nodes = 0;
  for (CellId c : ids<CellId>(complex.cell_count()))
    nodes += static_cast<std::size_t>(complex.winding_number(c));
  state.counters["cells"] = static_cast<double>(complex.cell_count());
  state.counters["patches"] = static_cast<double>(complex.patch_count());
  state.counters["arcs"] = static_cast<double>(complex.arc_count());
  state.counters["nodes"] = static_cast<double>(nodes);
  state.counters["max_w"] = static_cast<double>(complex.max_winding_number());
  state.counters["states"] = static_cast<double>(result.stats.states);
  state.counters["branches"] = static_cast<double>(result.stats.branches);
  state.counters["dead_ends"] = static_cast<double>(result.stats.dead_ends);
  state.counters["probes"] = static_cast<double>(result.stats.probes);
  state.counters["found"] = result.status == ImmersionStatus::Immersible ? 1.0 : 0.0;
  state.counters["choice_rebuilds"] = static_cast<double>(result.stats.choice_rebuilds);
  state.counters["search_s"] = result.stats.seconds;
}

enum class Variant { Default, Classic, Scan };

template <int D>
void run(benchmark::State& state, const CellComplex<D>& complex, Variant variant) {
  SearchOptions options;
  const bool classic = variant == Variant::Classic;
  options.time_limit_seconds = classic ? kClassicTimeLimit : kTimeLimit;
  if (classic) {
    options.sheets_first = false;
    options.continue_sheets = false;
  }
  options.incremental_choice = variant != Variant::Scan;
  SearchResult result;
  for (auto _ : state) {
    result = find_immersions(complex, options);
    benchmark::DoNotOptimize(result.immersions.data());
  }
  report(state, complex, result);
  if (result.status != ImmersionStatus::Immersible) state.SkipWithError("no immersion within the time limit");
}

void pile2(benchmark::State& state, Variant variant) {
  const int k = static_cast<int>(state.range(0));
  const auto seed = static_cast<std::uint64_t>(state.range(1));
  const dim2::BuildResult built = dim2::build_complex(dim2::circles_pile(k, seed, 32));
  if (!built.complex || !built.report.ok() || built.inversion) {
    state.SkipWithError("the pile did not build");
    return;
  }
  run(state, built.complex->complex, variant);
}

void pile3(benchmark::State& state, Variant variant) {
  const int k = static_cast<int>(state.range(0));
  const auto seed = static_cast<std::uint64_t>(state.range(1));
  dim3::BuildOptions options;
  options.exact_volumes = false;  // the search does not read volumes
  const dim3::BuildResult built = dim3::build_complex(dim3::spheres_pile(k, seed, 8), options);
  if (!built.complex || !built.report.ok() || built.inversion) {
    state.SkipWithError("the pile did not build");
    return;
  }
  run(state, built.complex->complex, variant);
}

void BM_SearchPile2(benchmark::State& state) { pile2(state, Variant::Default); }
void BM_SearchPile2Classic(benchmark::State& state) { pile2(state, Variant::Classic); }
void BM_SearchPile2Scan(benchmark::State& state) { pile2(state, Variant::Scan); }
void BM_SearchPile3(benchmark::State& state) { pile3(state, Variant::Default); }
void BM_SearchPile3Classic(benchmark::State& state) { pile3(state, Variant::Classic); }
void BM_SearchPile3Scan(benchmark::State& state) { pile3(state, Variant::Scan); }

BENCHMARK(BM_SearchPile2)
    ->ArgNames({"k", "seed"})
    ->ArgsProduct({{16, 24, 32, 48, 64, 96, 128}, {1, 2, 3, 4, 5}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SearchPile2Classic)
    ->ArgNames({"k", "seed"})
    ->ArgsProduct({{16, 24}, {1, 2, 3, 4, 5}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SearchPile2Scan)
    ->ArgNames({"k", "seed"})
    ->ArgsProduct({{32, 64, 128}, {1, 2, 3, 4, 5}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SearchPile3)
    ->ArgNames({"k", "seed"})
    ->ArgsProduct({{8, 12, 16, 24, 32, 48, 64}, {1, 2, 3, 4, 5}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SearchPile3Classic)
    ->ArgNames({"k", "seed"})
    ->ArgsProduct({{8, 12}, {1, 2, 3, 4, 5}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

BENCHMARK(BM_SearchPile3Scan)
    ->ArgNames({"k", "seed"})
    ->ArgsProduct({{12, 24, 32}, {1, 2, 3, 4, 5}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace imm::bench
