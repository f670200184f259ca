// The image path of `slamkit vio` (see vio_images.h).
#include "vio_images.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <fstream>
#include <string>

#include "cli_util.h"
#include "slamkit/io/visual_inertial_sequence_io.h"
#include "slamkit/sim/visual_inertial_sequences.h"

namespace slamkit::cli {

void check_epipolar_search_input(const EpipolarSearchOptions& o, const char* option) {
  try {
    check_epipolar_search_options(o);
  } catch (const std::invalid_argument& e) {
    throw InputError(option, 0, "epipolar_search", e.what());
  }
}

void add_dynamic_group_options(CLI::App* sub, DynamicGroupOptions* groups, const std::string& scope) {
  sub->add_option("--group-support", groups->min_support,
                  scope + "a dynamic flag stands only with at least this many other flags near it (0: off)")
      ->check(CLI::Range(0, 1000))->capture_default_str();
  sub->add_option("--group-radius", groups->radius_factor,
                  scope + "the group rule's neighbourhood, in multiples of the detector's minimum feature distance (30 px)")
      ->check(FiniteRange(0.0, 100.0, true))->capture_default_str();
}

void check_affine_realign_input(const AffineRealignOptions& o) {
  try {
    check_affine_realign_options(o);
  } catch (const std::invalid_argument& e) {
    throw InputError("--affine-realign", 0, "affine_realign", e.what());
  }
}

VisualInertialSim image_vio_run(const VioImageCliOptions& o, nlohmann::json* frontend, std::ostream& log) {
  if (!is_visual_inertial_sequence_name(o.sim))
    throw InputError(o.sim, 0, "sim", "--images needs a named sequence (room1..room4, euroc:...): the renderer rebuilds its scene");
  const ImageFrontendOptions& fo = o.vio.frontend;
  if (fo.consistency_hits > fo.consistency_checks)
    throw InputError("--consistency-hits", 0, "consistency_hits",
                     std::to_string(fo.consistency_hits) + " hits of " + std::to_string(fo.consistency_checks) +
                         " checks: must be at most --consistency-checks");
  check_epipolar_search_input(fo.epipolar_search, "--epipolar-search-range");
  check_affine_realign_input(fo.affine_realign);
  if (!(o.vio.score_min_distance_m <= o.vio.score_max_distance_m))  // also NaN
    throw InputError("--score-min-distance", 0, "score_min_distance_m",
                     "the scored distance range [" + std::to_string(o.vio.score_min_distance_m) + ", " +
                         std::to_string(o.vio.score_max_distance_m) + "] m is empty or not a number");
  VisualInertialSimOptions opt;
  opt.seed = o.seed;
  opt.dynamic = parse_dynamic_level(o.dynamic);
  opt.duration = o.duration;
  const SequenceSimulation run = simulate_visual_inertial_sequence(o.sim, o.data, opt);
  const VisualInertialSim& sim = run.sim;
  const RenderedScene scene = build_rendered_scene(sim, *run.spline, run.options);
  ImageRendererOptions ro;
  ro.seed = run.options.seed;
  ro.mask_radius_px = run.sequence.mask_radius_px;
  const ImageRenderer renderer(scene, *sim.camera, ro);
  const ThreadPool pool(o.threads);
  ImageVioReport report;
  report.image_source = o.image_dir.empty() ? "rendered in memory" : o.image_dir;
  const FrameImageSource source = o.image_dir.empty() ? rendered_frames(sim, renderer, &pool) : folder_frames(sim, o.image_dir);
  log << "vio: front end on " << sim.frames.size() << " " << renderer.width() << "x" << renderer.height() << " images ("
      << report.image_source << ", " << scene.walkers.size() << " walkers), epipolar baseline "
      << o.vio.frontend.baseline_frames << " frames\n";
  const Stopwatch clock;
  ImageVioOptions vo = o.vio;
  std::ofstream feature_log;
  if (!o.feature_log.empty()) {
    feature_log.open(o.feature_log);
    if (!feature_log) throw InputError(o.feature_log, 0, "feature_log", "cannot write the file");
    feature_log << "frame,id,u,v,u_then,v_then,baseline,motion,distance_px,distance_1_px,hits,checks,truth,object_distance_m,scene_range_m,isolated,graced\n";
    feature_log.precision(9);
    // scene_range_m: the true range of the ray through the feature at frame k (the renderer's nearest hit).
    vo.on_scored = [&feature_log, &sim, &renderer](std::size_t k, const FrontendFeature& f, int truth, double d) {
      const SimFrame& frame = sim.frames.at(k);
      const RayHit hit = renderer.cast(frame.t, frame_camera_pose(sim, frame), f.uv);
      feature_log << k << ',' << f.id << ',' << f.uv.x() << ',' << f.uv.y() << ',' << f.uv_then.x() << ',' << f.uv_then.y()
                  << ',' << f.baseline << ',' << to_string(f.motion) << ',' << f.distance_px << ',' << f.distance_1_px << ',' << f.hits << ','
                  << f.checks << ',' << truth << ',' << d << ',' << (hit.hit ? hit.distance : std::nan(""))
                  << ',' << (f.isolated ? 1 : 0) << ',' << (f.graced ? 1 : 0) << '\n';
    };
  }
  VisualInertialSim tracked = track_images(sim, source, walker_speeds(scene), walker_distances(scene, sim), vo, &report,
                                           [&](std::size_t k, std::size_t n) {
    if (o.quiet || (k % 100 != 0 && k + 1 != n)) return;
    char line[160];
    std::snprintf(line, sizeof line, "  front end %5zu/%zu  %.1f s elapsed\n", k + 1, n, clock.seconds());
    log << line << std::flush;
  });
  const DetectionScore& s = report.score;
  const DetectionScore& c = report.score_centre;
  const DetectionScore& a = report.score_all_distances;
  const double cpu_frontend_s = report.frontend_cpu_s;
  const double duration = sim.frames.back().t - sim.frames.front().t;
  *frontend = {{"kind", "frontend"},
               {"image_source", report.image_source},
               {"frames", report.frames},
               {"features_per_frame", report.features_per_frame},
               {"baseline_frames", o.vio.frontend.baseline_frames},
               {"sticky_dynamic", o.vio.frontend.sticky_dynamic},
               {"threshold_px", o.vio.frontend.filter.threshold_px},
               {"pixel_sigma", o.vio.pixel_sigma},
               {"baseline_threshold_exponent", o.vio.frontend.baseline_threshold_exponent},
               {"consistency_checks", o.vio.frontend.consistency_checks},
               {"consistency_hits", o.vio.frontend.consistency_hits},
               {"trusted_model", o.vio.frontend.trusted_model},
               {"refine_essential", o.vio.frontend.filter.refine_essential},
               {"imu_rotation", o.vio.frontend.filter.known_rotation},
               {"rotation_prior_sigma_rad", o.vio.frontend.filter.rotation_prior_sigma_rad},
               {"pure_rotation_share", o.vio.frontend.filter.pure_rotation_share},
               {"cheirality", o.vio.frontend.filter.cheirality},
               {"gyro_klt", gyro_klt_name(o.vio.frontend.tracker.gyro_klt)},
               {"klt_window", o.vio.frontend.tracker.klt_window},
               {"klt_levels", o.vio.frontend.tracker.klt_pyramid_levels},
               {"rlof_refine", rlof_refine_name(o.vio.frontend.tracker.rlof_refine)},
               {"dynamic_precision", s.precision()},
               {"dynamic_recall", s.recall()},
               {"dynamic_precision_centre", c.precision()},
               {"dynamic_recall_centre", c.recall()},
               {"dynamic_precision_all_distances", a.precision()},
               {"dynamic_recall_all_distances", a.recall()},
               {"score_rule", "patch: labels under the KLT window, mixed patches counted apart, objects at "
                              "score_min..max_distance_m from the camera (docs/frontend.md)"},
               {"score", {{"true_positive", s.true_positive}, {"false_positive", s.false_positive},
                          {"false_negative", s.false_negative}, {"true_negative", s.true_negative},
                          {"mixed", s.mixed}, {"mixed_flagged", s.mixed_flagged},
                          {"patch_half_size_px", report.score_patch_half_size_px},
                          {"excluded_slow", s.excluded}, {"min_speed_mps", o.vio.min_speed_mps},
                          {"excluded_distance", s.excluded_range}, {"min_distance_m", o.vio.score_min_distance_m},
                          {"max_distance_m", o.vio.score_max_distance_m}}},
               {"score_all_distances", {{"true_positive", a.true_positive}, {"false_positive", a.false_positive},
                                        {"false_negative", a.false_negative}, {"true_negative", a.true_negative},
                                        {"mixed", a.mixed}, {"mixed_flagged", a.mixed_flagged},
                                        {"excluded_slow", a.excluded}}},
               {"score_centre", {{"true_positive", c.true_positive}, {"false_positive", c.false_positive},
                                 {"false_negative", c.false_negative}, {"true_negative", c.true_negative},
                                 {"excluded_slow", c.excluded}}},
               {"static_ratio", {{"mean", report.static_ratio_mean}, {"min", report.static_ratio_min}}},
               {"affine_realign", o.vio.frontend.affine_realign.enabled},
               {"affine_refit", o.vio.frontend.affine_realign.refit_model},
               {"refits_affine", report.refits_affine},
               {"realigned_affine", report.realigned_affine},
               {"unflagged_affine", report.unflagged_affine},
               {"group_min_support", o.vio.frontend.groups.min_support},
               {"group_radius_px", o.vio.frontend.groups.radius_px(o.vio.frontend.tracker.min_distance_px)},
               {"isolated_flags", report.isolated_flags},
               {"trust_contest_ratio", o.vio.frontend.trust_contest_ratio},
               {"trust_contest_frames", o.vio.frontend.trust_contest_frames},
               {"contests_lost", report.contests_lost},
               {"young_trust_majority", o.vio.frontend.young_trust_majority},
               {"trust_undecided_frames", report.trust_undecided_frames},
               {"mover_grace_claims", o.vio.frontend.mover_grace_claims},
               {"graced_flags", report.graced_flags},
               {"group_turned_min_support", o.vio.frontend.groups.turned_min_support},
               {"group_turned_static_tests", o.vio.frontend.groups.turned_static_tests},
               {"frames_too_few_matches", report.frames_too_few_matches},
               {"frames_no_fundamental", report.frames_no_fundamental},
               {"frames_static_camera", report.frames_static_camera},
               {"frames_known_rotation", report.frames_known_rotation},
               {"frames_pure_rotation", report.frames_pure_rotation},
               {"frames_rotation_rejected", report.frames_rotation_rejected},
               {"frames_gyro_seeded", report.frames_gyro_seeded},
               {"tracked_per_frame", report.tracked_per_frame},
               {"lost_klt_per_frame", report.lost_klt_per_frame},
               {"lost_forward_backward_per_frame", report.lost_forward_backward_per_frame},
               {"image_ms_per_frame", report.image_ms_per_frame},
               {"tracking_ms_per_frame", report.tracking_ms_per_frame},
               {"classification_ms_per_frame", report.classification_ms_per_frame},
               {"image_time_s", report.image_s},
               {"frontend_time_s", report.frontend_s},
               {"frontend_realtime_factor", duration / std::max(1e-9, report.frontend_s)},
               {"frontend_cpu_ms_per_frame", 1e3 * cpu_frontend_s / std::max<std::size_t>(1, report.frames)},
               {"frontend_realtime_factor_cpu", duration / std::max(1e-9, cpu_frontend_s)}};
  char line[400];
  std::snprintf(line, sizeof line,
                "front end: dynamic precision %.3f recall %.3f (objects at %g-%g m: tp %ld fp %ld fn %ld mixed %ld; any distance:"
                " %.3f / %.3f; centre pixel: %.3f / %.3f),"
                " M mean %.3f min %.3f, images %.1f ms/frame, tracking %.1f + classification %.1f ms/frame\n",
                s.precision(), s.recall(), o.vio.score_min_distance_m, o.vio.score_max_distance_m, s.true_positive,
                s.false_positive, s.false_negative, s.mixed, a.precision(), a.recall(), c.precision(),
                c.recall(), report.static_ratio_mean,
                report.static_ratio_min, report.image_ms_per_frame, report.tracking_ms_per_frame,
                report.classification_ms_per_frame);
  log << line;
  return tracked;
}

}  // namespace slamkit::cli
