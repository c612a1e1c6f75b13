// Deformation and simulation on simplicial meshes (deform/): one family per stage, D = 2 and 3,
// on Kuhn grids of the unit box (tests/deform/grid.h) built outside the timed loop. The 3D sizes
// reach the paper's quintuple-torus mesh (about 85k tets at 24 cells per side: 82,944 tets).
// Counters: the system size (free unknowns) and the elements.
//
//  BM_Deform_FemQuintuple/scenario/pcg  consecutive implicit Euler steps of the quintuple torus's
//                                 unglued mesh (../shared/data/real/3d/quintupleTorus.obj meshed on
//                                 tet/quintupleTorus.veg, 84,938 tets; skipped when ../shared is
//                                 absent), one FemSolver for the whole run. scenario 0: the
//                                 vertices with x <= -2.4 fixed, those with x >= 2.4 jump by
//                                 (0, 0, 0.3) in the first step and stay there (BENCHMARKS.md's
//                                 handle-jump step, then the free vibration); scenario 1: nothing
//                                 fixed, gravity along -y, the ground 0.05 below the lowest vertex
//                                 (the Fig. 22 drop: free fall, then contact). pcg = FemOptions::
//                                 max_pcg_iterations (0: a factorization every Newton iteration).
//                                 Counters: wall seconds (s_) and process CPU seconds, all
//                                 threads (cpu_), of the setup (fem_prepare: the Newton matrix's
//                                 pattern and symbolic analysis, before the first step and not in
//                                 it), of the first step and median and max of the following
//                                 steps; the stages' CPU summed over all steps (s_analysis: 0, the
//                                 setup did it); Newton iterations, factorizations, PCG
//                                 iterations, system size.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>

#include "core/parallel.h"
#include "deform/arap.h"
#include "deform/convert.h"
#include "deform/fem.h"
#include "deform/grid.h"
#include "deform/weights.h"
#include "dim3/mesh3.h"
#include "dim3/self_connecting.h"
#include "dim3/surface.h"

namespace imm::bench {
namespace {

using deform::SimplexMesh;

template <int D>
std::vector<Eigen::Index> end_faces(const SimplexMesh<D>& mesh) {
  return deform::test::vertices_where<D>(mesh, 0, 0.0, 1.0);
}

template <int D>
Eigen::MatrixXd bent_targets(const SimplexMesh<D>& mesh, const std::vector<Eigen::Index>& handles) {
  Eigen::MatrixXd targets(static_cast<Eigen::Index>(handles.size()), D);
  for (std::size_t k = 0; k < handles.size(); ++k) {
    Eigen::Matrix<double, 1, D> p = mesh.vertices.row(handles[k]);
    if (p(0) > 0.5) p(D - 1) += 0.5;
    targets.row(static_cast<Eigen::Index>(k)) = p;
  }
  return targets;
}

template <int D>
void BM_Deform_ArapPrecompute(benchmark::State& state) {
  const SimplexMesh<D> mesh = deform::test::unit_grid<D>(static_cast<int>(state.range(0)));
  const std::vector<Eigen::Index> handles = end_faces<D>(mesh);
  for (auto _ : state) benchmark::DoNotOptimize(deform::arap_precompute<D>(mesh, handles));
  state.counters["elements"] = static_cast<double>(mesh.element_count());
  state.counters["unknowns"] = static_cast<double>((mesh.vertex_count() - static_cast<Eigen::Index>(handles.size())) * D);
}

/// Ten local/global iterations (local rotations fused with the energy, the right-hand side, the
/// prefactored solve of all coordinates, the Anderson step), on range(1) threads: the time per
/// iteration is the reported time / 10. The first call starts at rest, later ones continue from
/// the bent state (convergence tests off, so every call does ten iterations).
template <int D>
void BM_Deform_ArapIteration(benchmark::State& state) {
  const SimplexMesh<D> mesh = deform::test::unit_grid<D>(static_cast<int>(state.range(0)));
  const std::vector<Eigen::Index> handles = end_faces<D>(mesh);
  const deform::ArapData<D> data = deform::arap_precompute<D>(mesh, handles);
  const Eigen::MatrixXd targets = bent_targets<D>(mesh, handles);
  Eigen::MatrixXd x = mesh.vertices;
  const deform::ArapOptions options{.max_iterations = 10,
                                    .relative_tolerance = -1.0,
                                    .threads = static_cast<unsigned>(state.range(1)),
                                    .energy_tolerance = -1.0};
  for (auto _ : state) {
    const deform::ArapReport r = deform::arap_solve<D>(data, targets, x, options);
    benchmark::DoNotOptimize(r);
  }
  state.counters["elements"] = static_cast<double>(mesh.element_count());
  state.counters["iterations_per_call"] = 10;
}

/// One implicit Euler step (Newton to convergence) of a bar bent by its end face.
template <int D>
void BM_Deform_FemStep(benchmark::State& state) {
  const SimplexMesh<D> mesh = deform::test::unit_grid<D>(static_cast<int>(state.range(0)));
  const std::vector<Eigen::Index> fixed = end_faces<D>(mesh);
  deform::FemOptions options;
  options.material = {.youngs_modulus = 1e4, .poisson_ratio = 0.3, .density = 1.0};
  options.time_step = 1.0 / 30.0;
  options.gravity = Eigen::VectorXd::Zero(D);
  options.gravity[D - 1] = -9.81;
  const deform::FemData<D> data = deform::fem_precompute<D>(mesh, fixed, options.material);
  const Eigen::MatrixXd targets = bent_targets<D>(mesh, fixed);
  int newton = 0;
  for (auto _ : state) {
    state.PauseTiming();
    deform::FemState<D> s{mesh.vertices, Eigen::MatrixXd::Zero(mesh.vertex_count(), D)};
    state.ResumeTiming();
    newton = deform::fem_step<D>(data, s, targets, options).newton_iterations;
  }
  state.counters["elements"] = static_cast<double>(mesh.element_count());
  state.counters["newton_iterations"] = newton;
}

/// The quintuple torus's unglued mesh (built once; nullopt when ../shared is absent or it fails).
const std::optional<SimplexMesh<3>>& quintuple_mesh() {
  static const std::optional<SimplexMesh<3>> mesh = []() -> std::optional<SimplexMesh<3>> {
    const std::string obj = std::string(IMM_SHARED_DATA_DIR) + "/3d/quintupleTorus.obj";
    const std::string veg = std::string(IMM_SHARED_DATA_DIR) + "/tet/quintupleTorus.veg";
    if (!std::filesystem::exists(obj) || !std::filesystem::exists(veg)) return std::nullopt;
    const dim3::SurfaceReadResult read = dim3::read_surface(obj);
    if (!read.report.ok()) return std::nullopt;
    dim3::ImmerseOptions io;
    io.build.exact_volumes = false;
    const dim3::Immersed im = dim3::immerse_surface(read.surface, io);
    if (!im.build.complex || im.search.immersions.empty()) return std::nullopt;
    dim3::MeshOptions options;
    options.background_path = veg;
    const dim3::MeshResult m =
        dim3::mesh_immersion(*im.build.complex, im.search.immersions[0], options, im.input_vertices, im.input_triangles);
    if (!m.report.ok()) return std::nullopt;
    return deform::to_simplex_mesh(m.mesh);
  }();
  return mesh;
}

void BM_Deform_FemQuintuple(benchmark::State& state) {
  const std::optional<SimplexMesh<3>>& mesh = quintuple_mesh();
  if (!mesh) {
    state.SkipWithError("../shared/data/real/3d/quintupleTorus.obj or tet/quintupleTorus.veg absent (or not meshed)");
    return;
  }
  const bool drop = state.range(0) == 1;
  const int steps = drop ? 12 : 6;
  deform::FemOptions options;  // E = 1e4, nu = 0.3, density 1, h = 1/30: the program's defaults
  options.time_step = 1.0 / 30.0;
  options.max_pcg_iterations = static_cast<int>(state.range(1));
  std::vector<Eigen::Index> fixed;
  Eigen::MatrixXd targets(0, 3);
  if (drop) {
    options.gravity = Eigen::Vector3d(0, -9.81, 0);
    options.ground_normal = Eigen::Vector3d(0, 1, 0);
    options.ground_offset = mesh->vertices.col(1).minCoeff() - 0.05;
  } else {
    for (Eigen::Index v = 0; v < mesh->vertex_count(); ++v)
      if (mesh->vertices(v, 0) <= -2.4 || mesh->vertices(v, 0) >= 2.4) fixed.push_back(v);
    targets = mesh->vertices(fixed, Eigen::all);
    for (Eigen::Index k = 0; k < targets.rows(); ++k)
      if (targets(k, 0) >= 2.4) targets(k, 2) += 0.3;
  }
  const deform::FemData<3> data = deform::fem_precompute<3>(*mesh, fixed, options.material);
  std::vector<double> seconds, cpu;  // per step: wall, and process CPU (all threads)
  deform::FemSeconds stages;
  int newton = 0, factorizations = 0, pcg = 0, unconverged = 0;
  deform::FemReport last;
  double setup_seconds = 0.0, setup_cpu = 0.0;
  // Runs f, adding its wall seconds to `wall` and its process CPU seconds to `cpu_seconds`.
  const auto timed = [](double& wall, double& cpu_seconds, const auto& f) {
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = process_cpu_seconds();
    f();
    cpu_seconds += process_cpu_seconds() - cpu_start;
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  for (auto _ : state) {
    deform::FemSolver solver;
    setup_seconds = setup_cpu = 0.0;
    timed(setup_seconds, setup_cpu, [&] { benchmark::DoNotOptimize(deform::fem_prepare<3>(data, solver)); });
    deform::FemState<3> s{mesh->vertices, Eigen::MatrixXd::Zero(mesh->vertex_count(), 3)};
    seconds.clear();
    cpu.clear();
    stages = {};
    newton = factorizations = pcg = unconverged = 0;
    for (int step = 0; step < steps; ++step) {
      seconds.push_back(0.0);
      cpu.push_back(0.0);
      timed(seconds.back(), cpu.back(), [&] { last = deform::fem_step<3>(data, s, targets, options, &solver); });
      newton += last.newton_iterations;
      factorizations += last.factorizations;
      pcg += last.pcg_iterations;
      unconverged += last.converged ? 0 : 1;
      stages.analysis += last.seconds.analysis;
      stages.assembly += last.seconds.assembly;
      stages.factorization += last.seconds.factorization;
      stages.solve += last.seconds.solve;
      stages.line_search += last.seconds.line_search;
    }
  }
  std::vector<double> later(seconds.begin() + 1, seconds.end()), later_cpu(cpu.begin() + 1, cpu.end());
  std::sort(later.begin(), later.end());
  std::sort(later_cpu.begin(), later_cpu.end());
  state.counters["unknowns"] = static_cast<double>(last.unknowns);
  state.counters["nonzeros"] = static_cast<double>(last.nonzeros);
  state.counters["steps"] = steps;
  state.counters["s_setup"] = setup_seconds;
  state.counters["cpu_setup"] = setup_cpu;
  state.counters["s_first_step"] = seconds.front();
  state.counters["s_median_later"] = later[later.size() / 2];
  state.counters["s_max_later"] = later.back();
  state.counters["cpu_first_step"] = cpu.front();
  state.counters["cpu_median_later"] = later_cpu[later_cpu.size() / 2];
  state.counters["cpu_max_later"] = later_cpu.back();
  state.counters["s_analysis"] = stages.analysis;
  state.counters["s_assembly"] = stages.assembly;
  state.counters["s_factorization"] = stages.factorization;
  state.counters["s_solve"] = stages.solve;
  state.counters["s_line_search"] = stages.line_search;
  state.counters["newton"] = newton;
  state.counters["factorizations"] = factorizations;
  state.counters["pcg"] = pcg;
  state.counters["unconverged"] = unconverged;
}

/// Bounded biharmonic weights for 4 handles (single vertices at four corners of the box).
template <int D>
void BM_Deform_Bbw4(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const SimplexMesh<D> mesh = deform::test::unit_grid<D>(n);
  std::vector<std::vector<Eigen::Index>> handles;
  // Corner vertex ids of the lattice: 0, n, (n+1)n + ... (the four corners with the last axes at 0 or 1).
  const Eigen::Index side = n + 1;
  handles.push_back({0});
  handles.push_back({n});
  handles.push_back({side * n});
  handles.push_back({side * n + n});
  int iterations = 0;
  for (auto _ : state) {
    const deform::WeightsResult r = deform::bounded_biharmonic_weights<D>(mesh, handles);
    iterations = 0;
    for (int i : r.active_set_iterations) iterations += i;
  }
  state.counters["elements"] = static_cast<double>(mesh.element_count());
  state.counters["active_set_iterations"] = iterations;
}

/// Bounded biharmonic weights for 4 handles where the bounds matter: a 4 x 1 x 1 bar of
/// 60 x 15 x 15 cubes (81,000 tets, about the size of the quintuple-torus mesh), handles the vertices
/// at x = 0, 4/3, 8/3, 4 on its bottom front edge. The unconstrained biharmonic weights of such
/// handles overshoot [0, 1] between them (the active sets are not empty, unlike the corner
/// handles of BM_Deform_Bbw4).
void BM_Deform_Bbw4Bar(benchmark::State& state) {
  const SimplexMesh<3> mesh = deform::test::box_grid<3>({60, 15, 15}, {4.0, 1.0, 1.0});
  std::vector<std::vector<Eigen::Index>> handles(4);
  for (Eigen::Index v = 0; v < mesh.vertex_count(); ++v)
    if (mesh.vertices(v, 1) == 0.0 && mesh.vertices(v, 2) == 0.0)
      for (int k = 0; k < 4; ++k)
        if (std::abs(mesh.vertices(v, 0) - 4.0 * k / 3.0) < 1e-9) handles[static_cast<std::size_t>(k)].push_back(v);
  int iterations = 0;
  for (auto _ : state) {
    const deform::WeightsResult r = deform::bounded_biharmonic_weights<3>(mesh, handles);
    iterations = 0;
    for (int i : r.active_set_iterations) iterations += i;
  }
  state.counters["elements"] = static_cast<double>(mesh.element_count());
  state.counters["active_set_iterations"] = iterations;
}

BENCHMARK_TEMPLATE(BM_Deform_ArapPrecompute, 2)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_Deform_ArapPrecompute, 3)->Arg(12)->Arg(24)->Unit(benchmark::kMillisecond);
// Process CPU time: the local step runs on several threads, whose time the default (main-thread) CPU timer misses.
BENCHMARK_TEMPLATE(BM_Deform_ArapIteration, 2)->Args({64, 1})->Args({128, 1})->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();
BENCHMARK_TEMPLATE(BM_Deform_ArapIteration, 3)->Args({12, 1})->Args({24, 1})->Args({24, 2})->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();
BENCHMARK_TEMPLATE(BM_Deform_FemStep, 2)->Arg(64)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_Deform_FemStep, 3)->Arg(12)->Arg(24)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_Deform_FemQuintuple)
    ->ArgNames({"scenario", "pcg"})
    ->Args({0, 20})
    ->Args({1, 20})
    ->Args({0, 0})
    ->Args({1, 0})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);
BENCHMARK_TEMPLATE(BM_Deform_Bbw4, 2)->Arg(64)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_TEMPLATE(BM_Deform_Bbw4, 3)->Arg(12)->Arg(24)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_Deform_Bbw4Bar)->Unit(benchmark::kMillisecond)->Iterations(1)->MeasureProcessCPUTime();

}  // namespace
}  // namespace imm::bench
