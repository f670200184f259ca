// The DVI front end on images with the long-baseline epipolar test (see the header).
#include "slamkit/vio/image_frontend.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace slamkit {
namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

DynamicFilterOptions long_baseline_filter(const ImageFrontendOptions& o) {
  DynamicFilterOptions f = o.filter;
  f.threshold_px *= std::pow(std::max(1, o.baseline_frames), o.baseline_threshold_exponent);
  return f;
}

}  // namespace

ImageFrontend::ImageFrontend(ImageFrontendOptions options, std::shared_ptr<const CameraModel> camera, GrayImage mask)
    : options_(options),
      tracker_(options.tracker, std::move(mask), camera),
      filter_(options.filter, camera),
      filter_long_(long_baseline_filter(options), camera) {
  if (options_.baseline_frames < 1) throw std::invalid_argument("ImageFrontend: baseline_frames must be >= 1");
  if (!(options_.baseline_threshold_exponent >= 0.0 && options_.baseline_threshold_exponent <= 1.0))
    throw std::invalid_argument("ImageFrontend: baseline_threshold_exponent must be in [0, 1]");
  if (options_.consistency_checks < 1 || options_.consistency_checks > 16)
    throw std::invalid_argument("ImageFrontend: consistency_checks must be in 1..16");
  if (!(options_.min_patch_ncc_first <= 1.0)) throw std::invalid_argument("ImageFrontend: min_patch_ncc_first must be <= 1");
  if (!(options_.min_patch_ncc_baseline <= 1.0))
    throw std::invalid_argument("ImageFrontend: min_patch_ncc_baseline must be <= 1");
  if (options_.mover_grace_claims < 0 || options_.mover_grace_claims > 1000)
    throw std::invalid_argument("ImageFrontend: mover_grace_claims must be in 0..1000");
  if (options_.consistency_hits < 1 || options_.consistency_hits > options_.consistency_checks)
    throw std::invalid_argument("ImageFrontend: consistency_hits must be in 1..consistency_checks");
  check_epipolar_search_options(options_.epipolar_search);
  check_affine_realign_options(options_.affine_realign);
  check_dynamic_group_options(options_.groups);
  if (!(options_.trust_contest_ratio >= 0.0 && std::isfinite(options_.trust_contest_ratio)))
    throw std::invalid_argument("ImageFrontend: trust_contest_ratio must be finite and >= 0");
}

FeatureMotion consistent_motion(std::uint16_t over, int count, int checks, int hits, bool was_dynamic) {
  if (count <= 0) return FeatureMotion::kUnknown;
  const int n = std::min(count, checks);
  int h = 0;
  for (int i = 0; i < n; ++i) h += (over >> i) & 1;
  return h >= (was_dynamic ? 1 : hits) ? FeatureMotion::kDynamic : FeatureMotion::kStatic;
}

FrontendFrameResult ImageFrontend::process(const GrayImage& frame, const Eigen::Matrix3d* R_cur_prev) {
  FrontendFrameResult out;
  const auto t0 = std::chrono::steady_clock::now();
  out.tracking = tracker_.track(frame, R_cur_prev);
  out.tracking_ms = ms_since(t0);
  const auto t1 = std::chrono::steady_clock::now();
  const int k = options_.baseline_frames;
  const std::vector<TrackedFeature>& tracked = out.tracking.features;
  out.features.resize(tracked.size());
  // Current pixels of the test (the tracks', or their RLOF test chain's); the re-search may move them.
  std::vector<Eigen::Vector2d> uv_now(tracked.size());
  for (std::size_t i = 0; i < tracked.size(); ++i) uv_now[i] = tracked[i].uv_test;
  std::vector<char> refound(tracked.size(), 0);  // moved by the re-search or the re-alignment
  bool moved = false;
  for (std::size_t i = 0; i < tracked.size(); ++i) {
    out.features[i].id = tracked[i].id;
    out.features[i].uv = tracked[i].uv;
  }
  // Baseline of each feature: min(age, k, frames seen so far).
  const int available = static_cast<int>(history_.size());
  std::vector<int> baseline(tracked.size());
  int longest = 0;
  for (std::size_t i = 0; i < tracked.size(); ++i) {
    const int b = std::min({tracked[i].age, k, available});
    baseline[i] = b >= k ? k : std::min(b, 1);  // two RANSACs per frame at most: k and 1
    longest = std::max(longest, baseline[i]);
  }
  bool cold_start = false;  // a test fitted on all its matches: too few trusted
  for (int b = longest; b >= 1; b = b > 1 ? 1 : 0) {
    const auto& then = history_[b - 1];
    std::vector<Eigen::Vector2d> p1, p2;
    std::vector<std::size_t> index;  // feature of each match
    for (std::size_t i = 0; i < tracked.size(); ++i) {
      if (tracked[i].age < b) continue;
      const auto it = then.find(tracked[i].id);
      if (it == then.end()) continue;  // cannot happen while ids persist; kept safe
      p1.push_back(it->second), p2.push_back(uv_now[i]), index.push_back(i);
    }
    bool any = false;
    for (std::size_t m = 0; m < index.size() && !any; ++m) any = baseline[index[m]] == b;
    if (!any) continue;
    std::vector<char> trusted;  // static in its last test(s): fits the camera's motion (see the header)
    if (options_.trusted_model) {
      trusted.assign(index.size(), 0);
      for (std::size_t m = 0; m < index.size(); ++m) {
        const auto h = tests_.find(tracked[index[m]].id);
        trusted[m] = h != tests_.end() && h->second.count >= options_.trusted_min_tests && !h->second.dynamic &&
                     (h->second.over & 1u) == 0;
      }
    }
    const DynamicFeatureFilter& filter = b > 1 ? filter_long_ : filter_;
    // The rotation over the b frames: R_{t,t−b} = R_{t,t−1} R_{t−1,t−2} ⋯ R_{t−b+1,t−b}.
    std::optional<Eigen::Matrix3d> R;
    if (options_.filter.known_rotation && R_cur_prev && b - 1 <= static_cast<int>(rotations_.size())) {
      R = *R_cur_prev;
      for (int j = 0; j + 1 < b && R; ++j) R = rotations_[j] ? std::optional<Eigen::Matrix3d>(*R * *rotations_[j]) : std::nullopt;
    }
    Classification c = filter.classify(p1, p2, options_.trusted_model ? &trusted : nullptr, R ? &*R : nullptr);
    // Trust contest while the trust is young (see the header): a cold start is a fit on all matches.
    if (options_.trusted_model && std::count(trusted.begin(), trusted.end(), 1) < options_.filter.min_subset_fit())
      cold_start = true;
    if (options_.trusted_model && options_.trust_contest_ratio > 0.0 && young_trust(frames_since_cold_start_) &&
        filter.contest(p1, p2, R ? &*R : nullptr, options_.trust_contest_ratio, &c))
      ++out.n_contests_lost;
    std::vector<char> tested(index.size());  // only the features whose flag this test sets
    for (std::size_t m = 0; m < index.size(); ++m) tested[m] = baseline[index[m]] == b;
    // Matches whose pixel in frame t a second look moved: their tracks continue from there.
    const auto take_moved = [&](const std::vector<char>& moved_now) {
      for (std::size_t m = 0; m < index.size(); ++m)
        if (moved_now[m]) uv_now[index[m]] = p2[m], refound[index[m]] = 1, moved = true;
    };
    const bool have_frame = b <= static_cast<int>(frames_.size());
    if (options_.epipolar_search.enabled && have_frame) {
      const EpipolarSearchResult s =
          search_along_epipolar(frames_[b - 1], frame, p1, &p2, filter, &c, options_.epipolar_search, &tested);
      take_moved(s.refound);
      out.n_refound_epipolar += s.refound_count;
    }
    const auto realign = [&](Classification* model, const std::vector<char>& consider) {
      const AffineRealignResult a =
          realign_affine(frames_[b - 1], frame, p1, &p2, filter, model, options_.affine_realign, &consider);
      take_moved(a.realigned);
      out.n_realigned_affine += a.realigned_count, out.n_unflagged_affine += a.unflagged_count;
      return a;
    };
    if (options_.affine_realign.enabled && have_frame) {
      const AffineRealignResult a = realign(&c, tested);
      // A better model: the camera's motion fitted again on the trusted tracks plus those the
      // re-alignment turned static, and the features it flags re-aligned in turn.
      if (options_.affine_realign.refit_model && options_.trusted_model && a.unflagged_count > 0) {
        std::vector<char> trusted_more = trusted;
        for (std::size_t m = 0; m < index.size(); ++m)
          if (a.unflagged[m]) trusted_more[m] = 1;
        Classification refit = filter.classify(p1, p2, &trusted_more, R ? &*R : nullptr);
        // Kept only if it passes at least as many of the trusted tracks as the first model: a wrongly
        // unflagged mover must not pull the model away from the static consensus.
        const auto trusted_static = [&](const Classification& x) {
          int n = 0;
          for (std::size_t m = 0; m < index.size(); ++m) n += trusted[m] && x.flags[m] == FeatureMotion::kStatic;
          return n;
        };
        if (refit.status == ClassificationStatus::kEpipolar && trusted_static(refit) >= trusted_static(c)) {
          std::vector<char> again(index.size());
          for (std::size_t m = 0; m < index.size(); ++m) again[m] = tested[m] && !a.realigned[m];
          realign(&refit, again);
          ++out.n_refits_affine;
          c = std::move(refit);
        }
      }
    }
    if (b == longest) out.status = c.status, out.motion_model = c.motion_model;
    for (std::size_t m = 0; m < index.size(); ++m) {
      FrontendFeature& f = out.features[index[m]];
      if (b == 1) f.distance_1_px = c.distance_px[m];
      if (baseline[index[m]] != b) continue;
      f.motion = c.flags[m];
      f.distance_px = c.distance_px[m];
      f.baseline = b;
      f.uv_then = p1[m];
    }
  }
  if (moved) {  // re-found on the epipolar line or realigned: the track continues from there
    std::vector<std::int64_t> ids;
    std::vector<Eigen::Vector2d> uv;
    for (std::size_t i = 0; i < out.features.size(); ++i)
      if (refound[i]) {
        out.features[i].uv = out.tracking.features[i].uv = uv_now[i];
        ids.push_back(out.features[i].id), uv.push_back(uv_now[i]);
      }
    tracker_.relocate(ids, uv);
  }
  // The test positions travel with their features (drops below compact the lists); the history keeps them.
  for (std::size_t i = 0; i < uv_now.size(); ++i) out.tracking.features[i].uv_test = uv_now[i];
  // Drops the rejected tracks from the tracker and out (keep[i] = 0), in order; returns how many.
  const auto drop_rejected = [&](const std::vector<std::int64_t>& rejected, const std::vector<char>& keep) {
    if (rejected.empty()) return 0;
    tracker_.drop(rejected);
    std::size_t w = 0;
    for (std::size_t i = 0; i < out.features.size(); ++i)
      if (keep[i]) out.features[w] = out.features[i], out.tracking.features[w] = out.tracking.features[i], ++w;
    out.features.resize(w), out.tracking.features.resize(w);
    return static_cast<int>(rejected.size());
  };
  // Appearance over the tested baseline: reject the tracks whose patch changed (see the header).
  if (options_.min_patch_ncc_baseline > -1.0) {
    std::vector<std::int64_t> rejected;
    std::vector<char> keep(out.features.size(), 1);
    for (std::size_t i = 0; i < out.features.size(); ++i) {
      const FrontendFeature& f = out.features[i];
      if (f.baseline < 1 || f.baseline > static_cast<int>(frames_.size())) continue;
      const double ncc = patch_ncc(frames_[f.baseline - 1], f.uv_then, frame, f.uv, options_.tracker.patch_half_px);
      if (ncc < options_.min_patch_ncc_baseline) keep[i] = 0, rejected.push_back(f.id);  // NaN: kept
    }
    out.n_rejected_appearance = drop_rejected(rejected, keep);
  }
  // Appearance against the first frame (see the header): crop the patch of a new track, compare later.
  if (options_.min_patch_ncc_first > -1.0) {
    const int h = options_.tracker.patch_half_px, side = 2 * h + 4;
    std::unordered_map<std::int64_t, FirstPatch> alive;
    std::vector<std::int64_t> rejected;
    std::vector<char> keep(out.features.size(), 1);
    for (std::size_t i = 0; i < out.features.size(); ++i) {
      const FrontendFeature& f = out.features[i];
      auto it = first_patch_.find(f.id);
      if (it == first_patch_.end()) {  // new: the crop's origin floor(uv) − h − 1 keeps the bilinear patch inside
        const int x0 = static_cast<int>(std::floor(f.uv.x())) - h - 1, y0 = static_cast<int>(std::floor(f.uv.y())) - h - 1;
        if (!f.uv.allFinite() || x0 < 0 || y0 < 0 || x0 + side > frame.width || y0 + side > frame.height) continue;
        FirstPatch p{GrayImage(side, side), f.uv - Eigen::Vector2d(x0, y0)};
        for (int y = 0; y < side; ++y)
          for (int x = 0; x < side; ++x) p.crop.at(x, y) = frame.at(x0 + x, y0 + y);
        alive.emplace(f.id, std::move(p));
        continue;
      }
      const double ncc = patch_ncc(it->second.crop, it->second.centre, frame, f.uv, h);
      if (ncc < options_.min_patch_ncc_first) keep[i] = 0, rejected.push_back(f.id);  // NaN: kept
      else alive.emplace(f.id, std::move(it->second));
    }
    first_patch_.swap(alive);
    out.n_rejected_first_patch = drop_rejected(rejected, keep);
  }
  // Consistency over the track's last tests, then sticky flags; bookkeeping of the current ids only.
  std::unordered_map<std::int64_t, TestHistory> tests;
  tests.reserve(out.features.size());
  std::unordered_set<std::int64_t> still;
  std::vector<char> turned(out.features.size(), 0);  // flagged after turned_static_tests static tests (groups)
  std::vector<TestHistory*> history(out.features.size());  // each feature's entry in `tests` (stable nodes)
  const int turned_tests = options_.groups.turned_static_tests;  // 1..16 (checked)
  for (std::size_t i = 0; i < out.features.size(); ++i) {
    FrontendFeature& f = out.features[i];
    TestHistory h;
    if (const auto it = tests_.find(f.id); it != tests_.end()) h = it->second;
    const bool was_static = h.count >= turned_tests && !h.dynamic && (h.over & ((1u << turned_tests) - 1u)) == 0;
    if (f.motion != FeatureMotion::kUnknown) {  // a test ran this frame: shift it in
      h.over = static_cast<std::uint16_t>((h.over << 1) | (f.motion == FeatureMotion::kDynamic ? 1 : 0));
      h.count = std::min(h.count + 1, 16);
      f.motion = consistent_motion(h.over, h.count, options_.consistency_checks, options_.consistency_hits, h.dynamic);
      h.dynamic = f.motion == FeatureMotion::kDynamic;
    }
    const int n = std::min(h.count, options_.consistency_checks);
    f.checks = n, f.hits = 0;
    for (int i = 0; i < n; ++i) f.hits += (h.over >> i) & 1;
    // A confirmed mover's dip: flagged in this frame by its run of claims (see the header).
    const int grace = options_.mover_grace_claims;
    if (grace > 0 && f.motion == FeatureMotion::kStatic && h.claim_run >= grace)
      f.motion = FeatureMotion::kDynamic, f.graced = true, ++out.n_graced;
    history[i] = &tests.emplace(f.id, h).first->second;
    turned[i] = was_static && f.motion == FeatureMotion::kDynamic;
    if (options_.sticky_dynamic && flagged_dynamic_.count(f.id)) f.motion = FeatureMotion::kDynamic;
    if (f.motion == FeatureMotion::kDynamic) still.insert(f.id);
  }
  flagged_dynamic_.swap(still);
  tests_.swap(tests);
  // Dynamic groups: a flag with no flagged neighbour is isolated (the test histories keep their tests).
  std::vector<Eigen::Vector2d> uv(out.features.size());
  std::vector<FeatureMotion> flags(out.features.size());
  for (std::size_t i = 0; i < out.features.size(); ++i) uv[i] = out.features[i].uv, flags[i] = out.features[i].motion;
  std::vector<char> isolated;
  out.n_isolated = mark_isolated_flags(uv, flags, options_.groups,
                                       options_.groups.radius_px(options_.tracker.min_distance_px), &isolated, &turned);
  // Young trust without a majority (see the header): no flag of this frame claims a mover.
  if (options_.young_trust_majority && options_.trusted_model && options_.trust_contest_ratio > 0.0 &&
      young_trust(cold_start ? 0 : frames_since_cold_start_ + 1)) {  // this frame's age
    const auto n_flags = std::count(flags.begin(), flags.end(), FeatureMotion::kDynamic);
    const auto n_static = std::count(flags.begin(), flags.end(), FeatureMotion::kStatic);
    if (n_flags > 0 && n_static < options_.trust_contest_ratio * n_flags) {
      out.trust_undecided = true;
      for (std::size_t i = 0; i < flags.size(); ++i)
        if (flags[i] == FeatureMotion::kDynamic && !isolated[i]) isolated[i] = 1, ++out.n_isolated;
    }
  }
  for (std::size_t i = 0; i < out.features.size(); ++i) {
    FrontendFeature& f = out.features[i];
    f.isolated = isolated[i] != 0;
    const bool claimed = f.motion == FeatureMotion::kDynamic && !f.isolated && !f.graced;
    history[i]->claim_run = claimed ? std::min(history[i]->claim_run + 1, 1 << 20) : 0;
  }
  for (const FrontendFeature& f : out.features) {
    if (f.motion == FeatureMotion::kStatic) ++out.n_static;
    else if (f.motion == FeatureMotion::kDynamic) out.n_dynamic += f.isolated ? 0 : 1;
    else ++out.n_unknown;
  }
  const int classified = out.n_static + out.n_dynamic + out.n_isolated;
  out.static_ratio = classified > 0 ? static_cast<double>(out.n_static) / classified : 1.0;
  frames_since_cold_start_ = cold_start ? 0 : frames_since_cold_start_ + 1;
  // History: this frame becomes t − 1.
  std::unordered_map<std::int64_t, Eigen::Vector2d> now;
  now.reserve(tracked.size());
  for (const TrackedFeature& f : tracked) now.emplace(f.id, f.uv_test);
  history_.push_front(std::move(now));
  while (static_cast<int>(history_.size()) > k) history_.pop_back();
  rotations_.push_front(R_cur_prev ? std::optional<Eigen::Matrix3d>(*R_cur_prev) : std::nullopt);
  while (static_cast<int>(rotations_.size()) > k) rotations_.pop_back();
  if (keep_frames()) {
    frames_.push_front(frame);
    while (static_cast<int>(frames_.size()) > k) frames_.pop_back();
  }
  out.classification_ms = ms_since(t1);
  return out;
}

GrayImage circular_mask(int width, int height, double cx, double cy, double radius_px, double margin_px) {
  if (radius_px <= 0.0) return {};
  GrayImage mask(width, height, 0);
  const double r = radius_px - margin_px;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      if (std::hypot(x - cx, y - cy) <= r) mask.at(x, y) = 255;
  return mask;
}

}  // namespace slamkit
