// The affine re-alignment (ImageFrontendOptions::affine_realign) on a rendered TUM-VI room at full
// resolution (512 × 512, the room2 trajectory with a high-dynamic crowd): the static false alarms
// of the long-baseline test are mostly track errors (docs/frontend.md, "Session 35"), which the
// re-alignment moves back onto their epipolar line; the walkers stay flagged. Measured (session 35,
// the default front end otherwise): off precision 0.896 recall 0.902 (687 false alarms), realigned
// 0.984 / 0.892 (96, with the model refit). Front end only (no window), about 18 s on 2 cores. Needs the TUM-VI ground
// truth and calibration (../shared/datasets/vio/tumvi).
#include <gtest/gtest.h>

#include <cstdio>

#include "slamkit/core/parallel.h"
#include "slamkit/io/visual_inertial_sequence_io.h"
#include "slamkit/sim/image_renderer.h"
#include "slamkit/sim/rendered_scene.h"
#include "slamkit/vio/image_vio.h"
#include "testing/data.h"

namespace slamkit {
namespace {

// room2 high seed 1, rendered once for the tests below (the renders of the benchmark).
struct RenderedRoom {
  SequenceSimulation run;
  RenderedScene scene;
  std::vector<GrayImage> images, labels;
  FrameImageSource source() const {
    return [this](std::size_t k, GrayImage* image, GrayImage* label) { *image = images[k], *label = labels[k]; };
  }
};

const RenderedRoom& room2_high() {
  static const RenderedRoom room = [] {
    VisualInertialSimOptions opt;
    opt.seed = 1;
    opt.dynamic = DynamicLevel::kHigh;
    opt.duration = 20.0;  // the false alarms come in bursts (fast turns at 18-19.5 s): the whole stretch of the benchmark
    RenderedRoom r{simulate_visual_inertial_sequence("room2", testing::data_root().string(), opt), {}, {}, {}};
    r.scene = build_rendered_scene(r.run.sim, *r.run.spline, r.run.options);
    ImageRendererOptions ro;
    ro.seed = r.run.options.seed;
    ro.mask_radius_px = r.run.sequence.mask_radius_px;
    const ImageRenderer renderer(r.scene, *r.run.sim.camera, ro);
    const ThreadPool pool(2);
    r.images.resize(r.run.sim.frames.size()), r.labels.resize(r.run.sim.frames.size());
    const FrameImageSource render = rendered_frames(r.run.sim, renderer, &pool);
    for (std::size_t k = 0; k < r.images.size(); ++k) render(k, &r.images[k], &r.labels[k]);
    return r;
  }();
  return room;
}

TEST(ImageFrontendRealign, CutsTheStaticFalseAlarmsOfARenderedRoom) {
  SLAMKIT_REQUIRE_DATA(root, "vio/tumvi");
  const RenderedRoom& room = room2_high();
  const auto& run = room.run;
  const auto& scene = room.scene;
  const FrameImageSource cached = room.source();
  ImageVioReport off, on;
  for (bool realign : {false, true}) {
    ImageVioOptions o;
    o.frontend.affine_realign.enabled = realign;
    o.frontend.groups.min_support = 0;  // the re-alignment alone (the group rule: below)
    track_images(run.sim, cached, walker_speeds(scene), ObjectDistances{}, o, realign ? &on : &off);
  }
  const DetectionScore& a = off.score;
  const DetectionScore& b = on.score;
  std::printf("off: precision %.3f recall %.3f (tp %ld fp %ld fn %ld); realigned: precision %.3f recall %.3f "
              "(tp %ld fp %ld fn %ld; %zu moved, %zu unflagged)\n",
              a.precision(), a.recall(), a.true_positive, a.false_positive, a.false_negative, b.precision(), b.recall(),
              b.true_positive, b.false_positive, b.false_negative, on.realigned_affine, on.unflagged_affine);
  ASSERT_GT(a.true_positive + a.false_negative, 500) << "the walkers must be seen";
  EXPECT_EQ(off.realigned_affine, 0u);
  EXPECT_GT(on.unflagged_affine, 0u);
  EXPECT_LT(b.false_positive, a.false_positive / 2);
  EXPECT_GT(b.precision(), a.precision());
  EXPECT_GT(b.recall(), a.recall() - 0.05);
}

// The group rule (ImageFrontendOptions::groups, dynamic_groups.h) after the re-alignment: the
// static false alarms left are mostly single tracks (T-junctions, corners that are no 3-D point)
// while a walker near enough carries several flagged features. An isolated flag claims no moving
// object (it is scored as "not dynamic") and stays out of the estimator as before. Session 36, this
// room, every walker scored (no distance range): without the rule precision 0.984 recall 0.892 (tp
// 5972 fp 96 fn 722), with it 0.989 / 0.855 (tp 5724 fp 66 fn 970; 594 isolated): beyond 6 m a
// walker is small and often carries one feature, so the rule costs recall there; at the issue's
// 2-6 m it removes mostly false alarms (benchmark in docs/frontend.md, "Session 36").
TEST(ImageFrontendGroups, MarksIsolatedFlagsOfARenderedRoom) {
  SLAMKIT_REQUIRE_DATA(root, "vio/tumvi");
  const RenderedRoom& room = room2_high();
  ImageVioReport off, on;
  for (int support : {0, 1}) {
    ImageVioOptions o;
    o.frontend.groups.min_support = support;
    o.frontend.young_trust_majority = false;  // the group rule alone (the young-trust rule: below)
    o.frontend.mover_grace_claims = 0;        // nor do claims carry a flag through a dip (below)
    track_images(room.run.sim, room.source(), walker_speeds(room.scene), ObjectDistances{}, o, support ? &on : &off);
  }
  const DetectionScore& a = off.score;
  const DetectionScore& b = on.score;
  std::printf("groups off: precision %.3f recall %.3f (tp %ld fp %ld fn %ld); on: precision %.3f recall %.3f "
              "(tp %ld fp %ld fn %ld; %zu isolated)\n",
              a.precision(), a.recall(), a.true_positive, a.false_positive, a.false_negative, b.precision(), b.recall(),
              b.true_positive, b.false_positive, b.false_negative, on.isolated_flags);
  ASSERT_GT(a.true_positive + a.false_negative, 500) << "the walkers must be seen";
  EXPECT_EQ(off.isolated_flags, 0u);
  EXPECT_GT(on.isolated_flags, 0u);
  // Only claims change (the tracks and tests are the same): the same movers are scored, and an
  // isolated flag is a hit or a false alarm less, or one on a feature the score leaves out (mixed, slow).
  EXPECT_EQ(b.true_positive + b.false_negative, a.true_positive + a.false_negative);
  EXPECT_LE(a.true_positive + a.false_positive - b.true_positive - b.false_positive, static_cast<long>(on.isolated_flags));
  EXPECT_GT(a.true_positive + a.false_positive - b.true_positive - b.false_positive, 0);
  EXPECT_LT(b.false_positive, a.false_positive * 4 / 5);
  EXPECT_GT(b.precision(), a.precision());
  EXPECT_GT(b.recall(), a.recall() - 0.06);
}

// Session 38: a flag on a track whose last two tests were static needs two flagged neighbours
// (groups.turned_min_support), and while the trust is young a frame claims movers only when its
// static features outnumber its flags 1.5 : 1 (young_trust_majority). Both change claims only (the
// same tracks, tests and estimator input). Session 38, this room, every walker scored: off precision
// 0.989 recall 0.855 (tp 5724 fp 66), on 0.991 / 0.831 (tp 5566 fp 52; 5 undecided frames): the
// hits lost are mostly far walkers' (at the 2-6 m: 453 -> 451 hits for the same 66 -> 52
// false alarms; the benchmark: docs/frontend.md, "Session 38").
// The session-38 rules' runs, kept for the grace test below (grace off: the rules change claims only).
struct RulesRuns {
  ImageVioReport report[2];  // [0]: rules off, [1]: on
  VisualInertialSim tracks[2];
};
const RulesRuns& rules_runs() {
  static const RulesRuns runs = [] {
    const RenderedRoom& room = room2_high();
    RulesRuns r;
    for (bool rules : {false, true}) {
      ImageVioOptions o;
      o.frontend.mover_grace_claims = 0;
      if (!rules) o.frontend.groups.turned_min_support = 0, o.frontend.young_trust_majority = false;
      r.tracks[rules] = track_images(room.run.sim, room.source(), walker_speeds(room.scene), ObjectDistances{}, o,
                                     &r.report[rules]);
    }
    return r;
  }();
  return runs;
}

void print_score(const char* name, const ImageVioReport& r) {
  const DetectionScore& s = r.score;
  std::printf("%s: precision %.3f recall %.3f (tp %ld fp %ld fn %ld; %zu isolated, %zu undecided frames, %zu graced)\n",
              name, s.precision(), s.recall(), s.true_positive, s.false_positive, s.false_negative, r.isolated_flags,
              r.trust_undecided_frames, r.graced_flags);
}

TEST(ImageFrontendGroups, TurnedFlagsAndYoungTrustClaimLess) {
  SLAMKIT_REQUIRE_DATA(root, "vio/tumvi");
  const RulesRuns& runs = rules_runs();
  const ImageVioReport& off = runs.report[0];
  const ImageVioReport& on = runs.report[1];
  print_score("rules off", off), print_score("rules on", on);
  const DetectionScore& a = off.score;
  const DetectionScore& b = on.score;
  ASSERT_GT(a.true_positive + a.false_negative, 500) << "the walkers must be seen";
  EXPECT_EQ(off.trust_undecided_frames, 0u);
  EXPECT_EQ(b.true_positive + b.false_negative, a.true_positive + a.false_negative);
  EXPECT_GT(on.isolated_flags, off.isolated_flags);
  EXPECT_LT(b.false_positive, a.false_positive);
  EXPECT_GT(b.precision(), a.precision());
  EXPECT_GT(b.recall(), a.recall() - 0.04);
  // Claims only: the estimator gets the same tracks with the same flags.
  const auto& tracks = runs.tracks;
  ASSERT_EQ(tracks[0].frames.size(), tracks[1].frames.size());
  for (std::size_t k = 0; k < tracks[0].frames.size(); ++k) {
    const auto& x = tracks[0].frames[k].observations;
    const auto& y = tracks[1].frames[k].observations;
    ASSERT_EQ(x.size(), y.size()) << "frame " << k;
    for (std::size_t i = 0; i < x.size(); ++i)
      ASSERT_TRUE(x[i].track_id == y[i].track_id && x[i].dynamic == y[i].dynamic && x[i].classified == y[i].classified &&
                  x[i].uv == y[i].uv)
          << "frame " << k << " observation " << i;
  }
}

// Session 39: a track claimed as a mover in each of its last three frames keeps its flag through one
// test under the threshold (mover_grace_claims): a walker whose motion runs along the epipolar line
// for a frame stays flagged. The tests are the same; the graced observations, and only they, turn
// from static to dynamic (the window leaves them out). Session 39, this room, every walker scored:
// grace off precision 0.991 recall 0.831, on 0.990 / 0.849 (tp 5566 -> 5680, fp 52 -> 58; 181 graced).
// The benchmark at 2-6 m, seeds 1-5: 0.907 / 0.794 -> 0.906 / 0.832 (docs/frontend.md, "Session 39").
TEST(ImageFrontendGroups, AClaimedMoverKeepsItsFlagThroughADip) {
  SLAMKIT_REQUIRE_DATA(root, "vio/tumvi");
  const RenderedRoom& room = room2_high();
  const RulesRuns& runs = rules_runs();
  ImageVioReport on;
  const VisualInertialSim tracks = track_images(room.run.sim, room.source(), walker_speeds(room.scene),
                                                ObjectDistances{}, ImageVioOptions{}, &on);
  const ImageVioReport& off = runs.report[1];
  print_score("grace off", off), print_score("grace on", on);
  const DetectionScore& a = off.score;
  const DetectionScore& b = on.score;
  EXPECT_EQ(off.graced_flags, 0u);
  EXPECT_GT(on.graced_flags, 50u);
  EXPECT_EQ(b.true_positive + b.false_negative, a.true_positive + a.false_negative);
  EXPECT_GT(b.recall(), a.recall() + 0.01);
  EXPECT_GT(b.precision(), a.precision() - 0.01);
  // Same tracks; observations differ only static -> dynamic, one per graced flag.
  const VisualInertialSim& before = runs.tracks[1];
  ASSERT_EQ(before.frames.size(), tracks.frames.size());
  std::size_t turned = 0;
  for (std::size_t k = 0; k < tracks.frames.size(); ++k) {
    const auto& x = before.frames[k].observations;
    const auto& y = tracks.frames[k].observations;
    ASSERT_EQ(x.size(), y.size()) << "frame " << k;
    for (std::size_t i = 0; i < x.size(); ++i) {
      ASSERT_TRUE(x[i].track_id == y[i].track_id && x[i].classified == y[i].classified && x[i].uv == y[i].uv)
          << "frame " << k << " observation " << i;
      ASSERT_TRUE(x[i].dynamic == y[i].dynamic || (!x[i].dynamic && y[i].dynamic)) << "frame " << k << " observation " << i;
      turned += x[i].dynamic != y[i].dynamic;
    }
  }
  EXPECT_EQ(turned, on.graced_flags);
}

}  // namespace
}  // namespace slamkit
