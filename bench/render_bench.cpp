// Image rendering speed (issue 13 part 3), written to bench/results/render.json: room1 with
// --dynamic high (the crowd: the most boxes), every `--step`-th frame of the whole sequence,
// rendered with 1 and 2 threads (supersample 1) and with 2 threads at supersample 2; ms per
// frame (mean, median, p95, max), plus the PNG writing time per frame (image + labels) and
// the scene build time; and thread CPU time per frame (the shared machine's wall time varies
// with its load). --figures DIR writes frame --figure-frame (default: the sampled frame whose
// labelled share is nearest 0.15, with the camera looking within 30° of horizontal) and its labels
// (ids spread over gray levels for viewing) as render_room1_{frame,labels}.png.
// Usage: render_bench [--data DIR] [--step N] [--out FILE] [--figures DIR] [--figure-frame K]
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "slamkit/io/kalibr_calibration.h"
#include "slamkit/io/trajectory_io.h"
#include "slamkit/sim/image_renderer.h"
#include "slamkit/vio/image_io.h"

using namespace slamkit;
namespace fs = std::filesystem;

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }
double process_cpu() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

nlohmann::json stats(std::vector<double> ms) {
  std::sort(ms.begin(), ms.end());
  double sum = 0;
  for (double v : ms) sum += v;
  const auto q = [&](double p) { return ms[std::min(ms.size() - 1, static_cast<std::size_t>(p * (ms.size() - 1) + 0.5))]; };
  return {{"frames", ms.size()}, {"mean_ms", sum / ms.size()}, {"median_ms", q(0.5)}, {"p95_ms", q(0.95)},
          {"max_ms", ms.back()}};
}

}  // namespace

int main(int argc, char** argv) {
  std::string data = std::getenv("SLAMKIT_DATA") ? std::getenv("SLAMKIT_DATA") : "../shared/datasets";
  std::string out = std::string(SLAMKIT_SOURCE_DIR) + "/bench/results/render.json";
  std::size_t step = 10, figure_frame = static_cast<std::size_t>(-1);
  std::string figures;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--data") data = argv[i + 1];
    else if (a == "--step") step = std::max(1, std::atoi(argv[i + 1]));
    else if (a == "--out") out = argv[i + 1];
    else if (a == "--figures") figures = argv[i + 1];
    else if (a == "--figure-frame") figure_frame = static_cast<std::size_t>(std::atoi(argv[i + 1]));
  }
  const fs::path vio = fs::path(data) / "vio";
  const CameraCalibration cam = read_kalibr_camchain((vio / "tumvi/calib/openvins_kalibr_imucam_chain.yaml").string()).at(0);
  const BSplineTrajectory spline = BSplineTrajectory::fit(read_trajectory((vio / "tumvi/gt/dataset-room1_512_16.csv").string()));
  VisualInertialSimOptions so;
  so.seed = 1;
  so.dynamic = DynamicLevel::kHigh;
  so.mask_radius_px = 300.0;
  const VisualInertialSim sim = simulate_visual_inertial(spline, cam.model, cam.T_cam_imu, so);
  double t0 = now();
  const RenderedScene scene = build_rendered_scene(sim, spline, so);
  const double scene_s = now() - t0;
  nlohmann::json j;
  j["kind"] = "render_bench";
  j["sequence"] = "room1";
  j["dynamic"] = "high";
  j["image"] = {{"width", cam.width}, {"height", cam.height}, {"model", cam.distortion_model}, {"mask_radius_px", 300}};
  j["frames_in_sequence"] = sim.frames.size();
  j["frame_step"] = step;
  j["furniture"] = scene.furniture.size();
  j["walkers"] = scene.walkers.size();
  j["textures"] = scene.textures.size();
  j["scene_build_s"] = scene_s;
  j["hardware_threads"] = ThreadPool::hardware_threads();
  const fs::path tmp = fs::temp_directory_path() / "slamkit_render_bench";
  double best_share = 1e9;
  std::size_t best_frame = 0;
  for (const auto& [threads, S] : std::vector<std::pair<int, int>>{{1, 1}, {2, 1}, {2, 2}}) {
    ImageRendererOptions ro;
    ro.seed = 1;
    ro.mask_radius_px = 300.0;
    ro.supersample = S;
    t0 = now();
    const ImageRenderer renderer(scene, *cam.model, ro);
    const double setup = now() - t0;
    const ThreadPool pool(threads);
    GrayImage image, labels;
    std::vector<double> ms, png_ms, cpu_ms;
    std::size_t boxes = 0, labelled = 0;
    fs::create_directories(tmp);
    for (std::size_t k = 0; k < sim.frames.size(); k += step) {
      const SimFrame& f = sim.frames[k];
      t0 = now();
      const double c0 = process_cpu();
      renderer.render(f.t, frame_camera_pose(sim, f), &image, &labels, &pool);
      ms.push_back(1e3 * (now() - t0));
      cpu_ms.push_back(1e3 * (process_cpu() - c0));
      boxes += scene.boxes_at(f.t).size();
      std::size_t frame_labelled = 0;
      for (std::uint8_t l : labels.pixels) frame_labelled += l != 0;
      labelled += frame_labelled;
      if (threads == 1) {
        const double share = frame_labelled / (512.0 * 512.0);
        const Eigen::Vector3d axis = frame_camera_pose(sim, f).rotation().act(Eigen::Vector3d::UnitZ());
        if (std::abs(axis.z()) < 0.5 && std::abs(share - 0.15) < best_share) best_share = std::abs(share - 0.15), best_frame = k;
      }
      if (threads == 2 && S == 1) {
        t0 = now();
        write_png((tmp / "i.png").string(), image);
        write_png((tmp / "l.png").string(), labels);
        png_ms.push_back(1e3 * (now() - t0));
      }
    }
    nlohmann::json r = stats(ms);
    r["threads"] = threads;
    r["supersample"] = S;
    r["setup_s"] = setup;
    r["cpu"] = stats(cpu_ms);  // all threads' CPU time per frame
    r["mean_boxes"] = static_cast<double>(boxes) / ms.size();
    r["mean_labelled_pixel_share"] = static_cast<double>(labelled) / (ms.size() * 512.0 * 512.0);
    r["projected_2800_frames_s"] = 2800 * r["mean_ms"].get<double>() / 1e3;
    if (!png_ms.empty()) r["png_write"] = stats(png_ms);
    std::cerr << "threads " << threads << " supersample " << S << ": " << r.dump() << "\n";
    j["runs"].push_back(r);
  }
  fs::remove_all(tmp);
  if (figure_frame == static_cast<std::size_t>(-1)) figure_frame = best_frame;
  if (!figures.empty() && figure_frame < sim.frames.size()) {
    ImageRendererOptions ro;
    ro.seed = 1;
    ro.mask_radius_px = 300.0;
    const ImageRenderer renderer(scene, *cam.model, ro);
    GrayImage image, labels;
    const SimFrame& f = sim.frames[figure_frame];
    renderer.render(f.t, frame_camera_pose(sim, f), &image, &labels);
    std::size_t valid = 0;
    for (std::uint8_t& l : labels.pixels) l = l == 0 ? 0 : static_cast<std::uint8_t>(90 + (l * 53) % 166), valid += l != 0;
    write_png((fs::path(figures) / "render_room1_frame.png").string(), image);
    write_png((fs::path(figures) / "render_room1_labels.png").string(), labels);
    j["figure"] = {{"frame", figure_frame}, {"t", f.t}, {"labelled_pixels", valid}};
  }
  std::ofstream(out) << j.dump(2) << "\n";
  std::cerr << "wrote " << out << "\n";
}
