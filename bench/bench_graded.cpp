// Graded backgrounds (issue 17 item 3, dim3/graded_background.h) on the comb, whose teeth are
// 1/64 apart: small tets in the gaps, large ones inside and outside.
//
//  BM_GradedBackground_Comb/teeth/far/surface/gap
//      make_graded_background alone on comb(teeth). Counters: tets, vertices, gap_tets,
//      min_dihedral_deg, uniform_tets = the tets of the uniform grid (make_grid_background's
//      count, computed without building it) whose cubes are as small as the graded mesh's
//      smallest, and fewer_x = uniform_tets / tets.
//  BM_Mesh3_GradedComb/teeth/far/surface/gap
//      the whole mesh_immersion on that graded background (2 threads). Counters as above plus
//      output_tets, duplicated = background tets with more copies than the winding number (a tet
//      spanning a gap between two teeth: 0 means the background itself separates the teeth) and
//      components = face-connected components of the output (1: the comb stays one solid).
// The surface, complex and immersion are built outside the timed loop. CPU time is what to read
// on this shared machine (the mesher's virtual stage may use two threads).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "dim3/generators3.h"
#include "dim3/graded_background.h"
#include "dim3/mesh3.h"
#include "dim3/self_connecting.h"

namespace imm::bench {
namespace {

dim3::Box3 box_of(const dim3::Surface& s) {
  dim3::Box3 b{s.vertices.front(), s.vertices.front()};
  for (const dim3::Point3& p : s.vertices)
    for (int d = 0; d < 3; ++d) {
      b.lo[d] = std::min(b.lo[d], p[d]);
      b.hi[d] = std::max(b.hi[d], p[d]);
    }
  return b;
}

/// The tets make_grid_background(box, resolution) would build (the same cube count per axis:
/// one cube of margin, the shift of attempt 0 at most one more), without building them.
double uniform_tets(const dim3::Box3& box, double cube) {
  double n = 6;
  for (int d = 0; d < 3; ++d) n *= std::ceil((box.hi[d] - box.lo[d]) / cube + 2.0123457 + 0.00731 * d);
  return n;
}

/// The uniform grid resolution (cubes along the longest side) whose cube is no larger than `cube`.
double uniform_resolution(const dim3::Box3& box, double cube) {
  double longest = 0;
  for (int d = 0; d < 3; ++d) longest = std::max(longest, box.hi[d] - box.lo[d]);
  return std::ceil(longest / cube);
}

dim3::GradedOptions graded_options(const benchmark::State& state) {
  dim3::GradedOptions o;
  o.far_resolution = static_cast<int>(state.range(1));
  o.surface_resolution = static_cast<int>(state.range(2));
  o.gap_resolution = static_cast<int>(state.range(3));
  return o;
}

void set_size_counters(benchmark::State& state, const dim3::Box3& box, const dim3::GradedStats& g) {
  double longest = 0;
  for (int d = 0; d < 3; ++d) longest = std::max(longest, box.hi[d] - box.lo[d]);
  const double smallest = std::min(g.gap_size, g.surface_size);
  const double resolution = uniform_resolution(box, smallest);
  const double uniform = uniform_tets(box, longest / resolution);
  state.counters["tets"] = static_cast<double>(g.tets);
  state.counters["vertices"] = static_cast<double>(g.vertices);
  state.counters["gap_tets"] = static_cast<double>(g.gap_tets);
  state.counters["smallest_cube"] = smallest;
  state.counters["uniform_resolution"] = resolution;
  state.counters["uniform_tets"] = uniform;
  state.counters["fewer_x"] = uniform / static_cast<double>(g.tets);
  state.counters["min_dihedral_deg"] = g.min_dihedral_deg;
  state.counters["max_dihedral_deg"] = g.max_dihedral_deg;
}

void BM_GradedBackground_Comb(benchmark::State& state) {
  const dim3::Surface comb = dim3::comb(static_cast<int>(state.range(0)));
  const dim3::Box3 box = box_of(comb);
  const dim3::GradedOptions options = graded_options(state);
  dim3::GradedStats stats;
  for (auto _ : state) {
    dim3::GradedBackground g = dim3::make_graded_background(comb, box, options);
    if (!g.report.ok()) {
      state.SkipWithError(g.report.summary().c_str());
      return;
    }
    stats = g.stats;
    benchmark::DoNotOptimize(g.mesh.tets.data());
  }
  set_size_counters(state, box, stats);
  state.counters["closure_bisections"] = static_cast<double>(stats.closure_bisections);
}
BENCHMARK(BM_GradedBackground_Comb)
    ->Args({2, 8, 64, 512})
    ->Args({4, 8, 64, 512})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

void BM_Mesh3_GradedComb(benchmark::State& state) {
  const dim3::Surface comb = dim3::comb(static_cast<int>(state.range(0)));
  dim3::ImmerseOptions io;
  io.build.exact_volumes = false;
  const dim3::Immersed im = dim3::immerse_surface(comb, io);
  if (!im.build.complex || im.search.immersions.empty()) {
    state.SkipWithError("the comb has no immersion");
    return;
  }
  dim3::MeshOptions options;
  options.graded = graded_options(state);
  options.threads = 2;
  dim3::MeshResult result;
  for (auto _ : state) {
    result = dim3::mesh_immersion(*im.build.complex, im.search.immersions.front(), options, im.input_vertices,
                                  im.input_triangles);
    if (!result.report.ok()) {
      state.SkipWithError(result.report.summary().c_str());
      return;
    }
  }
  set_size_counters(state, box_of(comb), result.stats.graded);
  std::vector<std::size_t> copies(result.background.tets.size(), 0);
  for (int t : result.background_tet) ++copies[static_cast<std::size_t>(t)];
  std::size_t duplicated = 0;
  for (std::size_t n : copies) duplicated += n > 1 ? 1 : 0;  // winding number 1 everywhere
  state.counters["output_tets"] = static_cast<double>(result.stats.output_tets);
  state.counters["cut_tets"] = static_cast<double>(result.stats.cut_tets);
  state.counters["duplicated"] = static_cast<double>(duplicated);
  state.counters["components"] = static_cast<double>(dim3::face_connected_components(result.mesh));
  state.counters["background_s"] = result.stats.seconds_background;
  state.counters["virtual_s"] = result.stats.seconds_virtual;
  state.counters["assembly_s"] = result.stats.seconds_assembly;
}
BENCHMARK(BM_Mesh3_GradedComb)->Args({2, 8, 64, 512})->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
}  // namespace imm::bench
