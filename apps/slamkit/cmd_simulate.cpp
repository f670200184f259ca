// slamkit simulate --vi room1|...|euroc:V1_01|FILE.tum: fits a B-spline to a real path, runs
// the visual-inertial simulator on it (TUM-VI fisheye and IMU noise, or EuRoC radtan for the
// euroc: paths) and writes the run in the slamkit simulation format (docs/formats.md), with a
// summary, JSON (--json), the true trajectory at the camera times (--truth, TUM) and a top
// view of the room (--plot, SVG). With --images DIR it also renders the grayscale images and
// per-pixel labels of the run (sim/image_renderer.h) into an EuRoC/ASL folder (vio/image_io.h).
// See docs/simulator.md.
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli_util.h"
#include "commands.h"
#include "slamkit/eval/svg.h"
#include "slamkit/io/trajectory_io.h"
#include "slamkit/io/visual_inertial_sequence_io.h"
#include "slamkit/io/visual_inertial_sim_io.h"
#include "slamkit/sim/image_renderer.h"
#include "slamkit/sim/visual_inertial_sim.h"
#include "slamkit/vio/image_io.h"

namespace slamkit::cli {
namespace {

namespace fs = std::filesystem;

struct SimulateArgs {
  std::string vi, output, json, truth, plot, dynamic = "none", data, images;
  std::uint64_t seed = 1;
  int threads = 0;
  double duration = 0.0, knot_spacing = 0.1;
};

// Top view (x–y) of the room: walls as the box outline, static landmarks, the path and the
// moving groups' walks.
void write_plot(const VisualInertialSim& sim, const std::string& path) {
  Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const auto& l : sim.landmarks)
    if (l.group < 0) lo = lo.cwiseMin(l.position.head<2>()), hi = hi.cwiseMax(l.position.head<2>());
  const double W = 720, margin = 40, scale = (W - 2 * margin) / std::max(hi.x() - lo.x(), hi.y() - lo.y());
  const double H = 2 * margin + scale * (hi.y() - lo.y()) + 40;
  const auto X = [&](double x) { return margin + scale * (x - lo.x()); };
  const auto Y = [&](double y) { return H - 40 - margin - scale * (y - lo.y()) + 0.0; };
  SvgWriter svg(W, H);
  svg.rect(0, 0, W, H, "#ffffff");
  SvgWriter::Text title;
  title.size = 14, title.bold = true;
  svg.text(margin, 24, "slamkit simulate: " + sim.source + " (dynamic " + to_string(sim.dynamic) + ", seed " +
                           std::to_string(sim.seed) + "), top view", title);
  SvgWriter::Stroke wall{"#444444", 1.5};
  svg.rect(X(lo.x()), Y(hi.y()), scale * (hi.x() - lo.x()), scale * (hi.y() - lo.y()), "none", &wall);
  svg.begin_group("landmarks");
  for (const auto& l : sim.landmarks)
    if (l.group < 0 && l.id % 3 == 0) svg.circle(X(l.position.x()), Y(l.position.y()), 1.2, "#9a9a9a");
  svg.end_group();
  svg.begin_group("groups");
  for (const auto& g : sim.groups) {
    const Eigen::Vector3d a = g.pose(g.t_on).translation(), b = g.pose(g.t_off).translation();
    svg.line(X(a.x()), Y(a.y()), X(b.x()), Y(b.y()), SvgWriter::Stroke{"#d62728", 2.0, "", 0.6});
    svg.circle(X(b.x()), Y(b.y()), 3.0, "#d62728");
  }
  svg.end_group();
  std::vector<Point2> pts;
  for (const auto& x : sim.imu_truth) pts.emplace_back(X(x.p_world.x()), Y(x.p_world.y()));
  svg.begin_group("path");
  svg.polyline(pts, SvgWriter::Stroke{"#1f77b4", 1.6}, 2.0);
  svg.end_group();
  SvgWriter::Text legend;
  legend.size = 11;
  svg.text(margin, H - 16, "blue: IMU path · grey: static landmarks (every 3rd) · red: moving groups (walk, end dot) · box: walls; " +
                               std::to_string(static_cast<int>(std::round(hi.x() - lo.x()))) + " m × " +
                               std::to_string(static_cast<int>(std::round(hi.y() - lo.y()))) + " m", legend);
  write_file_atomically(path, svg.str(), "plot");
}

// Renders every frame of the run into an EuRoC/ASL folder, with a progress line; returns the
// rendering time per frame [ms] (without PNG writing) and the total time [s].
std::pair<double, double> render_images(const VisualInertialSim& sim, const BSplineTrajectory& spline,
                                        const VisualInertialSimOptions& opt, const VisualInertialSequence& src, int threads,
                                        ImageSequenceWriter* writer) {
  const Stopwatch clock;
  const RenderedScene scene = build_rendered_scene(sim, spline, opt);
  ImageRendererOptions ro;
  ro.seed = opt.seed;
  ro.mask_radius_px = src.mask_radius_px;
  const ImageRenderer renderer(scene, *sim.camera, ro);
  const ThreadPool pool(threads);
  std::cerr << "simulate: rendering " << sim.frames.size() << " frames (" << renderer.width() << "x" << renderer.height()
            << ", " << scene.furniture.size() << " furniture boxes, " << scene.walkers.size() << " walkers, "
            << pool.threads() << " threads) into " << writer->root() << "\n";
  GrayImage image, labels;
  double render_seconds = 0.0;
  for (std::size_t k = 0; k < sim.frames.size(); ++k) {
    const SimFrame& f = sim.frames[k];
    const Stopwatch frame_clock;
    renderer.render(f.t, frame_camera_pose(sim, f), &image, &labels, &pool);
    render_seconds += frame_clock.seconds();
    writer->add_frame(f.t, image, &labels);
    if (k % 20 == 0 || k + 1 == sim.frames.size()) {
      const double done = static_cast<double>(k + 1) / sim.frames.size();
      const int bar = static_cast<int>(30 * done);
      std::cerr << "\r  [" << std::string(bar, '#') << std::string(30 - bar, '.') << "] " << (k + 1) << "/"
                << sim.frames.size() << std::fixed << std::setprecision(1) << "  " << 1e3 * render_seconds / (k + 1)
                << " ms/frame render, ETA " << clock.seconds() / done * (1 - done) << " s   " << std::flush;
    }
  }
  std::cerr << "\n";
  writer->write_imu(sim.imu);
  writer->write_groundtruth(sim.imu_truth);
  writer->write_objects(scene);
  writer->finish();
  namespace fs = std::filesystem;
  fs::copy_file(src.camchain, fs::path(writer->root()) / "camchain.yaml", fs::copy_options::overwrite_existing);
  fs::copy_file(src.imu, fs::path(writer->root()) / "imu.yaml", fs::copy_options::overwrite_existing);
  Trajectory truth;
  for (const SimFrame& f : sim.frames) truth.push_back_ns(stamp_ns(f.t), SE3(SO3(f.truth.q_world_imu), f.truth.p_world));
  write_trajectory((fs::path(writer->root()) / "groundtruth.tum").string(), truth, TrajectoryFormat::kTum);
  return {sim.frames.empty() ? 0.0 : 1e3 * render_seconds / sim.frames.size(), clock.seconds()};
}

void run(const SimulateArgs& a) {
  check_outputs({{&a.output, "-o"}, {&a.json, "--json"}, {&a.truth, "--truth"}, {&a.plot, "--plot"}});
  if (a.output.empty() && a.images.empty()) throw InputError("", 0, "output", "give -o FILE, --images DIR or both");
  const Stopwatch clock;
  VisualInertialSimOptions opt;
  opt.seed = a.seed;
  opt.dynamic = parse_dynamic_level(a.dynamic);
  opt.duration = a.duration;
  std::unique_ptr<ImageSequenceWriter> writer;
  if (!a.images.empty()) writer = std::make_unique<ImageSequenceWriter>(a.images);  // fails before any work
  std::cerr << "simulate: fitting a cubic B-spline (knots every " << a.knot_spacing << " s) to the path of " << a.vi
            << " and simulating the camera and the IMU\n";
  const SequenceSimulation run = simulate_visual_inertial_sequence(a.vi, a.data, opt, a.knot_spacing);
  const VisualInertialSim& sim = run.sim;
  const BSplineFitReport& fit = run.fit;
  std::cerr << "simulate: " << run.sequence.trajectory.string() << ": " << fit.samples << " poses, " << fit.control_points
            << " control points, fit RMSE " << 1e3 * fit.position_rmse << " mm / " << fit.rotation_rmse * 180 / M_PI
            << " deg; " << run.camera_name << " (" << run.distortion_model << ")\n";
  const SimSummary s = summarize(sim);
  if (!a.output.empty()) write_visual_inertial_sim(a.output, sim);
  std::pair<double, double> render_time{0.0, 0.0};
  if (writer) render_time = render_images(sim, *run.spline, run.options, run.sequence, a.threads, writer.get());
  if (!a.truth.empty()) {
    Trajectory truth;
    for (const SimFrame& f : sim.frames) {
      TrajectorySample x;
      x.stamp = f.t;
      x.T_world_body = SE3(SO3(f.truth.q_world_imu), f.truth.p_world);
      truth.push_back(x);
    }
    write_trajectory(a.truth, truth, TrajectoryFormat::kTum);
  }
  if (!a.plot.empty()) write_plot(sim, a.plot);
  const double seconds = clock.seconds();
  std::cout << std::fixed << std::setprecision(3) << "simulated " << a.vi << " (dynamic " << a.dynamic << ", seed " << a.seed
            << ") -> " << (a.output.empty() ? a.images : a.output) << "\n"
            << "  duration          " << s.duration << " s, " << s.frames << " frames (20 Hz), " << s.imu_samples
            << " IMU samples\n"
            << "  features/frame    mean " << std::setprecision(1) << s.features_per_frame_mean << ", min "
            << s.features_per_frame_min << "; " << s.tracks << " tracks, " << s.mean_track_length << " frames long\n"
            << std::setprecision(3) << "  dynamic share     " << s.dynamic_share << " of observations; static ratio M mean "
            << s.static_ratio_mean << ", min " << s.static_ratio_min << "; frames with dynamic features "
            << s.frames_with_dynamic << ", with M < 0.9 / 0.7 / 0.5: " << s.frames_static_below_09 << " / "
            << s.frames_static_below_07 << " / " << s.frames_static_below_half << "\n"
            << "  landmarks         " << s.static_landmarks << " static, " << s.dynamic_landmarks << " in " << s.groups
            << " moving groups\n"
            << "  spline fit        RMSE " << 1e3 * fit.position_rmse << " mm (max " << 1e3 * fit.position_max << "), "
            << fit.rotation_rmse * 180 / M_PI << " deg (max " << fit.rotation_max * 180 / M_PI << ")\n"
            << "  time              " << seconds << " s\n";
  if (writer)
    std::cout << std::setprecision(1) << "  images            " << s.frames << " frames in " << a.images << " (mav0/cam0, labels0), "
              << render_time.first << " ms/frame rendering, " << render_time.second << " s with PNG writing\n";
  if (!a.json.empty()) {
    nlohmann::json j;
    j["kind"] = "simulate";
    j["schema"] = 1;
    j["source"] = a.vi;
    j["path"] = run.sequence.trajectory.string();
    j["output"] = a.output;
    j["seed"] = a.seed;
    j["dynamic"] = a.dynamic;
    j["camera"] = {{"model", run.distortion_model}, {"width", run.width}, {"height", run.height},
                   {"mask_radius_px", run.sequence.mask_radius_px}};
    j["duration_s"] = s.duration;
    j["frames"] = s.frames;
    j["imu_samples"] = s.imu_samples;
    j["features_per_frame"] = {{"mean", s.features_per_frame_mean}, {"min", s.features_per_frame_min}};
    j["tracks"] = s.tracks;
    j["mean_track_length"] = s.mean_track_length;
    j["dynamic_share"] = s.dynamic_share;
    j["static_ratio"] = {{"mean", s.static_ratio_mean}, {"min", s.static_ratio_min}};
    j["frames_with_dynamic"] = s.frames_with_dynamic;
    j["frames_static_below"] = {{"0.5", s.frames_static_below_half}, {"0.7", s.frames_static_below_07},
                                {"0.9", s.frames_static_below_09}};
    j["landmarks"] = {{"static", s.static_landmarks}, {"dynamic", s.dynamic_landmarks}, {"groups", s.groups}};
    j["spline_fit"] = {{"knot_spacing_s", a.knot_spacing}, {"samples", fit.samples},
                       {"control_points", fit.control_points}, {"position_rmse_m", fit.position_rmse},
                       {"position_max_m", fit.position_max}, {"rotation_rmse_deg", fit.rotation_rmse * 180 / M_PI},
                       {"rotation_max_deg", fit.rotation_max * 180 / M_PI}};
    j["time_s"] = seconds;
    if (writer)
      j["images"] = {{"dir", a.images}, {"frames", s.frames}, {"render_ms_per_frame", render_time.first},
                     {"total_s", render_time.second}, {"threads", a.threads}};
    write_json(a.json, j);
  }
}

}  // namespace

void add_simulate_command(CLI::App& app) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* cmd = app.add_subcommand("simulate", "Simulate a visual-inertial run on a real path (docs/simulator.md)");
  cmd->add_option("--vi", args->vi, "room1..room4, euroc:V1_01, euroc:V1_02, euroc:V2_03, or a trajectory file (TUM, EuRoC CSV)")
      ->required();
  cmd->add_option("--seed", args->seed, "random seed")->capture_default_str();
  cmd->add_option("--dynamic", args->dynamic, "moving groups: none, low or high")
      ->check(CLI::IsMember({"none", "low", "high"}))
      ->capture_default_str();
  cmd->add_option("-o,--output", args->output, "simulation file to write (docs/formats.md)");
  cmd->add_option("--images", args->images, "render grayscale images and labels into this folder (EuRoC/ASL layout)");
  cmd->add_option("--threads", args->threads, "rendering threads (0: all cores)")->capture_default_str();
  cmd->add_option("--json", args->json, "summary as JSON");
  cmd->add_option("--truth", args->truth, "true IMU poses at the camera times (TUM)");
  cmd->add_option("--plot", args->plot, "top view of the room (SVG)");
  cmd->add_option("--duration", args->duration, "seconds from the start (0: the whole path)")->check(cli::NonNegativeNumber);
  cmd->add_option("--knot-spacing", args->knot_spacing, "B-spline knot spacing [s]")
      ->check(CLI::Range(0.01, 10.0))
      ->capture_default_str();
  cmd->add_option("--data", args->data, "datasets folder (default: $SLAMKIT_DATA or ../shared/datasets)");
  cmd->callback([args]() { run(*args); });
}

}  // namespace slamkit::cli
