// 3D meshing of an immersion (paper §7 with d = 3, dim3/mesh3.h) and a double-precision baseline.
//
//  BM_Mesh3_QuintupleTorusVeg     ../shared/data/real/3d/quintupleTorus.obj (Fig. 22) meshed on
//                                 ../shared/data/real/tet/quintupleTorus.veg: one whole
//                                 mesh_immersion per iteration (reading the .veg included).
//                                 Counters: background and output tets, polygons, the stage times
//                                 and virtual_tets_per_s = background tets / seconds_virtual.
//                                 Skipped when ../shared is absent.
//  BM_Mesh3_ClipDoubles/threads   "the practical ceiling" of the clipping stage: the same cut
//                                 triangles (Complex::cut_vertices / cut_triangles, in doubles)
//                                 clipped to the same background tets by a plain double-precision
//                                 Sutherland–Hodgman against the four face planes (no exactness,
//                                 no symbolic vertices, no genericity check, no pieces). The
//                                 (tet, cut triangle) candidate pairs come from
//                                 CGAL::box_intersection_d outside the timed loop. tets_per_s on
//                                 the same tets, so exact / double is read off one run:
//                                 virtual_tets_per_s (above) / tets_per_s (here). The exact stage
//                                 also finds its candidates, and computes pieces, sides and local
//                                 regions: the ratio bounds what any exact scheme can gain.
//  BM_Mesh3_Resolution/N          tube_overlap(16) (Fig. 1/5 in 3D, 3,296 triangles) on a
//                                 generated grid of N cubes along the longest side: scaling with
//                                 the background. SetComplexityN = background tets.
//  BM_Mesh3_SurfaceSize/sides     helix(4, sides) (5 sides^2 * 4 + 14 sides triangles, the same
//                                 shape and box for every size) on a fixed 32-cube grid: scaling
//                                 with the surface. SetComplexityN = triangles.
//  BM_Mesh3_Scale/threads/resolution  two_tori(160) (102,400 triangles; the 2.53 M-tet case of
//                                 BENCHMARKS.md at resolution 125) on growing generated grids,
//                                 1 or 2 threads (issue 17): the size ladder. Counters: the
//                                 stage times (wall), each per background tet and per cut tet
//                                 (ns_*), process CPU seconds, peak RSS (MB; the process's peak,
//                                 so run one size per process with --benchmark_filter) and bytes
//                                 of peak RSS per background and per output tet.
//  BM_Mesh3_TwoThreadRatio_*/rounds  the quintuple torus on its .veg, and two_tori(160) at
//                                 resolution 125: rounds of 1 then 2 threads, interleaved in one
//                                 process (issue 17's "two threads >= 1.8x one thread"). Counters:
//                                 medians, minima and three ratios (of the medians, per round, of
//                                 the minima).
// Inputs (surface, complex with volumes in doubles, first immersion) are built outside the timed
// loop. Every family uses real (wall) time, since the exact stage may run on several threads.
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "dim3/generators3.h"
#include "core/unglue.h"
#include "dim3/mesh3.h"
#include "dim3/self_connecting.h"
#include "dim3/tet_mesh.h"

namespace imm::bench {
namespace {

/// A surface, its complex and its first immersion.
struct Mesh3Input {
  dim3::Immersed immersed;
  [[nodiscard]] const dim3::Complex& complex() const { return *immersed.build.complex; }
  [[nodiscard]] const Immersion& immersion() const { return immersed.search.immersions.front(); }
};

/// @return nullopt (and `error` set) when the surface is invalid or has no immersion.
std::optional<Mesh3Input> prepare(const dim3::Surface& surface, std::string& error) {
  dim3::ImmerseOptions options;
  options.build.exact_volumes = false;  // the search and the meshing do not read them
  Mesh3Input input{dim3::immerse_surface(surface, options)};
  if (!input.immersed.build.complex || !input.immersed.build.report.ok()) {
    error = "input is not valid: " + input.immersed.build.report.summary();
    return std::nullopt;
  }
  if (input.immersed.search.immersions.empty()) {
    error = "input has no immersion";
    return std::nullopt;
  }
  return input;
}

std::string shared_path(const std::string& relative) { return std::string(IMM_SHARED_DATA_DIR) + "/" + relative; }

const std::string kQuintupleObj = "3d/quintupleTorus.obj";
const std::string kQuintupleVeg = "tet/quintupleTorus.veg";

/// The quintuple torus, built once and shared by the exact and the double families.
const std::optional<Mesh3Input>& quintuple_input(std::string& error) {
  static std::string first_error;
  static const std::optional<Mesh3Input> input = []() -> std::optional<Mesh3Input> {
    const std::string obj = shared_path(kQuintupleObj);
    if (!std::filesystem::exists(obj) || !std::filesystem::exists(shared_path(kQuintupleVeg))) {
      first_error = "../shared/data/real/" + kQuintupleObj + " or " + kQuintupleVeg + " absent";
      return std::nullopt;
    }
    dim3::SurfaceReadResult read = dim3::read_surface(obj);
    if (!read.report.ok()) {
      first_error = "unreadable " + obj + ": " + read.report.summary();
      return std::nullopt;
    }
    return prepare(read.surface, first_error);
  }();
  error = first_error;
  return input;
}

/// Per-stage counters (dim3::MeshStats' stage clocks): wall (s_*), CPU over all threads (cpu_s_*),
/// the calling thread's CPU (serial_s_*, the serial part on two threads or more), CPU per
/// background tet (per cut tet for the tets' clipping), and the serial fraction of the stages.
void add_stage_counters(benchmark::State& state, const dim3::MeshStats& stats) {
  const auto background = static_cast<double>(stats.background_tets);
  const auto cut = static_cast<double>(std::max<std::size_t>(stats.cut_tets, 1));
  const double mesh_seconds = stats.seconds_background + stats.seconds_virtual + stats.seconds_assembly;
  state.counters["ns_per_bg_tet"] = 1e9 * mesh_seconds / background;
  const std::pair<const char*, dim3::StageSeconds> stages[] = {
      {"candidates", stats.seconds_candidates}, {"tets", stats.seconds_tets},
      {"faces", stats.seconds_faces},           {"regions", stats.seconds_regions},
      {"atoms", stats.seconds_atoms},           {"unglue", stats.seconds_unglue},
      {"emit", stats.seconds_emit}};
  // The background (generated or read) is one sequential step: serial throughout.
  double cpu_sum = stats.seconds_background, serial_sum = stats.seconds_background;
  for (const auto& [name, seconds] : stages) {
    cpu_sum += seconds.cpu;
    serial_sum += seconds.serial;
    state.counters[std::string("s_") + name] = seconds.wall;
    state.counters[std::string("cpu_s_") + name] = seconds.cpu;
    state.counters[std::string("serial_s_") + name] = seconds.serial;
    // The clipping of the cut tets is per cut tet; every other stage is per background tet (CPU).
    const bool per_cut = std::string(name) == "tets";
    state.counters[std::string(per_cut ? "cpu_ns_per_cut_" : "cpu_ns_per_bg_") + name] =
        1e9 * seconds.cpu / (per_cut ? cut : background);
  }
  // The caller's share of the stages' CPU: their serial fraction (on two threads or more).
  if (cpu_sum > 0.0) state.counters["serial_fraction"] = serial_sum / cpu_sum;
}

/// One mesh_immersion call per iteration; the counters of the last one.
void run_mesh(benchmark::State& state, const Mesh3Input& input, const dim3::MeshOptions& options) {
  dim3::MeshStats stats;
  for (auto _ : state) {
    dim3::MeshResult r = dim3::mesh_immersion(input.complex(), input.immersion(), options, input.immersed.input_vertices);
    if (!r.report.ok()) {
      state.SkipWithError(("meshing failed: " + r.report.summary()).c_str());
      return;
    }
    benchmark::DoNotOptimize(r.mesh.tets.data());
    stats = std::move(r.stats);
  }
  add_stage_counters(state, stats);
  state.counters["triangles"] = static_cast<double>(input.immersed.surface.triangle_count());
  state.counters["cut_triangles"] = static_cast<double>(input.complex().cut_triangles.size());
  state.counters["background_tets"] = static_cast<double>(stats.background_tets);
  state.counters["candidate_pairs"] = static_cast<double>(stats.candidate_pairs);
  state.counters["polygons"] = static_cast<double>(stats.polygons);
  state.counters["cut_tets"] = static_cast<double>(stats.cut_tets);
  state.counters["output_tets"] = static_cast<double>(stats.output_tets);
  state.counters["attempts"] = static_cast<double>(stats.attempts);
  state.counters["s_background"] = stats.seconds_background;
  state.counters["s_virtual"] = stats.seconds_virtual;
  state.counters["s_assembly"] = stats.seconds_assembly;
  if (stats.seconds_virtual > 0.0)
    state.counters["virtual_tets_per_s"] = static_cast<double>(stats.background_tets) / stats.seconds_virtual;
}

/// Process CPU seconds (all threads) and peak resident set (KB) so far.
std::pair<double, double> process_cpu_and_peak() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const auto seconds = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
  return {seconds(usage.ru_utime) + seconds(usage.ru_stime), static_cast<double>(usage.ru_maxrss)};
}

// ---- the quintuple torus on its .veg -----------------------------------------------------------

/// The quintuple torus, with `options` set to mesh it on its .veg; null (the benchmark skipped)
/// when ../shared is absent.
const Mesh3Input* quintuple_on_its_veg(benchmark::State& state, dim3::MeshOptions& options) {
  std::string error;
  const std::optional<Mesh3Input>& input = quintuple_input(error);
  if (!input) {
    state.SkipWithError(error.c_str());
    return nullptr;
  }
  options.background_path = shared_path(kQuintupleVeg);
  return &*input;
}

void BM_Mesh3_QuintupleTorusVeg(benchmark::State& state) {
  dim3::MeshOptions options;
  const Mesh3Input* input = quintuple_on_its_veg(state, options);
  if (input == nullptr) return;
  options.threads = static_cast<unsigned>(state.range(0));
  run_mesh(state, *input, options);
}
BENCHMARK(BM_Mesh3_QuintupleTorusVeg)
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->Iterations(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// ---- the double-precision baseline -------------------------------------------------------------

using P3 = std::array<double, 3>;

P3 minus(const P3& a, const P3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const P3& a, const P3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
P3 cross(const P3& a, const P3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

/// Face f is opposite vertex f, oriented so that vertex f lies on its positive side (as in
/// dim3/virtual_tets.cpp).
constexpr int kFace[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};

/// A convex polygon with at most 3 + 4 vertices (a triangle clipped by four planes).
struct SmallPolygon {
  std::array<P3, 8> v;
  int n = 0;
};

/// Plain Sutherland–Hodgman in doubles: `poly` clipped to n . p >= d for the four face planes.
void clip_doubles(const std::array<P3, 4>& normal, const std::array<double, 4>& offset, SmallPolygon& poly) {
  SmallPolygon next;
  std::array<double, 8> s{};
  for (int f = 0; f < 4 && poly.n > 0; ++f) {
    bool any_out = false;
    for (int i = 0; i < poly.n; ++i) {
      s[i] = dot(normal[f], poly.v[i]) - offset[f];
      any_out = any_out || s[i] < 0.0;
    }
    if (!any_out) continue;
    next.n = 0;
    for (int i = 0; i < poly.n; ++i) {
      const int j = i + 1 == poly.n ? 0 : i + 1;
      if (s[i] >= 0.0) next.v[next.n++] = poly.v[i];
      if ((s[i] < 0.0) != (s[j] < 0.0)) {
        const double t = s[i] / (s[i] - s[j]);
        const P3& p = poly.v[i];
        const P3& q = poly.v[j];
        next.v[next.n++] = {p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1]), p[2] + t * (q[2] - p[2])};
      }
    }
    poly = next;
  }
}

struct ClipResult {
  std::size_t polygons = 0;
  double checksum = 0.0;  ///< sum of the polygons' vertex coordinates (keeps the work alive)
};

/// Clips every candidate of tets [first, last) (`cand_first` indexes `pairs` by tet).
ClipResult clip_tets(const dim3::TetMesh& bg, const std::vector<P3>& cut_vertices,
                     const std::vector<dim3::Triangle>& cut_triangles, const std::vector<std::uint32_t>& pair_triangle,
                     const std::vector<std::size_t>& cand_first, std::size_t first, std::size_t last) {
  ClipResult out;
  SmallPolygon poly;
  for (std::size_t t = first; t < last; ++t) {
    if (cand_first[t] == cand_first[t + 1]) continue;
    std::array<P3, 4> v;
    for (int k = 0; k < 4; ++k) v[k] = bg.vertices[static_cast<std::size_t>(bg.tets[t][k])];
    std::array<P3, 4> normal;
    std::array<double, 4> offset{};
    for (int f = 0; f < 4; ++f) {
      const P3& a = v[kFace[f][0]];
      normal[f] = cross(minus(v[kFace[f][1]], a), minus(v[kFace[f][2]], a));
      offset[f] = dot(normal[f], a);
    }
    for (std::size_t c = cand_first[t]; c < cand_first[t + 1]; ++c) {
      const dim3::Triangle& tri = cut_triangles[pair_triangle[c]];
      poly.n = 3;
      for (int k = 0; k < 3; ++k) poly.v[k] = cut_vertices[tri[k]];
      clip_doubles(normal, offset, poly);
      if (poly.n >= 3) {
        ++out.polygons;
        for (int i = 0; i < poly.n; ++i) out.checksum += poly.v[i][0] + poly.v[i][1] + poly.v[i][2];
      }
    }
  }
  return out;
}

void BM_Mesh3_ClipDoubles(benchmark::State& state) {
  std::string error;
  const std::optional<Mesh3Input>& input = quintuple_input(error);
  if (!input) {
    state.SkipWithError(error.c_str());
    return;
  }
  static const dim3::TetReadResult read = dim3::read_tet_mesh(shared_path(kQuintupleVeg));
  if (!read.report.ok()) {
    state.SkipWithError(("unreadable background: " + read.report.summary()).c_str());
    return;
  }
  const dim3::TetMesh& bg = read.mesh;
  const dim3::Complex& c3 = input->complex();

  // Candidate (tet, cut triangle) pairs, sorted by tet, outside the timed loop.
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::uint32_t>;
  std::vector<Box> tet_boxes, triangle_boxes;
  tet_boxes.reserve(bg.tets.size());
  for (std::uint32_t t = 0; t < bg.tets.size(); ++t) {
    CGAL::Bbox_3 b;
    for (int k = 0; k < 4; ++k) {
      const P3& p = bg.vertices[static_cast<std::size_t>(bg.tets[t][k])];
      b += CGAL::Bbox_3(p[0], p[1], p[2], p[0], p[1], p[2]);
    }
    tet_boxes.emplace_back(b, t);
  }
  triangle_boxes.reserve(c3.cut_triangles.size());
  for (std::uint32_t x = 0; x < c3.cut_triangles.size(); ++x) {
    CGAL::Bbox_3 b;
    for (std::uint32_t v : c3.cut_triangles[x]) {
      const P3& p = c3.cut_vertices[v];
      b += CGAL::Bbox_3(p[0], p[1], p[2], p[0], p[1], p[2]);
    }
    triangle_boxes.emplace_back(b, x);
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  CGAL::box_intersection_d(tet_boxes.begin(), tet_boxes.end(), triangle_boxes.begin(), triangle_boxes.end(),
                           [&](const Box& a, const Box& b) { pairs.emplace_back(a.info(), b.info()); });
  std::sort(pairs.begin(), pairs.end());
  std::vector<std::size_t> cand_first(bg.tets.size() + 1, 0);
  std::vector<std::uint32_t> pair_triangle;
  pair_triangle.reserve(pairs.size());
  for (const auto& [t, x] : pairs) {
    ++cand_first[t + 1];
    pair_triangle.push_back(x);
  }
  for (std::size_t t = 0; t < bg.tets.size(); ++t) cand_first[t + 1] += cand_first[t];

  const auto threads = static_cast<std::size_t>(state.range(0));
  std::vector<ClipResult> part(threads);
  ClipResult total;
  for (auto _ : state) {
    const auto run = [&](std::size_t k) {
      part[k] = clip_tets(bg, c3.cut_vertices, c3.cut_triangles, pair_triangle, cand_first,
                          bg.tets.size() * k / threads, bg.tets.size() * (k + 1) / threads);
    };
    std::vector<std::thread> workers;
    for (std::size_t k = 1; k < threads; ++k) workers.emplace_back(run, k);
    run(0);
    for (std::thread& w : workers) w.join();
    total = ClipResult();
    for (const ClipResult& r : part) {
      total.polygons += r.polygons;
      total.checksum += r.checksum;
    }
    benchmark::DoNotOptimize(total.checksum);
  }
  state.counters["cut_triangles"] = static_cast<double>(c3.cut_triangles.size());
  state.counters["background_tets"] = static_cast<double>(bg.tets.size());
  state.counters["candidate_pairs"] = static_cast<double>(pairs.size());
  state.counters["polygons"] = static_cast<double>(total.polygons);
  state.counters["tets_per_s"] =
      benchmark::Counter(static_cast<double>(bg.tets.size()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_Mesh3_ClipDoubles)
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->Iterations(3)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// ---- scaling -----------------------------------------------------------------------------------

/// BM_Mesh3_Method/method/resolution: exact clipping (0) against the CSG baseline (1, Nef
/// polyhedron booleans per cut tet) on tube_overlap(6) (516 triangles), both on one thread; the
/// same duplication.
void BM_Mesh3_Method(benchmark::State& state) {
  static std::string error;
  static const std::optional<Mesh3Input> input = prepare(dim3::tube_overlap(6), error);
  if (!input) {
    state.SkipWithError(error.c_str());
    return;
  }
  dim3::MeshOptions options;
  options.method = state.range(0) == 1 ? MeshMethod::Csg : MeshMethod::Clip;
  options.resolution = static_cast<int>(state.range(1));
  options.threads = 1;  // both methods on one thread (BM_Stage_Virtual compares them on all)
  run_mesh(state, *input, options);
  state.SetLabel(state.range(0) == 1 ? "csg" : "clip");
}
BENCHMARK(BM_Mesh3_Method)
    ->ArgNames({"method", "resolution"})
    ->ArgsProduct({{0, 1}, {6, 10}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_Mesh3_Resolution(benchmark::State& state) {
  static std::string error;
  static const std::optional<Mesh3Input> input = prepare(dim3::tube_overlap(16), error);
  if (!input) {
    state.SkipWithError(error.c_str());
    return;
  }
  dim3::MeshOptions options;
  options.resolution = static_cast<int>(state.range(0));
  run_mesh(state, *input, options);
  state.SetComplexityN(static_cast<benchmark::IterationCount>(state.counters["background_tets"].value));
}
BENCHMARK(BM_Mesh3_Resolution)
    ->RangeMultiplier(2)
    ->Range(8, 64)
    ->Iterations(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Complexity();

void BM_Mesh3_SurfaceSize(benchmark::State& state) {
  std::string error;
  const dim3::SurfaceGenerateResult g = dim3::generate_surface("helix", {"4", std::to_string(state.range(0))});
  if (!g.ok()) {
    state.SkipWithError(g.error.c_str());
    return;
  }
  const std::optional<Mesh3Input> input = prepare(g.surface, error);
  if (!input) {
    state.SkipWithError(error.c_str());
    return;
  }
  dim3::MeshOptions options;
  options.resolution = 32;
  run_mesh(state, *input, options);
  state.SetComplexityN(static_cast<benchmark::IterationCount>(g.surface.triangle_count()));
}
BENCHMARK(BM_Mesh3_SurfaceSize)
    ->ArgName("sides")
    ->RangeMultiplier(2)
    ->Range(8, 64)
    ->Iterations(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Complexity();

// ---- meshing at scale (issue 17) -------------------------------------------------------------

/// two_tori(160), built once and shared by the scale and the two-thread families; null (the
/// benchmark skipped) if it cannot be prepared.
const Mesh3Input* two_tori_160(benchmark::State& state) {
  static std::string error;
  static const std::optional<Mesh3Input> input = prepare(dim3::two_tori(160), error);
  if (!input) state.SkipWithError(error.c_str());
  return input ? &*input : nullptr;
}

void BM_Mesh3_Scale(benchmark::State& state) {
  const Mesh3Input* input = two_tori_160(state);
  if (input == nullptr) return;
  dim3::MeshOptions options;
  options.threads = static_cast<unsigned>(state.range(0));
  options.resolution = static_cast<int>(state.range(1));
  dim3::MeshStats stats;
  double cpu = 0.0;
  for (auto _ : state) {
    const double cpu_start = process_cpu_and_peak().first;
    dim3::MeshResult r =
        dim3::mesh_immersion(input->complex(), input->immersion(), options, input->immersed.input_vertices);
    cpu += process_cpu_and_peak().first - cpu_start;
    if (!r.report.ok()) {
      state.SkipWithError(("meshing failed: " + r.report.summary()).c_str());
      return;
    }
    benchmark::DoNotOptimize(r.mesh.tets.data());
    stats = std::move(r.stats);
  }
  const double peak_kb = process_cpu_and_peak().second;
  const auto background = static_cast<double>(stats.background_tets);
  state.counters["background_tets"] = background;
  state.counters["cut_tets"] = static_cast<double>(stats.cut_tets);
  state.counters["output_tets"] = static_cast<double>(stats.output_tets);
  state.counters["cpu_s"] = cpu / static_cast<double>(state.iterations());
  state.counters["peak_MB"] = peak_kb / 1024.0;
  state.counters["cpu_ns_per_bg_tet"] = 1e9 * state.counters["cpu_s"].value / background;
  state.counters["B_per_bg_tet"] = peak_kb * 1024.0 / background;
  state.counters["B_per_out_tet"] = peak_kb * 1024.0 / static_cast<double>(std::max<std::size_t>(stats.output_tets, 1));
  add_stage_counters(state, stats);
}
BENCHMARK(BM_Mesh3_Scale)
    ->ArgNames({"threads", "resolution"})
    ->ArgsProduct({{1, 2}, {64, 125, 160, 200}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// ---- the two-thread speed-up, measured interleaved (issue 17) ---------------------------------

/// Rounds of one mesh_immersion on 1 thread, then one on 2, in one process: a change of the
/// host's speed during the run falls on both thread counts, where sequential repetitions of the
/// families above put it on one of them. The mesh stage's wall per call (the .veg read included
/// when `options.background_path` is set). Counters: medians and minima of each, the ratio of the
/// medians, the median of the per-round ratios and the ratio of the minima (host noise only adds
/// time, and adds more to a two-thread call, which needs both vCPUs).
void run_thread_ratio(benchmark::State& state, const Mesh3Input& input, dim3::MeshOptions options) {
  const auto rounds = static_cast<std::size_t>(state.range(0));
  std::vector<double> one, two, paired;
  std::string error;
  const auto timed = [&](unsigned threads) {
    options.threads = threads;
    const auto start = std::chrono::steady_clock::now();
    dim3::MeshResult r = dim3::mesh_immersion(input.complex(), input.immersion(), options, input.immersed.input_vertices);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (!r.report.ok()) error = "meshing failed: " + r.report.summary();
    benchmark::DoNotOptimize(r.mesh.tets.data());
    return ms;
  };
  for (auto _ : state) {
    for (std::size_t k = 0; k < rounds && error.empty(); ++k) {
      one.push_back(timed(1));
      two.push_back(timed(2));
      paired.push_back(one.back() / two.back());
    }
  }
  if (!error.empty()) {
    state.SkipWithError(error.c_str());
    return;
  }
  const auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  };
  const double min_one = *std::min_element(one.begin(), one.end());
  const double min_two = *std::min_element(two.begin(), two.end());
  state.counters["ms_1_median"] = median(one);
  state.counters["ms_2_median"] = median(two);
  state.counters["ms_1_min"] = min_one;
  state.counters["ms_2_min"] = min_two;
  state.counters["ratio_of_medians"] = median(one) / median(two);
  state.counters["ratio_paired_median"] = median(paired);
  state.counters["ratio_of_minima"] = min_one / min_two;
}

void BM_Mesh3_TwoThreadRatio_QuintupleTorusVeg(benchmark::State& state) {
  dim3::MeshOptions options;
  const Mesh3Input* input = quintuple_on_its_veg(state, options);
  if (input != nullptr) run_thread_ratio(state, *input, options);
}
BENCHMARK(BM_Mesh3_TwoThreadRatio_QuintupleTorusVeg)
    ->ArgName("rounds")
    ->Arg(15)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_Mesh3_TwoThreadRatio_TwoTori(benchmark::State& state) {
  const Mesh3Input* input = two_tori_160(state);
  if (input == nullptr) return;
  dim3::MeshOptions options;
  options.resolution = 125;  // 2,532,864 background tets
  run_thread_ratio(state, *input, options);
}
BENCHMARK(BM_Mesh3_TwoThreadRatio_TwoTori)
    ->ArgName("rounds")
    ->Arg(5)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace imm::bench
