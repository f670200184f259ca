// Time to load (and to write) standard pose-graph files with slamkit's io module.
//
//   build/bench/bench_io_load --benchmark_out=bench/results/io_load.json --benchmark_out_format=json
//
// read_pose_graph includes everything a caller gets: parsing, reference checks, the
// information-matrix health check (one eigen-decomposition per edge) and, for edges-only
// files, the odometry completion. Datasets: $SLAMKIT_DATA (default <source>/../shared/datasets);
// a missing file is reported as a skipped benchmark, not a failure.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "slamkit/io/pose_graph_io.h"

namespace {

std::filesystem::path data_root() {
  const char* env = std::getenv("SLAMKIT_DATA");
  std::filesystem::path p = env && *env ? std::filesystem::path(env) : std::filesystem::path("../shared/datasets");
  if (p.is_relative()) p = std::filesystem::path(SLAMKIT_SOURCE_DIR) / p;
  return p.lexically_normal();
}

void read_graph(benchmark::State& state, const std::string& relative) {
  const std::filesystem::path path = data_root() / relative;
  if (!std::filesystem::exists(path)) {
    state.SkipWithError(("dataset not found: " + path.string() + " (set SLAMKIT_DATA)").c_str());
    return;
  }
  std::size_t vertices = 0, edges = 0;
  for (auto _ : state) {
    const slamkit::PoseGraph g = slamkit::read_pose_graph(path.string());
    vertices = g.vertices().size();
    edges = g.edges.size();
    benchmark::DoNotOptimize(g.edges.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * std::filesystem::file_size(path)));
  state.counters["vertices"] = static_cast<double>(vertices);
  state.counters["edges"] = static_cast<double>(edges);
}

void write_graph(benchmark::State& state, const std::string& relative) {
  const std::filesystem::path path = data_root() / relative;
  if (!std::filesystem::exists(path)) {
    state.SkipWithError(("dataset not found: " + path.string() + " (set SLAMKIT_DATA)").c_str());
    return;
  }
  const slamkit::PoseGraph g = slamkit::read_pose_graph(path.string());
  std::size_t bytes = 0;
  for (auto _ : state) {
    const std::string text = slamkit::pose_graph_to_string(g, slamkit::PoseGraphFormat::kAuto);
    bytes = text.size();
    benchmark::DoNotOptimize(text.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes));
}

}  // namespace

BENCHMARK_CAPTURE(read_graph, city10000_g2o, "posegraph/2d/city10000.g2o")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_graph, torus3D_g2o, "posegraph/3d/torus3D.g2o")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_graph, CSAIL_P_toro_graph, "posegraph/2d/toro/CSAIL_P_toro.graph")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(read_graph, sphere2500_gtsam_txt, "posegraph/3d/gtsam_txt/sphere2500.txt")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(write_graph, city10000_g2o, "posegraph/2d/city10000.g2o")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(write_graph, torus3D_g2o, "posegraph/3d/torus3D.g2o")->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
