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

TEST(ImageFrontendRealign, CutsTheStaticFalseAlarmsOfARenderedRoom) {
  SLAMKIT_REQUIRE_DATA(root, "vio/tumvi");
  VisualInertialSimOptions opt;
  opt.seed = 1;
  opt.dynamic = DynamicLevel::kHigh;
  opt.duration = 20.0;  // the false alarms come in bursts (fast turns at 18-19.5 s): the whole stretch of the benchmark
  const SequenceSimulation run = simulate_visual_inertial_sequence("room2", testing::data_root().string(), opt);
  const RenderedScene scene = build_rendered_scene(run.sim, *run.spline, run.options);
  ImageRendererOptions ro;
  ro.seed = run.options.seed;
  ro.mask_radius_px = run.sequence.mask_radius_px;
  const ImageRenderer renderer(scene, *run.sim.camera, ro);
  const ThreadPool pool(2);
  std::vector<GrayImage> images(run.sim.frames.size()), labels(run.sim.frames.size());
  const FrameImageSource render = rendered_frames(run.sim, renderer, &pool);
  for (std::size_t k = 0; k < images.size(); ++k) render(k, &images[k], &labels[k]);
  const FrameImageSource cached = [&](std::size_t k, GrayImage* image, GrayImage* label) {
    *image = images[k], *label = labels[k];
  };
  ImageVioReport off, on;
  for (bool realign : {false, true}) {
    ImageVioOptions o;
    o.frontend.affine_realign.enabled = realign;
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

}  // namespace
}  // namespace slamkit
