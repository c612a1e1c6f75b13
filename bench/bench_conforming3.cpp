// Conforming 3D meshes (issue 18, dim3/conforming_mesh3.h): one mesh_conforming per iteration
// (exact checks of the rounded cut mesh, TetGen -pY in a child process, labels, copies).
//
//  BM_Conforming3_QuintupleTorus   ../shared/data/real/3d/quintupleTorus.obj (Fig. 22), edge length
//                                  = longest box side / 16 (the CLI default). Skipped when
//                                  ../shared is absent.
//  BM_Conforming3_Helix/loops      helix(loops, 20): 2,003 triangles per loop (loops = 100 is the
//                                  issue's 200k-triangle helix), edge length = longest side / 16.
//                                  SetComplexityN = input triangles.
// Inputs (surface, complex with volumes in doubles, first immersion) are built outside the timed
// loop. Real (wall) time: TetGen runs in a child process, whose CPU time the benchmark's CPU
// clock does not see.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <filesystem>
#include <optional>
#include <string>

#include "dim3/conforming_mesh3.h"
#include "dim3/generators3.h"
#include "dim3/self_connecting.h"

namespace imm::bench {
namespace {

std::optional<dim3::Immersed> prepare_conforming(const dim3::Surface& surface, std::string& error) {
  dim3::ImmerseOptions options;
  options.build.exact_volumes = false;
  dim3::Immersed im = dim3::immerse_surface(surface, options);
  if (!im.build.complex || !im.build.report.ok() || im.search.immersions.empty()) {
    error = "input has no immersion";
    return std::nullopt;
  }
  return im;
}

void run_conforming(benchmark::State& state, const dim3::Immersed& im) {
  const dim3::Box3 box = dim3::bounding_box(im.surface);
  double longest = 0.0;
  for (int d = 0; d < 3; ++d) longest = std::max(longest, box.hi[d] - box.lo[d]);
  dim3::ConformingOptions options;
  options.edge_length = longest / 16;
  dim3::ConformingStats stats;
  for (auto _ : state) {
    dim3::ConformingResult r = dim3::mesh_conforming(*im.build.complex, im.search.immersions.front(), options,
                                                       im.input_vertices, im.input_triangles);
    if (!r.report.ok()) {
      state.SkipWithError(("meshing failed: " + r.report.summary()).c_str());
      return;
    }
    benchmark::DoNotOptimize(r.mesh.tets.data());
    stats = std::move(r.stats);
  }
  state.counters["triangles"] = static_cast<double>(im.input_triangles);
  state.counters["cut_triangles"] = static_cast<double>(stats.plc_triangles);
  state.counters["tetgen_tets"] = static_cast<double>(stats.tetgen_tets);
  state.counters["output_tets"] = static_cast<double>(stats.output_tets);
  state.counters["slivers_5deg"] = static_cast<double>(stats.slivers);
  state.counters["slivers_on_needle"] = static_cast<double>(stats.slivers_on_needle);
  state.counters["min_cell_wedge_deg"] = stats.min_cell_wedge;
  state.counters["s_checks"] = stats.seconds_checks;
  state.counters["s_tetgen"] = stats.seconds_tetgen;
  state.counters["s_assembly"] = stats.seconds_assembly;
}

void BM_Conforming3_QuintupleTorus(benchmark::State& state) {
  const std::string obj = std::string(IMM_SHARED_DATA_DIR) + "/3d/quintupleTorus.obj";
  if (!std::filesystem::exists(obj)) {
    state.SkipWithError("../shared/data/real/3d/quintupleTorus.obj absent");
    return;
  }
  static std::string error;
  static const std::optional<dim3::Immersed> im = [&]() -> std::optional<dim3::Immersed> {
    dim3::SurfaceReadResult read = dim3::read_surface(obj);
    if (!read.report.ok()) {
      error = read.report.summary();
      return std::nullopt;
    }
    return prepare_conforming(read.surface, error);
  }();
  if (!im) {
    state.SkipWithError(error.c_str());
    return;
  }
  run_conforming(state, *im);
}
BENCHMARK(BM_Conforming3_QuintupleTorus)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Conforming3_Helix(benchmark::State& state) {
  const dim3::SurfaceGenerateResult g =
      dim3::generate_surface("helix", {std::to_string(state.range(0)), "20"});
  std::string error = g.error;
  const std::optional<dim3::Immersed> im = g.ok() ? prepare_conforming(g.surface, error) : std::nullopt;
  if (!im) {
    state.SkipWithError(error.c_str());
    return;
  }
  run_conforming(state, *im);
  state.SetComplexityN(static_cast<std::int64_t>(im->input_triangles));
}
BENCHMARK(BM_Conforming3_Helix)->Arg(4)->Arg(20)->Arg(100)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace imm::bench
