// slamkit frontend VIDEO_OR_IMAGES... --out DIR [--calib kalibr.yaml] [--mask FILE] [--json OUT]
// The DVI front end (docs/frontend.md) on real pixels: tracks features through a video, a
// directory of images or a list of images (e.g. a stereo pair aloeL.jpg aloeR.jpg), flags each
// tracked feature static/dynamic by its epipolar distance, and writes every frame with the
// features drawn green (static), red (dynamic), yellow (unknown) as PNG (plus an MJPG AVI when
// the input is a video). The JSON has the per-frame counts, M = static/(static + dynamic) and a
// summary. Exit 1 with a message naming the file on unreadable input or a mask of the wrong size.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <string>

#include "cli_util.h"
#include "commands.h"
#include "vio_images.h"
#include "slamkit/io/kalibr_calibration.h"
#include "slamkit/vio/dynamic_feature_filter.h"
#include "slamkit/vio/dynamic_groups.h"
#include "slamkit/vio/feature_affine_realign.h"
#include "slamkit/vio/feature_epipolar_search.h"
#include "slamkit/vio/feature_tracker.h"
#include "slamkit/vio/frontend_io.h"

namespace slamkit::cli {

namespace {

struct FrontendCliOptions {
  std::vector<std::string> inputs;
  std::string out, calib, mask, json;
  FeatureTrackerOptions tracker;
  DynamicFilterOptions filter;
  EpipolarSearchOptions search;
  AffineRealignOptions realign;
  DynamicGroupOptions groups;
  int max_frames = 0;  // 0: all
  bool no_images = false, quiet = false;
};

std::string progress_bar(int done, int total) {
  const int width = 20, filled = total > 0 ? std::min(width, done * width / total) : 0;
  return "[" + std::string(filled, '#') + std::string(width - filled, '.') + "]";
}

void run_frontend(const FrontendCliOptions& o) {
  check_outputs({{&o.json, "--json"}});
  check_epipolar_search_input(o.search, "--search-range");
  check_affine_realign_input(o.realign);
  std::error_code ec;
  std::filesystem::create_directories(o.out, ec);
  if (!std::filesystem::is_directory(o.out)) throw InputError(o.out, 0, "--out", "cannot create the output directory");
  FrameSource source(o.inputs);
  std::shared_ptr<const CameraModel> camera;
  if (!o.calib.empty()) camera = read_kalibr_camchain(o.calib).front().model;
  GrayImage mask;
  if (!o.mask.empty()) mask = read_gray_image(o.mask);
  std::ostream& log = o.json == "-" ? std::cerr : std::cout;
  log << "frontend: " << source.description() << ", camera " << (camera ? camera->model_name() : "none (pixels as pinhole)")
      << ", up to " << o.tracker.max_features << " features, dynamic if d > " << o.filter.threshold_px << " px\n";

  FeatureTracker tracker(o.tracker, mask);
  const DynamicFeatureFilter filter(o.filter, camera);
  std::unique_ptr<VideoFileWriter> video;
  const int total = o.max_frames > 0 && source.frame_count() > 0 ? std::min(o.max_frames, source.frame_count())
                                                                  : o.max_frames > 0 ? o.max_frames : source.frame_count();
  const int report_every = std::max(1, total / 20);
  nlohmann::json frames = nlohmann::json::array();
  std::map<std::string, int> status_count;
  long all_static = 0, all_dynamic = 0, all_unknown = 0, all_refound = 0, all_realigned = 0, all_unflagged = 0,
       all_isolated = 0;
  double sum_ms = 0.0, max_ms = 0.0, sum_M = 0.0, min_M = std::numeric_limits<double>::infinity();
  int classified_frames = 0, too_few_frames = 0;
  GrayImage gray, prev_gray;
  ColorImage color;
  int k = 0;
  for (; (o.max_frames <= 0 || k < o.max_frames) && source.next(&gray, &color); ++k) {
    if (k == 0) {
      if (!mask.empty() && (mask.width != gray.width || mask.height != gray.height))
        throw InputError(o.mask, 0, "--mask",
                         "the mask is " + std::to_string(mask.width) + "x" + std::to_string(mask.height) +
                             " but the frames are " + std::to_string(gray.width) + "x" + std::to_string(gray.height));
      if (camera && (camera->width() != gray.width || camera->height() != gray.height))
        throw InputError(o.calib, 0, "cam0.resolution",
                         std::to_string(camera->width()) + "x" + std::to_string(camera->height()) +
                             " but the frames are " + std::to_string(gray.width) + "x" + std::to_string(gray.height));
    }
    const Stopwatch clock;
    TrackingResult t = tracker.track(gray);
    std::vector<Eigen::Vector2d> prev, cur;
    std::vector<std::int64_t> ids;
    t.matches(&prev, &cur, &ids);
    Classification c = filter.classify(prev, cur);
    // The tracks of the matches with moved[m] continue from their new pixel cur[m].
    const auto relocate = [&](const std::vector<char>& moved) {
      std::vector<std::int64_t> moved_ids;
      std::vector<Eigen::Vector2d> moved_uv;
      for (std::size_t m = 0; m < moved.size(); ++m)
        if (moved[m]) moved_ids.push_back(ids[m]), moved_uv.push_back(cur[m]), t.features[m].uv = cur[m];
      tracker.relocate(moved_ids, moved_uv);
    };
    int refound = 0, realigned = 0, unflagged = 0;
    if (o.search.enabled && !prev.empty()) {  // dynamic flags re-searched on their epipolar line
      const EpipolarSearchResult s = search_along_epipolar(prev_gray, gray, prev, &cur, filter, &c, o.search);
      relocate(s.refound);
      refound = s.refound_count;
    }
    if (o.realign.enabled && !prev.empty()) {  // dynamic flags re-aligned by an affine warp
      const AffineRealignResult a = realign_affine(prev_gray, gray, prev, &cur, filter, &c, o.realign);
      relocate(a.realigned);
      realigned = a.realigned_count, unflagged = a.unflagged_count;
    }
    // Dynamic groups: a flag with no other flag near it is isolated, not a moving object (dynamic_groups.h).
    std::vector<char> isolated_flags;
    const int isolated =
        mark_isolated_flags(cur, c.flags, o.groups, o.groups.radius_px(o.tracker.min_distance_px), &isolated_flags);
    const int dynamic = c.n_dynamic - isolated;
    if (o.search.enabled || o.realign.enabled) prev_gray = gray;
    const double ms = clock.seconds() * 1e3;
    // Flags per feature: the tracked ones come first in t.features, in the order of the matches.
    std::vector<FeatureMotion> flags(t.features.size(), FeatureMotion::kUnknown);
    std::copy(c.flags.begin(), c.flags.end(), flags.begin());
    const bool has_matches = k > 0;
    if (has_matches) {
      sum_ms += ms, max_ms = std::max(max_ms, ms);
      ++status_count[to_string(c.status)];
      all_static += c.n_static, all_dynamic += dynamic, all_unknown += c.n_unknown, all_refound += refound;
      all_realigned += realigned, all_unflagged += unflagged, all_isolated += isolated;
      if (c.n_static + c.n_dynamic > 0) sum_M += c.static_ratio, min_M = std::min(min_M, c.static_ratio), ++classified_frames;
      if (c.status == ClassificationStatus::kTooFewMatches) {
        ++too_few_frames;
        if (!o.quiet)
          log << "  frame " << k << ": only " << prev.size() << " tracked matches (fewer than " << o.filter.min_matches
              << "): all features unknown\n";
      }
    }
    frames.push_back({{"index", k}, {"name", source.frame_name(k)}, {"features", t.features.size()},
                      {"tracked", t.tracked}, {"detected", t.detected}, {"lost_klt", t.lost_klt},
                      {"lost_forward_backward", t.lost_forward_backward}, {"lost_border", t.lost_border},
                      {"lost_appearance", t.lost_appearance}, {"refound_epipolar", refound},
                      {"realigned_affine", realigned}, {"unflagged_affine", unflagged},
                      {"static", c.n_static}, {"dynamic", dynamic}, {"isolated", isolated},
                      {"unknown", has_matches ? c.n_unknown : 0},
                      {"static_ratio", c.static_ratio}, {"status", has_matches ? to_string(c.status) : "first_frame"},
                      {"median_flow_px", c.median_flow_px}, {"time_ms", ms}});
    if (!o.no_images || source.is_video()) {
      draw_features(&color, t.features, flags, &isolated_flags);
      if (!o.no_images) {
        char name[64];
        std::snprintf(name, sizeof name, "%05d_", k);
        write_png((std::filesystem::path(o.out) / (name + source.frame_name(k) + ".png")).string(), color);
      }
      if (source.is_video()) {
        if (!video)
          video = std::make_unique<VideoFileWriter>((std::filesystem::path(o.out) / "frontend.avi").string(), color.width,
                                                    color.height, source.fps());
        video->write(color);
      }
    }
    if (!o.quiet && (k % report_every == 0 || k + 1 == total)) {
      char line[240];
      std::snprintf(line, sizeof line, "  frame %5d/%d %s features %3zu tracked %3d static %3d dynamic %3d M %.3f (%s) %.2f ms\n",
                    k + 1, total, progress_bar(k + 1, total).c_str(), t.features.size(), t.tracked, c.n_static,
                    c.n_dynamic, c.static_ratio, has_matches ? to_string(c.status) : "first frame", ms);
      log << line << std::flush;
    }
  }
  const int pairs = std::max(0, k - 1);
  const long classified = all_static + all_dynamic + all_isolated;
  nlohmann::json j;
  j["kind"] = "frontend";
  j["slamkit_version"] = SLAMKIT_VERSION;
  j["input"] = source.description();
  j["camera"] = camera ? camera->model_name() : "none";
  j["options"] = {{"max_features", o.tracker.max_features}, {"min_distance_px", o.tracker.min_distance_px},
                  {"forward_backward_px", o.tracker.forward_backward_px}, {"klt_window", o.tracker.klt_window},
                  {"rlof_refine", rlof_refine_name(o.tracker.rlof_refine)},
                  {"klt_pyramid_levels", o.tracker.klt_pyramid_levels}, {"grid", o.tracker.grid_cols},
                  {"max_residual_ratio", o.tracker.max_residual_ratio},
                  {"threshold_px", o.filter.threshold_px},
                  {"ransac_threshold_px", o.filter.ransac_threshold_px},
                  {"static_camera_flow_px", o.filter.static_camera_flow_px},
                  {"epipolar_search", o.search.enabled}, {"search_range_px", o.search.search_half_px},
                  {"affine_realign", o.realign.enabled}, {"affine_min_correlation", o.realign.min_correlation},
                  {"group_min_support", o.groups.min_support}, {"group_radius_px", o.groups.radius_px(o.tracker.min_distance_px)},
                  {"search_ncc_drop", o.search.max_ncc_drop}, {"search_scan_px", o.search.line_scan_half_px}, {"search_min_ncc", o.search.min_ncc}};
  j["frames"] = k;
  j["static_ratio"] = {{"mean", classified_frames ? sum_M / classified_frames : 1.0},
                       {"min", classified_frames ? min_M : 1.0}};
  j["features_static"] = all_static;
  j["features_dynamic"] = all_dynamic;
  j["features_unknown"] = all_unknown;
  j["features_refound_epipolar"] = all_refound;
  j["features_realigned_affine"] = all_realigned;
  j["features_unflagged_affine"] = all_unflagged;
  j["features_isolated"] = all_isolated;
  j["share_dynamic"] = classified ? double(all_dynamic) / classified : 0.0;
  j["share_flagged"] = classified ? double(all_dynamic + all_isolated) / classified : 0.0;  // incl. isolated
  j["frames_too_few_matches"] = too_few_frames;
  j["classification_status"] = status_count;
  j["time_per_frame_ms"] = {{"mean", pairs ? sum_ms / pairs : 0.0}, {"max", max_ms}};
  j["per_frame"] = frames;
  char line[320];
  std::snprintf(line, sizeof line,
                "%d frames: M mean %.3f min %.3f, %.2f%% of %ld classified features dynamic (%ld isolated flags apart), %d "
                "frame(s) with too few "
                "matches, %.2f ms/frame (max %.2f)\n",
                k, j["static_ratio"]["mean"].get<double>(), j["static_ratio"]["min"].get<double>(),
                100.0 * j["share_dynamic"].get<double>(), classified, all_isolated, too_few_frames, j["time_per_frame_ms"]["mean"].get<double>(),
                max_ms);
  log << line;
  if (!o.json.empty()) write_json(o.json, j);
}

}  // namespace

void add_frontend_command(CLI::App& app) {
  CLI::App* sub = app.add_subcommand(
      "frontend", "track features in a video or images and flag moving ones by the epipolar check (docs/frontend.md)");
  auto o = std::make_shared<FrontendCliOptions>();
  sub->add_option("inputs", o->inputs, "a video file, a directory of images, or image files (e.g. aloeL.jpg aloeR.jpg)")
      ->required();
  sub->add_option("--out", o->out, "output directory for the annotated frames (PNG; frontend.avi for a video)")->required();
  sub->add_option("--calib", o->calib, "Kalibr camchain YAML: cam0's radtan/equidistant model undistorts the pixels");
  sub->add_option("--mask", o->mask, "image of the frame size, non-zero where features may be detected");
  sub->add_option("--json", o->json, "write per-frame counts, M and the summary as JSON ('-': stdout)");
  sub->add_option("--max-features", o->tracker.max_features, "features per frame")->check(CLI::Range(8, 5000))
      ->capture_default_str();
  sub->add_option("--min-distance", o->tracker.min_distance_px, "minimum distance between features (px)")
      ->check(CLI::Range(0.0, 1000.0))->capture_default_str();
  sub->add_option("--grid", o->tracker.grid_cols, "detect on an NxN grid (0: whole image)")->check(CLI::Range(0, 32))
      ->each([o](const std::string& n) { o->tracker.grid_rows = std::stoi(n); });
  sub->add_option("--pyramid-levels", o->tracker.klt_pyramid_levels, "KLT pyramid levels")->check(CLI::Range(0, 8))
      ->capture_default_str();
  sub->add_option("--klt-window", o->tracker.klt_window, "KLT window side (px)")->check(CLI::Range(3, 101))
      ->capture_default_str();
  sub->add_option_function<std::string>(
         "--rlof-refine", [o](const std::string& v) { o->tracker.rlof_refine = parse_rlof_refine(v); },
         "refine by robust local optical flow (RLOF: cross-based support region, M-estimator): off, track (= on: the "
         "tracks) or test (only the positions the epipolar test reads) [track]")
      ->check(CLI::IsMember({"off", "on", "track", "test"}));
  sub->add_option("--fb-threshold", o->tracker.forward_backward_px, "forward-backward check (px; 0: off)")
      ->check(CLI::Range(0.0, 100.0))->capture_default_str();
  sub->add_option("--max-residual-ratio", o->tracker.max_residual_ratio,
                  "drop tracks whose KLT residual exceeds this x the median (0: off)")
      ->check(cli::NonNegativeNumber)->capture_default_str();
  sub->add_option("--ambiguity", o->tracker.ambiguity_px,
                  "under large motion drop tracks whose two KLT candidates lie this far apart with similar residuals (px; 0: off)")
      ->check(cli::NonNegativeNumber)->capture_default_str();
  sub->add_option("--ambiguity-ratio", o->tracker.ambiguity_ratio,
                  "with --ambiguity: residual ratio min/max above which two candidates count as equally good")
      ->check(CLI::Range(0.0, 1.0))->capture_default_str();
  sub->add_option("--min-patch-ncc", o->tracker.min_patch_ncc,
                  "lose tracks whose patch NCC with the previous frame is below this (-1: off)")
      ->check(CLI::Range(-1.0, 1.0))->capture_default_str();
  sub->add_option("--patch-half", o->tracker.patch_half_px, "NCC patch half size (px)")->check(CLI::Range(1, 50))
      ->capture_default_str();
  sub->add_option("--threshold", o->filter.threshold_px, "epipolar distance above which a feature is dynamic (px)")
      ->check(cli::PositiveNumber)->capture_default_str();
  sub->add_option("--ransac-threshold", o->filter.ransac_threshold_px, "RANSAC inlier distance (px)")
      ->check(cli::PositiveNumber)->capture_default_str();
  sub->add_option("--static-camera-flow", o->filter.static_camera_flow_px,
                  "median flow below which the camera counts as static (px; negative: never)")
      ->capture_default_str();
  sub->add_option("--affine-realign", o->realign.enabled,
                  "align each dynamic-flagged feature's patch with the new frame by an affine warp (ECC) before its flag "
                  "counts; the track moves there, static if it now lies on its epipolar line")->capture_default_str();
  sub->add_option("--affine-min-correlation", o->realign.min_correlation,
                  "with --affine-realign: the alignment's normalized correlation must reach this")
      ->check(cli::FiniteRange(-1.0, 1.0))->capture_default_str();
  add_dynamic_group_options(sub, &o->groups, "");
  sub->add_option("--epipolar-search", o->search.enabled,
                  "re-search each dynamic-flagged feature along its epipolar line (KLT from seeds on the line); "
                  "re-found with a patch as good as its track's: static")->capture_default_str();
  sub->add_option("--search-range", o->search.search_half_px,
                  "with --epipolar-search: 1-D seeds up to this far along the line (px; 0: the nearest point only)")
      ->check(CLI::Range(0.0, 256.0))->capture_default_str();
  sub->add_option("--search-scan", o->search.line_scan_half_px,
                  "with --epipolar-search: 1-D NCC scan along the line up to this far (px; 0: off)")
      ->check(CLI::Range(0.0, 256.0))->capture_default_str();
  sub->add_option("--search-step", o->search.seed_step_px, "with --epipolar-search: spacing of the 1-D seeds (px)")
      ->check(CLI::Range(0.5, 256.0))->capture_default_str();
  sub->add_option("--search-levels", o->search.klt_pyramid_levels, "with --epipolar-search: KLT pyramid levels")
      ->check(CLI::Range(0, 8))->capture_default_str();
  sub->add_option("--search-ncc-drop", o->search.max_ncc_drop,
                  "with --epipolar-search: re-found iff its patch NCC >= the track's minus this")
      ->check(CLI::Range(0.0, 2.0))->capture_default_str();
  sub->add_option("--search-min-ncc", o->search.min_ncc, "with --epipolar-search: and its patch NCC >= this")
      ->check(CLI::Range(-1.0, 1.0))->capture_default_str();
  sub->add_option("--max-frames", o->max_frames, "stop after this many frames (0: all)")->check(cli::NonNegativeNumber);
  sub->add_flag("--no-images", o->no_images, "do not write the PNG frames");
  sub->add_flag("--quiet", o->quiet, "no progress lines");
  sub->callback([o]() { run_frontend(*o); });
}

}  // namespace slamkit::cli
