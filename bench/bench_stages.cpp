// One benchmark family per stage of the pipeline, for both dimensions, each stage timed alone
// on inputs whose earlier stages ran outside the timed loop (issue: "one family per stage:
// complex, search, virtual elements, assembly, for D = 2 and 3"):
//
//  BM_Stage_Complex/dim        the exact cell complex (paper §4): build_complex / build_complex.
//  BM_Stage_Search/dim         the first immersion (paper §5-6): find_immersions on that complex.
//  BM_Stage_Virtual/dim/method the local regions of every background element (paper §7.1):
//                              exact clipping (method 0, all threads) or the CSG baseline
//                              (method 1, all threads), on a background built outside the loop.
//  BM_Stage_Assembly/dim       atoms, duplicate and connect, embedding (paper §7.1.2, core/unglue.h)
//                              on local regions computed outside the loop.
//
// Inputs: 2D the doodle chain doodle-chain 4 (4 two-lobed doodles, 16 immersions) on a
// resolution-128 background; 3D two-tori 16 (two overlapping tori, 1,024 triangles, the input
// class of the paper's CSG comparison) on a 12-cube grid, small enough for the CSG baseline to
// take seconds, not minutes. Counters report the exact work where it is cheap to count:
// exact edge-triangle points and triple points (complex), clipped polygons, cut elements, side
// tests, tets redone exactly after the interval filter, exact point locations (virtual).
// Every family uses real (wall) time, since several stages run on threads.
#include <benchmark/benchmark.h>

#include <memory>
#include <optional>
#include <string>

#include "core/graph_search.h"
#include "dim2/complex2.h"
#include "dim2/generators.h"
#include "dim2/mesh2.h"
#include "dim2/mesh2_detail.h"
#include "dim3/complex3.h"
#include "dim3/generators3.h"
#include "dim3/mesh3_detail.h"
#include "dim3/self_connecting.h"
#include "dim3/tet_mesh.h"

namespace imm::bench {
namespace {

constexpr int kResolution2 = 128;
constexpr int kResolution3 = 12;

// ---- inputs, built once ---------------------------------------------------------------------

struct Input2 {
  dim2::CurveSet curves;
  std::shared_ptr<dim2::Complex2> complex;
  Immersion immersion;
  dim2::detail::Background background;
  dim2::detail::LocalRegions local;
};

const Input2& input2() {
  static const Input2 input = [] {
    Input2 in;
    const dim2::GenerateResult g = dim2::generate("doodle-chain", {"4"});
    IMM_ASSERT(g.ok(), g.error);
    in.curves = g.curves;
    dim2::BuildResult built = dim2::build_complex(in.curves);
    IMM_ASSERT(built.report.ok() && built.complex, built.report.summary());
    in.complex = built.complex;
    const SearchResult search = find_immersions(in.complex->complex);
    IMM_ASSERT(!search.immersions.empty(), "doodle-chain 4 has an immersion");
    in.immersion = search.immersions.front();
    dim2::MeshOptions options;
    options.resolution = kResolution2;
    ValidationReport report;
    in.background = dim2::detail::make_background(*in.complex, options, report);
    in.local = dim2::detail::compute_local_regions(*in.complex, in.background, false, report);
    IMM_ASSERT(report.ok(), report.summary());
    return in;
  }();
  return input;
}

struct Input3 {
  dim3::Surface surface;
  dim3::Immersed immersed;
  dim3::TetMesh background;
  dim3::detail::LocalRegions local;
  [[nodiscard]] const dim3::Complex& complex() const { return *immersed.build.complex; }
};

const Input3& input3() {
  static const Input3 input = [] {
    Input3 in;
    const dim3::SurfaceGenerateResult g = dim3::generate_surface("two-tori", {"16"});
    IMM_ASSERT(g.ok(), g.error);
    in.surface = g.surface;
    dim3::ImmerseOptions options;
    options.build.exact_volumes = false;  // the search and the meshing do not read them
    in.immersed = dim3::immerse_surface(in.surface, options);
    IMM_ASSERT(in.immersed.build.report.ok() && !in.immersed.search.immersions.empty(), "two-tori 16 is immersible");
    in.background = dim3::make_grid_background(dim3::bounding_box(in.complex().surface), kResolution3, 0);
    ValidationReport report;
    bool non_generic = false;
    in.local = dim3::detail::compute_local_regions(in.complex(), in.background, {0, 0, 0}, false, 0, true, report,
                                                    non_generic);
    IMM_ASSERT(report.ok() && !non_generic, report.summary());
    return in;
  }();
  return input;
}

// ---- stages ---------------------------------------------------------------------------------

void BM_Stage_Complex(benchmark::State& state) {
  if (state.range(0) == 2) {
    const Input2& in = input2();
    for (auto _ : state) {
      dim2::BuildResult built = dim2::build_complex(in.curves);
      benchmark::DoNotOptimize(built.complex.get());
    }
    state.counters["arcs"] = static_cast<double>(in.complex->complex.arc_count());
    state.counters["cells"] = static_cast<double>(in.complex->complex.cell_count());
  } else {
    const Input3& in = input3();
    dim3::BuildOptions options;
    options.exact_volumes = false;
    for (auto _ : state) {
      dim3::BuildResult built = dim3::build_complex(in.surface, options);
      benchmark::DoNotOptimize(built.complex.get());
    }
    const dim3::Complex& c = in.complex();
    state.counters["triangles"] = static_cast<double>(in.surface.triangle_count());
    state.counters["crossing_pairs"] = static_cast<double>(c.intersecting_pairs);
    state.counters["exact_points"] = static_cast<double>(c.intersection_points);
    state.counters["triple_points"] = static_cast<double>(c.triple_points);
    state.counters["cells"] = static_cast<double>(c.complex.cell_count());
  }
}
BENCHMARK(BM_Stage_Complex)->ArgName("dim")->Arg(2)->Arg(3)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Stage_Search(benchmark::State& state) {
  const CellComplex<2>* complex2 = state.range(0) == 2 ? &input2().complex->complex : nullptr;
  const CellComplex<3>* complex3 = state.range(0) == 3 ? &input3().complex().complex : nullptr;
  SearchResult last;
  for (auto _ : state) {
    last = complex2 ? find_immersions(*complex2) : find_immersions(*complex3);
    benchmark::DoNotOptimize(last.immersions.data());
  }
  state.counters["states"] = static_cast<double>(last.stats.states);
  state.counters["branches"] = static_cast<double>(last.stats.branches);
}
BENCHMARK(BM_Stage_Search)->ArgName("dim")->Arg(2)->Arg(3)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Stage_Virtual(benchmark::State& state) {
  const bool csg = state.range(1) == 1;
  state.SetLabel(csg ? "csg" : "clip");
  if (state.range(0) == 2) {
    const Input2& in = input2();
    dim2::detail::LocalRegions local;
    for (auto _ : state) {
      ValidationReport report;
      local = csg ? dim2::detail::compute_local_regions_csg(*in.complex, in.background, false, report)
                  : dim2::detail::compute_local_regions(*in.complex, in.background, false, report);
      if (!report.ok()) {
        state.SkipWithError(report.summary().c_str());
        return;
      }
    }
    state.counters["elements"] = static_cast<double>(in.background.triangles.size());
    state.counters["cut_elements"] = static_cast<double>(local.cut_elements);
    state.counters["point_locations"] = static_cast<double>(local.point_locations);
  } else {
    const Input3& in = input3();
    dim3::detail::LocalRegions local;
    for (auto _ : state) {
      ValidationReport report;
      bool non_generic = false;
      local = csg ? dim3::detail::compute_local_regions_csg(in.complex(), in.background, false, 0, {}, report,
                                                             non_generic)
                  : dim3::detail::compute_local_regions(in.complex(), in.background, {0, 0, 0}, false, 0, true,
                                                         report, non_generic);
      if (!report.ok()) {
        state.SkipWithError(report.summary().c_str());
        return;
      }
    }
    state.counters["elements"] = static_cast<double>(in.background.tets.size());
    state.counters["cut_elements"] = static_cast<double>(local.cut_elements);
    state.counters["polygons"] = static_cast<double>(local.polygons);
    state.counters["side_tests"] = static_cast<double>(local.side_tests);
    state.counters["exact_tets"] = static_cast<double>(local.exact_tets);
    state.counters["point_locations"] = static_cast<double>(local.point_locations);
  }
}
BENCHMARK(BM_Stage_Virtual)
    ->ArgNames({"dim", "method"})
    ->ArgsProduct({{2, 3}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_Stage_Assembly(benchmark::State& state) {
  if (state.range(0) == 2) {
    const Input2& in = input2();
    std::size_t triangles = 0;
    for (auto _ : state) {
      dim2::MeshResult result;
      dim2::detail::assemble(*in.complex, in.immersion, in.background, in.local, false, result);
      triangles = result.mesh.triangles.size();
      benchmark::DoNotOptimize(result.mesh.triangles.data());
    }
    state.counters["output_elements"] = static_cast<double>(triangles);
  } else {
    const Input3& in = input3();
    std::size_t tets = 0;
    for (auto _ : state) {
      dim3::MeshResult result;
      dim3::detail::assemble(in.complex(), in.immersed.search.immersions.front(), in.background, in.local,
                              in.immersed.input_vertices, in.immersed.input_triangles, false, result);
      tets = result.mesh.tets.size();
      benchmark::DoNotOptimize(result.mesh.tets.data());
    }
    state.counters["output_elements"] = static_cast<double>(tets);
  }
}
BENCHMARK(BM_Stage_Assembly)->ArgName("dim")->Arg(2)->Arg(3)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace imm::bench
