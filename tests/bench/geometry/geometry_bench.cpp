// Speed criteria of issue 8: one 350-sub-sphere BMS template of a generated particle mesh
// (voxelise + fill + quality metrics) in < 2 s; one generated particle (2562 vertices) in < 0.5 s.
#include <benchmark/benchmark.h>

#include <string>

#include "geometry/generate.hpp"
#include "geometry/mesh_distance.hpp"
#include "geometry/sphere_fill.hpp"
#include "geometry/template_quality.hpp"

namespace shapepress::geometry {
namespace {

ShapeTargets paper_targets() {
  ShapeTargets t;  // Giannis et al. 2023 §3.2: ASR 0.8, elongation 0.84, flatness 0.95
  t.D3 = 0.03;
  t.D8 = 0.008;
  t.asr_mean = 0.8;
  t.elongation = 0.84;
  t.flatness = 0.95;
  t.x10_m = 70e-6;
  t.x50_m = 180e-6;
  t.x90_m = 330e-6;
  return t;
}

void BM_GenerateOneParticle(benchmark::State& state) {
  GenerateOptions options;
  options.count = 1;
  std::uint64_t seed = 1;
  for (auto _ : state) {
    options.seed = seed++;
    benchmark::DoNotOptimize(generate_population(paper_targets(), options));
  }
}
BENCHMARK(BM_GenerateOneParticle)->Unit(benchmark::kMillisecond);

void BM_BondedTemplate350(benchmark::State& state) {
  GenerateOptions options;
  options.count = 1;
  const TriangleMesh mesh = generate_population(paper_targets(), options).front().mesh;
  const MassProperties exact = mesh_mass_properties(mesh);
  for (auto _ : state) {
    const SignedDistance shape = mesh_distance(mesh, 64);
    BondedFillOptions fill;
    fill.target_count = 350;
    const SphereTemplate t = fill_bonded(shape, fill);
    benchmark::DoNotOptimize(assess_fill(t, shape, exact));
  }
}
BENCHMARK(BM_BondedTemplate350)->Unit(benchmark::kMillisecond);

void BM_RigidTemplate150(benchmark::State& state) {
  GenerateOptions options;
  options.count = 1;
  const TriangleMesh mesh = generate_population(paper_targets(), options).front().mesh;
  const MassProperties exact = mesh_mass_properties(mesh);
  for (auto _ : state) {
    const SignedDistance shape = mesh_distance(mesh, 64);
    RigidFillOptions fill;
    fill.sphere_count = 150;
    const SphereTemplate t = fill_rigid(shape, fill);
    benchmark::DoNotOptimize(assess_fill(t, shape, exact));
  }
}
BENCHMARK(BM_RigidTemplate150)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace shapepress::geometry

BENCHMARK_MAIN();
