// BM_Render: a picture of a generated helix (2,000 triangles per turn, intersecting triangles
// coloured as the figures colour them) rendered by POV-Ray at 1200 x 900, end to end (scene
// text, the povray run, the PNG check and rename). The work happens in the povray process, so
// the family reports wall time (UseRealTime). Issue 15's target: 100k triangles in < 30 s.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <unistd.h>

#include "dim3/generators3.h"
#include "render/mesh_scenes.h"
#include "render/povray.h"

namespace {

void BM_Render_Helix(benchmark::State& state) {
  if (!imm::render::find_povray().error.empty()) {
    state.SkipWithError("POV-Ray not installed");
    return;
  }
  const int loops = static_cast<int>(state.range(0));
  const imm::dim3::Surface helix = imm::dim3::helix(loops, 20);  // 2000 * loops + 280 triangles
  imm::render::Scene scene;
  // Every other turn red, so the per-triangle texture path is the one measured.
  std::vector<bool> red(helix.triangle_count());
  for (std::size_t t = 0; t < red.size(); ++t) red[t] = (t / 2000) % 2 == 1;
  scene.parts.push_back(imm::render::surface_part(helix, red, imm::render::colors::kSurface, true));
  scene.view = imm::render::View{30, 25, 2};
  imm::render::RenderOptions options;
  options.width = static_cast<int>(state.range(1));
  options.height = options.width * 3 / 4;
  const auto png = std::filesystem::temp_directory_path() / ("imm_bench_render_" + std::to_string(::getpid()) + ".png");
  for (auto _ : state) {
    const imm::render::RenderStatus status = imm::render::render_png(scene, png.string(), options);
    if (!status.ok()) {
      state.SkipWithError(status.error.c_str());
      break;
    }
  }
  std::filesystem::remove(png);
  state.counters["triangles"] = static_cast<double>(helix.triangle_count());
  state.counters["pixels"] = static_cast<double>(options.width) * options.height;
}

}  // namespace

BENCHMARK(BM_Render_Helix)
    ->Args({5, 1200})
    ->Args({50, 1200})
    ->Args({50, 320})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);
