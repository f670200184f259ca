// slamkit vio --sim room1..room4|euroc:V1_01|euroc:V1_02|euroc:V2_03|FILE [--seed S]
//   [--dynamic none|low|high] [--duration S] [--trajectory OUT.tum] [--json OUT] [--plot OUT.svg]
// Runs the sliding-window visual-inertial estimator (docs/vio.md) on a named sequence simulated
// in memory (sim/visual_inertial_sequences.h, as `slamkit simulate --vi` does) or on a run
// written by `slamkit simulate --vi ... -o FILE`. Starts with the visual-inertial initializer
// (no ground truth after the first frame) unless --ground-truth-start.
// Prints a progress line every second of data; the JSON is an ATE run document (SE(3)
// alignment, the input of `slamkit report`) with the VIO keys of issue 12 on top.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <vector>

#include "cli_util.h"
#include "commands.h"
#include "slamkit/core/path_query.h"
#include "slamkit/eval/eval_plots.h"
#include "slamkit/eval/evaluation.h"
#include "slamkit/eval/run_json.h"
#include "slamkit/io/trajectory_io.h"
#include "slamkit/io/visual_inertial_sequence_io.h"
#include "slamkit/io/visual_inertial_sim_io.h"
#include "slamkit/vio/vio_sim_runner.h"
#include "vio_images.h"

namespace slamkit::cli {

namespace {

struct VioCliOptions {
  std::string sim, trajectory, json, plot, label, dynamic = "none", data;
  std::uint64_t seed = 1;
  double duration = 0.0;
  bool ground_truth_start = false;
  std::string dvi_startup = "on";        // DVI: the start-up SfM leaves out dynamic-flagged features
  double max_rotation_rms_deg = 2.0;     // start-up: SfM rotations against the gyroscope
  double max_scale_rel_sigma = 0.25;     // start-up: the scale's σ / scale
  int window = 10;
  int max_iterations = 4;  // measured: 4 beats 8 on ATE and time (docs/vio.md)
  int threads = 1;         // window solver threads (results identical for any count)
  bool quiet = false;
  std::string dvi = "off", alpha = "M^2", theta = "0.5", solver = "dense", static_ratio = "all";
  double outlier_px = 0.0;  // post-solve outlier rejection (VINS-Fusion); 0: off
  bool images = false;  // issue 13: the front end on rendered images (vio_images.h)
  VioImageCliOptions image;
};

VisualInertialSim load_visual_inertial_run(const VioCliOptions& o) {
  if (is_visual_inertial_sequence_name(o.sim)) {
    VisualInertialSimOptions opt;
    opt.seed = o.seed;
    opt.dynamic = parse_dynamic_level(o.dynamic);
    opt.duration = o.duration;
    return simulate_visual_inertial_sequence(o.sim, o.data, opt).sim;
  }
  if (path_exists(o.sim)) return read_visual_inertial_sim(o.sim);
  std::string names;
  for (const std::string& n : visual_inertial_sequence_names()) names += (names.empty() ? "" : ", ") + n;
  throw InputError(o.sim, 0, "sim", "neither a named sequence (" + names + ") nor a simulation file");
}

void run_vio(const VioCliOptions& o) {
  check_outputs({{&o.trajectory, "--trajectory"}, {&o.json, "--json"}, {&o.plot, "--plot"}, {&o.image.feature_log, "--feature-log"}});
  nlohmann::json frontend;
  VioImageCliOptions io = o.image;
  io.sim = o.sim, io.data = o.data, io.seed = o.seed, io.dynamic = o.dynamic, io.duration = o.duration, io.quiet = o.quiet;
  if (o.dvi != "on") {  // the baseline: the classifier only observes (scores); it never moves a track
    io.vio.frontend.affine_realign.enabled = false;
    io.vio.frontend.epipolar_search.enabled = false;
  }
  const VisualInertialSim sim =
      o.images ? image_vio_run(io, &frontend, o.json == "-" ? std::cerr : std::cout) : load_visual_inertial_run(o);
  VioStartupOptions startup;
  startup.use_ground_truth = o.ground_truth_start;
  startup.dvi_startup = o.dvi_startup == "on";
  startup.alignment.max_rotation_rms_deg = o.max_rotation_rms_deg;
  startup.alignment.max_scale_rel_sigma = o.max_scale_rel_sigma;
  SlidingWindowOptions so;
  so.window_size = o.window;
  so.max_iterations = o.max_iterations;
  so.num_threads = o.threads;
  so.dense_solver = o.solver == "dense";
  so.dvi.enabled = o.dvi == "on";
  parse_dvi_alpha(o.alpha, &so.dvi);  // DVI weighting (issue 13): used with --dvi on
  parse_dvi_theta(o.theta, &so.dvi);
  so.dvi.ratio_of_classified = o.static_ratio == "classified";
  so.outlier_reprojection_px = o.outlier_px;
  std::ostream& log = o.json == "-" ? std::cerr : std::cout;
  log << "vio: " << sim.source << ", " << sim.frames.size() << " frames, " << sim.imu.size() << " IMU samples, camera "
      << sim.camera->model_name() << ", window " << so.window_size << " keyframes\n";
  double next_report = sim.frames.front().t + 1.0;
  const VioRunResult r = run_vio_on_sim(sim, so, [&](std::size_t k, std::size_t n, const FrameEstimate& e) {
    if (o.quiet || e.stamp < next_report) return;
    next_report += 1.0;
    char line[200];
    std::snprintf(line, sizeof line, "  frame %5zu/%zu  t %8.2f s  keyframe %-3s  features %3d  solve %6.2f ms  marg %6.2f ms  p %.2f %.2f %.2f\n",
                  k, n, e.stamp - sim.frames.front().t, e.keyframe ? "yes" : "no", e.features, e.solve_ms,
                  e.marginalization_ms, e.state.p.x(), e.state.p.y(), e.state.p.z());
    log << line << std::flush;
  }, startup);

  EvalOptions ate;
  ate.kind = MetricKind::kAte;
  ate.align = AlignmentMode::kSe3;
  const EvalResult a = evaluate(r.estimate, r.truth, ate);
  EvalOptions rpe = ate;
  rpe.kind = MetricKind::kRpe;
  rpe.align = AlignmentMode::kNone;
  rpe.rpe.delta = 1.0;
  rpe.rpe.delta_unit = DeltaUnit::kSeconds;
  const EvalResult p = evaluate(r.estimate, r.truth, rpe);

  RunSource src;
  src.label = o.label.empty() ? "vio " + sim.source : o.label;
  src.est_path = o.trajectory.empty() ? "(vio estimate)" : o.trajectory;
  src.est_format = "tum";
  src.ref_path = sim.source + " (simulated truth)";
  src.ref_format = "tum";
  src.est_poses = r.estimate.size(), src.ref_poses = r.truth.size();
  nlohmann::json j = eval_result_to_json(a, src);
  double sum_ms = 0.0, max_ms = 0.0, solve_ms = 0.0, marg_ms = 0.0, max_solve = 0.0, max_marg = 0.0;
  for (const FrameEstimate& e : r.frames) {
    const double t = e.solve_ms + e.marginalization_ms;
    sum_ms += t, max_ms = std::max(max_ms, t);
    solve_ms += e.solve_ms, marg_ms += e.marginalization_ms;
    max_solve = std::max(max_solve, e.solve_ms), max_marg = std::max(max_marg, e.marginalization_ms);
  }
  const double nf = std::max<std::size_t>(1, r.frames.size());
  double m_sum = 0.0, m_min = 1.0;
  std::size_t dropped = 0, iterations = 0, outliers = 0;
  for (const FrameEstimate& e : r.frames) iterations += e.iterations, outliers += e.outliers_rejected;
  for (const FrameEstimate& e : r.frames) m_sum += e.static_ratio, m_min = std::min(m_min, e.static_ratio), dropped += e.visual_dropped;
  j["slamkit_version"] = SLAMKIT_VERSION;
  j["vio"] = {{"source", sim.source}, {"seed", sim.seed}, {"dynamic", to_string(sim.dynamic)},
              {"window_size", so.window_size}, {"camera", sim.camera->model_name()}};
  j["ate_rmse"] = a.translation_stats.rmse;
  j["rpe_rmse"] = p.translation_stats.rmse;
  j["realtime_factor"] = r.sequence_duration_s / std::max(1e-9, r.wall_time_s);
  j["realtime_factor_cpu"] = r.sequence_duration_s / std::max(1e-9, r.cpu_time_s);  // shared machines
  j["wall_time_s"] = r.wall_time_s;
  j["cpu_time_s"] = r.cpu_time_s;
  j["keyframes"] = r.keyframes;
  j["features_per_frame"] = r.features_per_frame;
  j["time_per_frame_ms"] = {{"mean", sum_ms / nf}, {"max", max_ms}};
  j["solve_time_per_frame_ms"] = {{"mean", solve_ms / nf}, {"max", max_solve}};
  j["marginalization_time_per_frame_ms"] = {{"mean", marg_ms / nf}, {"max", max_marg}};
  j["initialized_at_s"] = r.initialized_at_s;
  j["solver"] = o.solver;
  j["threads"] = o.threads;
  j["iterations_per_keyframe"] = static_cast<double>(iterations) / std::max<std::size_t>(1, r.keyframes);
  j["dvi"] = {{"enabled", so.dvi.enabled}, {"alpha", o.alpha}, {"theta", o.theta}, {"static_ratio", o.static_ratio}};
  j["static_ratio"] = {{"mean", m_sum / nf}, {"min", m_min}};
  j["visual_frames_dropped"] = dropped;
  j["outlier_rejection"] = {{"reprojection_px", so.outlier_reprojection_px}, {"features_rejected", outliers}};
  // M per frame (front-end flags, either mode) and its stretches below θ (the fixed θ).
  std::vector<double> m_frames;
  std::size_t below = 0, run = 0, longest = 0, stretches = 0;
  for (const FrameEstimate& e : r.frames) {
    m_frames.push_back(std::round(1e3 * e.static_ratio) * 1e-3);
    const bool low = e.static_ratio < so.dvi.theta;
    below += low, stretches += low && run == 0;
    run = low ? run + 1 : 0, longest = std::max(longest, run);
  }
  j["static_ratio_frames"] = m_frames;
  j["frames_static_below_theta"] = {{"frames", below}, {"stretches", stretches}, {"longest_frames", longest}};
  if (o.images) {
    j["frontend"] = frontend;
    j["dynamic_precision"] = frontend["dynamic_precision"];
    j["dynamic_recall"] = frontend["dynamic_recall"];
    // Tracking + classification + window, process CPU time (rendering or PNG reading apart).
    const double cpu = frontend["frontend_cpu_ms_per_frame"].get<double>() * 1e-3 * nf + r.cpu_time_s;
    j["dvi_pipeline_cpu_ms_per_frame"] = 1e3 * cpu / nf;
    j["dvi_pipeline_realtime_factor_cpu"] = r.sequence_duration_s / std::max(1e-9, cpu);
  }
  const VioStartupReport& su = r.startup;
  j["initialization"] = {{"method", su.method}, {"message", su.message}, {"attempts", su.attempts},
                         {"window_frames", su.window_frames}, {"window_start_s", su.window_start_s},
                         {"window_end_s", su.window_end_s}, {"scale_error", su.scale_error},
                         {"gravity_error_deg", su.gravity_error_deg}, {"velocity_error_mps", su.velocity_error},
                         {"gyro_bias_error", su.gyro_bias_error}, {"rotation_rms_deg", su.rotation_rms_deg},
                         {"scale_rel_sigma", su.scale_rel_sigma},
                         {"dynamic_left_out", su.dynamic_left_out}};
  char line[240];
  std::snprintf(line, sizeof line,
                "ATE RMSE %.4f m (SE(3) alignment), RPE RMSE %.4f m over 1 s, %zu keyframes, %.1f features/frame,"
                " %.2f ms/frame (max %.2f), %.1fx real time (%.1fx in CPU time)\n",
                a.translation_stats.rmse, p.translation_stats.rmse, r.keyframes, r.features_per_frame, sum_ms / nf,
                max_ms, j["realtime_factor"].get<double>(), j["realtime_factor_cpu"].get<double>());
  log << line;
  std::snprintf(line, sizeof line, "start-up: %s at %.2f s (%d windows tried): %s\n", su.method.c_str(),
                r.initialized_at_s, su.attempts, su.message.c_str());
  log << line;
  if (!o.trajectory.empty()) write_trajectory(o.trajectory, r.estimate, TrajectoryFormat::kTum);
  if (!o.json.empty()) write_json(o.json, j);
  if (!o.plot.empty()) {
    const EvalRunData data = eval_run_from_json(j, o.plot);
    write_file_atomically(o.plot, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n" + eval_figure(data).str(), "plot");
  }
}

}  // namespace

void add_vio_command(CLI::App& app) {
  CLI::App* sub = app.add_subcommand("vio", "sliding-window visual-inertial odometry on a simulated run (docs/vio.md)");
  auto o = std::make_shared<VioCliOptions>();
  sub->add_option("--sim", o->sim,
                  "room1..room4, euroc:V1_01, euroc:V1_02, euroc:V2_03 (simulated in memory) or a file written by "
                  "`slamkit simulate --vi ... -o FILE`")
      ->required();
  sub->add_option("--seed", o->seed, "random seed of a named sequence")->capture_default_str();
  sub->add_option("--dynamic", o->dynamic, "moving groups of a named sequence: none, low or high")
      ->check(CLI::IsMember({"none", "low", "high"}))
      ->capture_default_str();
  sub->add_option("--duration", o->duration, "seconds of a named sequence from its start (0: all)")
      ->check(cli::NonNegativeNumber);
  sub->add_option("--data", o->data, "datasets folder (default: $SLAMKIT_DATA or ../shared/datasets)");
  sub->add_flag("--ground-truth-start", o->ground_truth_start,
                "start from the true state at the first moving frame instead of the initializer (comparison)");
  sub->add_option("--dvi-startup", o->dvi_startup, "with --dvi on: the start-up SfM leaves out dynamic-flagged features")
      ->check(CLI::IsMember({"on", "off"}))->capture_default_str();
  sub->add_option("--max-rotation-rms", o->max_rotation_rms_deg,
                  "start-up: refuse a window whose SfM rotations disagree with the gyroscope by more (RMS, deg; 0: off)")
      ->check(cli::NonNegativeNumber)->capture_default_str();
  sub->add_option("--max-scale-sigma", o->max_scale_rel_sigma,
                  "start-up: refuse a window whose scale has a larger relative standard deviation (0: off)")
      ->check(cli::NonNegativeNumber)->capture_default_str();
  sub->add_option("--window", o->window, "keyframes in the window")->check(CLI::Range(2, 100))->capture_default_str();
  sub->add_option("--max-iterations", o->max_iterations, "LM iterations per keyframe")->check(CLI::Range(1, 100))
      ->capture_default_str();
  sub->add_option("--threads", o->threads, "threads of the window solver (same result for any count)")
      ->check(CLI::Range(1, 64))->capture_default_str();
  sub->add_option("--trajectory", o->trajectory, "write the estimate (TUM format)");
  sub->add_option("--json", o->json, "write the run as JSON ('-': stdout); input of `slamkit report`");
  sub->add_option("--plot", o->plot, "write an SVG figure (trajectory and ATE)");
  sub->add_option("--label", o->label, "name of the run in reports");
  sub->add_flag("--quiet", o->quiet, "no progress lines");
  sub->add_option("--dvi", o->dvi, "DVI: drop dynamic features, weigh a frame's vision by alpha(M)")
      ->check(CLI::IsMember({"on", "off"}))->capture_default_str();
  sub->add_option("--alpha", o->alpha, "DVI weight of a frame's vision: 1, M or M^k (M = static/all)")->capture_default_str();
  sub->add_option("--theta", o->theta, "DVI: frames with M below this keep no vision (a number, adaptive[:BASE,PER_GROUP,MAX])")
      ->capture_default_str();
  sub->add_option("--static-ratio", o->static_ratio,
                  "DVI: M = static / all features of a frame, or static / classified (new, untested tracks left out)")
      ->check(CLI::IsMember({"all", "classified"}))->capture_default_str();
  sub->add_option("--outlier-px", o->outlier_px,
                  "after each window solve remove features whose mean reprojection error exceeds this [px] (0: off)")
      ->check(cli::NonNegativeNumber)->capture_default_str();
  sub->add_option("--solver", o->solver, "window solver: dense (vio/dense_window_solver.h) or generic (the Optimizer)")
      ->check(CLI::IsMember({"dense", "generic"}))->capture_default_str();
  sub->add_flag("--images", o->images, "render the frames and run the DVI front end on their pixels (docs/frontend.md)");
  sub->add_option("--image-dir", o->image.image_dir, "with --images: read the frames from `simulate --images DIR` instead");
  sub->add_option("--baseline-frames", o->image.vio.frontend.baseline_frames, "with --images: epipolar test over k frames")
      ->check(CLI::Range(1, 50))->capture_default_str();
  sub->add_option("--sticky", o->image.vio.frontend.sticky_dynamic, "with --images: a track flagged dynamic stays so")
      ->capture_default_str();
  sub->add_option("--baseline-threshold-exponent", o->image.vio.frontend.baseline_threshold_exponent,
                  "with --images: threshold on the k-frame baseline = threshold * k^e")->check(CLI::Range(0.0, 1.0))->capture_default_str();
  sub->add_option("--consistency-checks", o->image.vio.frontend.consistency_checks,
                  "with --images: a track keeps its last N epipolar tests")->check(CLI::Range(1, 16))->capture_default_str();
  sub->add_option("--consistency-hits", o->image.vio.frontend.consistency_hits,
                  "with --images: dynamic iff at least H of them exceed the threshold")->check(CLI::Range(1, 16))->capture_default_str();
  sub->add_option("--min-patch-ncc", o->image.vio.frontend.tracker.min_patch_ncc,
                  "with --images: lose tracks whose patch NCC with the previous frame is below this (-1: off)")
      ->check(CLI::Range(-1.0, 1.0))->capture_default_str();
  sub->add_option("--min-patch-ncc-first", o->image.vio.frontend.min_patch_ncc_first,
                  "with --images: reject tracks whose patch NCC against their first frame is below this (-1: off)")
      ->check(CLI::Range(-1.0, 1.0))->capture_default_str();
  sub->add_option("--min-patch-ncc-baseline", o->image.vio.frontend.min_patch_ncc_baseline,
                  "with --images: reject tested tracks whose patch NCC over the baseline is below this (-1: off)")
      ->check(CLI::Range(-1.0, 1.0))->capture_default_str();
  sub->add_option("--ambiguity", o->image.vio.frontend.tracker.ambiguity_px,
                  "with --images: KLT ambiguity check distance (px; 0: off)")->check(cli::NonNegativeNumber)->capture_default_str();
  sub->add_option("--ambiguity-ratio", o->image.vio.frontend.tracker.ambiguity_ratio,
                  "with --images: KLT ambiguity residual ratio")->check(CLI::Range(0.0, 1.0))->capture_default_str();
  sub->add_option("--epipolar-threshold", o->image.vio.frontend.filter.threshold_px, "with --images: dynamic above (px)")
      ->check(cli::PositiveNumber)->capture_default_str();
  sub->add_option("--pixel-sigma", o->image.vio.pixel_sigma, "with --images: sigma of the tracks in the window (px)")
      ->check(cli::PositiveNumber)->capture_default_str();
  sub->add_option("--trusted-model", o->image.vio.frontend.trusted_model,
                  "with --images: fit the camera motion on the tracks static in their last test")->capture_default_str();
  sub->add_option("--trusted-min-tests", o->image.vio.frontend.trusted_min_tests,
                  "with --images: tests a track needs to be trusted")->check(CLI::Range(1, 16))->capture_default_str();
  sub->add_option("--trust-contest", o->image.vio.frontend.trust_contest_ratio,
                  "with --images: the trusted model gives way when the model of the tracks it flags passes this many "
                  "times as many matches (0: off)")->check(cli::FiniteRange(0.0, 1000.0))->capture_default_str();
  sub->add_option("--trust-contest-frames", o->image.vio.frontend.trust_contest_frames,
                  "with --images: the contest runs within this many frames of a cold start (< 0: always)")
      ->check(CLI::Range(-1, 1000000))->capture_default_str();
  sub->add_option("--young-trust-majority", o->image.vio.frontend.young_trust_majority,
                  "with --images: within --trust-contest-frames of a cold start, a frame's flags claim movers only "
                  "when its static features outnumber them --trust-contest times")->capture_default_str();
  sub->add_option("--mover-grace", o->image.vio.frontend.mover_grace_claims,
                  "with --images: a track claimed as a mover in each of its last N frames keeps its flag through one "
                  "test under the threshold (0: off)")->check(CLI::Range(0, 1000))->capture_default_str();
  sub->add_option("--group-turned-support", o->image.vio.frontend.groups.turned_min_support,
                  "with --images: a flag on a track static in its last --group-turned-tests tests needs this many "
                  "other flags near it")->check(CLI::Range(0, 1000))->capture_default_str();
  sub->add_option("--group-turned-tests", o->image.vio.frontend.groups.turned_static_tests,
                  "with --images: static tests in a row that make a newly flagged track 'turned'")
      ->check(CLI::Range(1, 16))->capture_default_str();
  sub->add_option("--min-trusted-matches", o->image.vio.frontend.filter.min_trusted_matches,
                  "with --images: fewer trusted matches: fit on all")->check(cli::NonNegativeNumber)->capture_default_str();
  sub->add_option("--refine-essential", o->image.vio.frontend.filter.refine_essential,
                  "with --images: refine E by robust least squares on the bearings")->capture_default_str();
  sub->add_option_function<std::string>(
         "--imu-rotation", [o](const std::string& v) { o->image.vio.frontend.filter.known_rotation = v == "on"; },
         "with --images: epipolar test with the gyroscope's rotation, only the translation fitted (2-point RANSAC) [on]")
      ->check(CLI::IsMember({"on", "off"}));
  sub->add_option_function<std::string>(
         "--cheirality", [o](const std::string& v) { o->image.vio.frontend.filter.cheirality = v == "on"; },
         "with --imu-rotation on: also flag a feature whose bearing lies behind R b1 on its epipolar circle "
         "(a negative depth for a static point) by more than the threshold [on]")
      ->check(CLI::IsMember({"on", "off"}));
  sub->add_option_function<std::string>(
         "--gyro-klt", [o](const std::string& v) { o->image.vio.frontend.tracker.gyro_klt = parse_gyro_klt(v); },
         "with --images: seed KLT with the gyroscope's rotation (infinite-depth prediction): off, seed (= on: "
         "replaces the zero-flow start) or candidate (added to the zero-flow and median-flow starts) [off]")
      ->check(CLI::IsMember({"on", "off", "seed", "candidate"}));
  sub->add_option("--rotation-prior-sigma", o->image.vio.frontend.filter.rotation_prior_sigma_rad,
                  "with --imu-rotation on and --refine-essential: sigma of the prior letting the refinement move R "
                  "(rad; 0: R held)")->check(cli::NonNegativeNumber)->capture_default_str();
  sub->add_option("--pure-rotation-share", o->image.vio.frontend.filter.pure_rotation_share,
                  "with --imu-rotation on: translation undefined when this share of the matches fits the rotation alone")
      ->check(CLI::Range(0.01, 1.0))->capture_default_str();
  sub->add_option("--epipolar-search", o->image.vio.frontend.epipolar_search.enabled,
                  "with --images: re-search dynamic-flagged features along their epipolar line before the flag counts")
      ->capture_default_str();
  sub->add_option("--epipolar-search-range", o->image.vio.frontend.epipolar_search.search_half_px,
                  "with --images --epipolar-search: 1-D seeds up to this far along the line (px; 0: nearest point only)")
      ->check(CLI::Range(0.0, 256.0))->capture_default_str();
  sub->add_option("--epipolar-search-ncc-drop", o->image.vio.frontend.epipolar_search.max_ncc_drop,
                  "with --images --epipolar-search: re-found iff its patch NCC >= the track's minus this")
      ->check(CLI::Range(0.0, 2.0))->capture_default_str();
  sub->add_option("--epipolar-search-min-ncc", o->image.vio.frontend.epipolar_search.min_ncc,
                  "with --images --epipolar-search: and its patch NCC >= this")->check(CLI::Range(-1.0, 1.0))->capture_default_str();
  sub->add_option("--affine-realign", o->image.vio.frontend.affine_realign.enabled,
                  "with --images: align each dynamic-flagged feature's patch over its test's baseline by an affine warp "
                  "(ECC) before the flag counts; the track moves there")
      ->capture_default_str();
  sub->add_option("--affine-min-correlation", o->image.vio.frontend.affine_realign.min_correlation,
                  "with --images --affine-realign: the alignment's normalized correlation must reach this")
      ->check(cli::FiniteRange(-1.0, 1.0))->capture_default_str();
  sub->add_option("--affine-refit", o->image.vio.frontend.affine_realign.refit_model,
                  "with --images --affine-realign: fit the camera's motion again when features turn static, and "
                  "re-align what it flags")
      ->capture_default_str();
  sub->add_option("--affine-static-ratio", o->image.vio.frontend.affine_realign.static_distance_ratio,
                  "with --images --affine-realign: a realigned feature turns static at most this fraction of the threshold "
                  "off its epipolar line")
      ->check(cli::FiniteRange(0.0, 1.0, true))->capture_default_str();
  add_dynamic_group_options(sub, &o->image.vio.frontend.groups, "with --images: ");
  sub->add_option("--score-min-distance", o->image.vio.score_min_distance_m,
                  "with --images: score only objects at least this far from the camera (m; issue 13: 2)")
      ->check(cli::NonNegativeNumber)->capture_default_str();
  sub->add_option("--score-max-distance", o->image.vio.score_max_distance_m,
                  "with --images: score only objects at most this far from the camera (m; issue 13: 6)")
      ->check(cli::NonNegativeNumber)->capture_default_str();
  sub->add_option("--score-patch-half", o->image.vio.score_patch_half_size_px,
                  "with --images: half side of the scoring label patch (px; -1: the KLT window's half, 0: centre pixel)")
      ->check(CLI::Range(-1, 50))->capture_default_str();
  sub->add_option("--klt-window", o->image.vio.frontend.tracker.klt_window, "with --images: KLT window side (px)")
      ->check(CLI::Range(3, 101))->capture_default_str();
  sub->add_option("--klt-levels", o->image.vio.frontend.tracker.klt_pyramid_levels,
                  "with --images: KLT pyramid levels above the full image")->check(CLI::Range(0, 8))->capture_default_str();
  sub->add_option_function<std::string>(
         "--rlof-refine", [o](const std::string& v) { o->image.vio.frontend.tracker.rlof_refine = parse_rlof_refine(v); },
         "with --images: refine by robust local optical flow (RLOF: cross-based support region, M-estimator): off, "
         "track (= on: the tracks) or test (only the positions the epipolar test reads) [track]")
      ->check(CLI::IsMember({"off", "on", "track", "test"}));
  sub->add_option("--feature-log", o->image.feature_log, "with --images: write every scored feature to this CSV");
  sub->add_option("--render-threads", o->image.threads, "with --images: renderer threads (0: all)");
  sub->callback([o]() { run_vio(*o); });
}

}  // namespace slamkit::cli
