// Speed of shape-stats on one SEM-like image: 2048 × 1536 px, ~200 particles (issue 7 asks
// for < 1 s on one core). Run: build/tests/bench/imaging_shape_stats_bench (OMP is pinned to
// one thread here). Not part of CI.
#include <benchmark/benchmark.h>
#include <omp.h>
#include <unistd.h>

#include <filesystem>

#include "imaging/sem_tiff.hpp"
#include "imaging/shape_stats.hpp"
#include "imaging/synth.hpp"

namespace {

using namespace shapepress::imaging;

std::filesystem::path sem_like_image() {
  static const std::filesystem::path path = [] {
    SynthOptions o;
    o.width = 2048;
    o.height = 1536;
    o.particles = 200;
    o.median_diameter_px = 60;
    o.info_bar_rows = 80;
    o.seed = 2024;
    SynthScene scene = render_synthetic_scene(o);
    auto p = std::filesystem::temp_directory_path() /
             ("shapepress_bench_" + std::to_string(::getpid()) + ".tif");
    write_sem_tiff(p, scene.image, "[Scan]\nPixelWidth=5e-07\n[Image]\nResolutionY=1456\n");
    return p;
  }();
  return path;
}

void BM_ShapeStatsOneImage(benchmark::State& state) {
  omp_set_num_threads(1);
  const auto path = sem_like_image();
  ShapeStatsOptions options;
  int particles = 0;
  for (auto _ : state) {
    ImageResult result = process_image(path, options);
    ShapeSummary summary = summarize(particle_samples({result}));
    particles = summary.particle_count;
    benchmark::DoNotOptimize(summary);
  }
  state.counters["particles"] = particles;
}
BENCHMARK(BM_ShapeStatsOneImage)->Unit(benchmark::kMillisecond)->MinTime(2.0);

}  // namespace

BENCHMARK_MAIN();
