// Rendered images: a pixel ray hits the expected plane point, labels agree with the moving
// boxes (projected surface and the uncull'd reference ray), results are identical for any thread
// count and reproduce for a seed, the images have texture and contrast, textures are band-limited.
#include "slamkit/sim/image_renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "testing/tumvi_rig.h"

namespace slamkit {
namespace {

using testing::tumvi_camera;
using testing::tumvi_T_cam_imu;
using testing::circle_path;

struct World {
  BSplineTrajectory spline = circle_path();
  VisualInertialSimOptions options;
  VisualInertialSim sim;
  RenderedScene scene;
  World(DynamicLevel level, int furniture, std::uint64_t seed = 1, int burst_rows_behind = 0) {
    options.seed = seed;
    options.dynamic = level;
    sim = simulate_visual_inertial(spline, tumvi_camera(), tumvi_T_cam_imu(), options);
    RenderedSceneOptions ro;
    ro.furniture_count = furniture;
    ro.texture_size = 256;  // keeps the test fast
    ro.burst_rows_behind = burst_rows_behind;
    scene = build_rendered_scene(sim, spline, options, ro);
  }
};

TEST(RenderedScene, MatchesTheFeatureSimulatorWorld) {
  World w(DynamicLevel::kHigh, 12);
  // The room is the simulator's: every static landmark lies on one of its faces.
  for (const SimLandmark& l : w.sim.landmarks) {
    if (l.group >= 0) continue;
    double on_face = 1e9;
    for (int i = 0; i < 3; ++i)
      on_face = std::min({on_face, std::abs(l.position(i) - w.scene.room_lo(i)), std::abs(l.position(i) - w.scene.room_hi(i))});
    ASSERT_LT(on_face, 1e-9);
  }
  ASSERT_GE(w.scene.walkers.size(), w.sim.groups.size());  // the simulator's groups first, then the bursts
  for (std::size_t k = 0; k < w.sim.groups.size(); ++k) {
    EXPECT_EQ(w.scene.walkers[k].id, 1 + w.sim.groups[k].id % 255);
    EXPECT_NEAR(w.scene.walkers[k].speed, w.sim.groups[k].velocity.norm(), 1e-12);
    EXPECT_GE(w.scene.walkers[k].speed, 0.5);
  }
  EXPECT_GE(w.scene.furniture.size(), 6u);
  for (const SceneBox& b : w.scene.furniture) {
    EXPECT_NEAR(b.centre.z() - b.half.z(), w.scene.room_lo.z(), 1e-12);  // on the floor
    for (const SimState& s : w.sim.imu_truth)  // clear of the path
      ASSERT_GT((s.p_world.head<2>() - b.centre.head<2>()).norm(), b.half.head<2>().norm() + 0.5);
  }
}

// Crowd bursts (high level only): queues of person boxes crossing the view at the burst centre,
// inside the room, clear of the camera, fast enough to count, and a large labelled share of the
// image at the centre time; none at the low level or with burst_interval_s = 0.
TEST(RenderedScene, CrowdBurstsCrossTheViewAtTheHighLevel) {
  World w(DynamicLevel::kHigh, 8);
  ASSERT_GE(w.scene.burst_centres.size(), 1u);
  const std::size_t bursts = w.scene.walkers.size() - w.sim.groups.size();
  EXPECT_GE(bursts, 5u);
  const RenderedSceneOptions defaults;
  for (std::size_t k = w.sim.groups.size(); k < w.scene.walkers.size(); ++k) {
    const SceneWalker& b = w.scene.walkers[k];
    EXPECT_EQ(b.path.id, static_cast<int>(k));
    EXPECT_EQ(b.id, 1 + b.path.id % 255);
    EXPECT_GE(b.speed, defaults.burst_speed_min);
    EXPECT_LE(b.speed, defaults.burst_speed_max);
    EXPECT_NEAR(b.path.velocity.norm(), b.speed, 1e-12);
    for (double t = b.path.t_on; t <= b.path.t_off; t += 0.1) {
      const Eigen::Vector3d p = b.path.pose(t).translation();
      for (int a = 0; a < 2; ++a) {
        EXPECT_GE(p(a), w.scene.room_lo(a) + 0.3 - 1e-9);
        EXPECT_LE(p(a), w.scene.room_hi(a) - 0.3 + 1e-9);
      }
      const Eigen::Vector3d c = (w.spline.pose(t) * w.sim.T_cam_imu.inverse()).translation();
      EXPECT_GE((c - p).head<2>().norm(), defaults.burst_camera_clearance - 0.05);
    }
  }
  // At a burst centre the crowd covers a large part of the view.
  const ImageRenderer renderer(w.scene, *w.sim.camera);
  GrayImage image, labels;
  const double tc = w.scene.burst_centres.front();
  // Queues in front of and behind the camera with burst_rows_behind (default 0: in front only).
  for (int rows_behind : {0, 2}) {
    const World s(DynamicLevel::kHigh, 8, 1, rows_behind);
    const double t = s.scene.burst_centres.front();
    const SE3 T_wc = s.spline.pose(t) * s.sim.T_cam_imu.inverse();
    Eigen::Vector3d view = T_wc.rotation().act(Eigen::Vector3d::UnitZ());
    view.z() = 0.0;
    int in_front = 0, behind = 0;
    for (std::size_t k = s.sim.groups.size(); k < s.scene.walkers.size(); ++k) {
      const SimMovingGroup& g = s.scene.walkers[k].path;
      if (!g.active(t)) continue;
      const double along = (g.pose(t).translation() - T_wc.translation()).dot(view);
      in_front += along > 0.0, behind += along < 0.0;
    }
    EXPECT_GT(in_front, 0);
    if (rows_behind > 0) EXPECT_GT(behind, 0);
    else EXPECT_EQ(behind, 0);
  }
  std::size_t k = 0;
  while (k + 1 < w.sim.frames.size() && w.sim.frames[k].t < tc) ++k;
  renderer.render(w.sim.frames[k].t, frame_camera_pose(w.sim, w.sim.frames[k]), &image, &labels);
  std::size_t moving = 0, valid = 0;
  for (int y = 0; y < labels.height; ++y)
    for (int x = 0; x < labels.width; ++x) {
      valid += image.at(x, y) > 0;
      moving += labels.at(x, y) > 0;
    }
  EXPECT_GT(static_cast<double>(moving), 0.25 * static_cast<double>(valid));
  World low(DynamicLevel::kLow, 8);
  EXPECT_EQ(low.scene.walkers.size(), low.sim.groups.size());
  EXPECT_TRUE(low.scene.burst_centres.empty());
}

TEST(ImageRenderer, APlanePointIsFoundAtItsProjection) {
  World w(DynamicLevel::kNone, 0);
  const ImageRenderer renderer(w.scene, *w.sim.camera);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int checked = 0;
  for (std::size_t k = 0; k < w.sim.frames.size(); k += 37) {
    const SimFrame& f = w.sim.frames[k];
    const SE3 T_world_cam = frame_camera_pose(w.sim, f);
    for (int n = 0; n < 60; ++n) {
      // A point on a random face of the (empty, convex) room.
      const int face = static_cast<int>(unit(rng) * 6) % 6, axis = face / 2;
      Eigen::Vector3d P;
      for (int i = 0; i < 3; ++i) P(i) = w.scene.room_lo(i) + unit(rng) * (w.scene.room_hi(i) - w.scene.room_lo(i));
      P(axis) = face % 2 ? w.scene.room_hi(axis) : w.scene.room_lo(axis);
      Eigen::Vector2d uv;
      const Eigen::Vector3d pc = T_world_cam.inverse().act(P);
      if (pc.z() < 0.05 || !w.sim.camera->project(pc, &uv) || !w.sim.camera->in_image(uv)) continue;
      const RayHit hit = renderer.cast(f.t, T_world_cam, uv);
      ASSERT_TRUE(hit.hit);
      EXPECT_EQ(hit.face, face);
      EXPECT_LT((hit.point - P).norm(), 1e-6 * (1.0 + pc.norm())) << "frame " << k;
      EXPECT_NEAR(hit.distance, pc.norm(), 1e-6);
      ++checked;
    }
  }
  EXPECT_GT(checked, 200);
}

// Pixels of walker k lie inside the projection of its box surface (sampled densely, so the
// fisheye's curved edges are covered) and every rendered label equals the label of the
// reference ray cast without tile culling.
TEST(ImageRenderer, LabelsAgreeWithTheProjectedMovingBoxes) {
  World w(DynamicLevel::kHigh, 8);
  const ImageRenderer renderer(w.scene, *w.sim.camera);
  GrayImage image, labels;
  std::size_t labelled = 0, frames_with_people = 0;
  for (std::size_t k = 0; k < w.sim.frames.size(); k += 29) {
    const SimFrame& f = w.sim.frames[k];
    const SE3 T_world_cam = frame_camera_pose(w.sim, f);
    const SE3 T_cam_world = T_world_cam.inverse();
    renderer.render(f.t, T_world_cam, &image, &labels);
    std::map<int, Eigen::Vector4d> rect;  // label → (min u, min v, max u, max v); NaN if a point does not project
    for (const SceneBox& b : w.scene.boxes_at(f.t)) {
      if (b.label == 0) continue;
      Eigen::Vector4d r(1e9, 1e9, -1e9, -1e9);
      bool all = true;
      for (int a = 0; a < 3 && all; ++a)
        for (int side = 0; side < 2 && all; ++side)
          for (int i = 0; i <= 12 && all; ++i)
            for (int j = 0; j <= 12 && all; ++j) {
              Eigen::Vector3d q;
              q(a) = side ? 1.0 : -1.0;
              q((a + 1) % 3) = -1.0 + i / 6.0, q((a + 2) % 3) = -1.0 + j / 6.0;
              const Eigen::Vector3d local = q.cwiseProduct(b.half);
              const Eigen::Vector3d world =
                  b.centre + Eigen::Vector3d(std::cos(b.yaw) * local.x() - std::sin(b.yaw) * local.y(),
                                             std::sin(b.yaw) * local.x() + std::cos(b.yaw) * local.y(), local.z());
              Eigen::Vector2d uv;
              const Eigen::Vector3d pc = T_cam_world.act(world);
              if (pc.z() <= 0.0 || !w.sim.camera->project(pc, &uv)) { all = false; break; }
              r = Eigen::Vector4d(std::min(r(0), uv.x()), std::min(r(1), uv.y()), std::max(r(2), uv.x()), std::max(r(3), uv.y()));
            }
      if (all) rect[b.label] = r;
    }
    bool people = false;
    for (int y = 0; y < 512; ++y)
      for (int x = 0; x < 512; ++x) {
        const int l = labels.at(x, y);
        if ((x + 3 * y) % 7 == 0) {
          ASSERT_EQ(l, renderer.cast(f.t, T_world_cam, Eigen::Vector2d(x, y)).label) << x << "," << y;
        }
        if (l == 0) continue;
        people = true;
        ++labelled;
        const auto it = rect.find(l);
        if (it == rect.end()) continue;  // the box reaches behind the camera: no bound to check
        const Eigen::Vector4d& r = it->second;
        ASSERT_TRUE(x >= r(0) - 2 && x <= r(2) + 2 && y >= r(1) - 2 && y <= r(3) + 2)
            << "label " << l << " at " << x << "," << y << " outside [" << r.transpose() << "]";
      }
    frames_with_people += people;
  }
  EXPECT_GT(frames_with_people, 3u);
  EXPECT_GT(labelled, 20000u);
}

TEST(ImageRenderer, IdenticalForAnyThreadCountAndReproducibleForASeed) {
  World w(DynamicLevel::kHigh, 12);
  const ImageRenderer renderer(w.scene, *w.sim.camera);
  const SimFrame& f = w.sim.frames[120];
  const SE3 T = frame_camera_pose(w.sim, f);
  GrayImage a, la, b, lb, c, lc;
  renderer.render(f.t, T, &a, &la);
  const ThreadPool one(1), two(2), three(3);
  renderer.render(f.t, T, &b, &lb, &two);
  EXPECT_EQ(a, b);
  EXPECT_EQ(la, lb);
  renderer.render(f.t, T, &c, &lc, &three);
  EXPECT_EQ(a, c);
  EXPECT_EQ(la, lc);
  renderer.render(f.t, T, &b, &lb, &one);
  EXPECT_EQ(a, b);
  // Another seed: other noise (and textures), same geometry and labels.
  ImageRendererOptions o;
  o.seed = 2;
  const ImageRenderer other(w.scene, *w.sim.camera, o);
  other.render(f.t, T, &b, &lb, &two);
  EXPECT_NE(a, b);
  EXPECT_EQ(la, lb);
  // A scene rebuilt from the same seed renders the same image.
  World again(DynamicLevel::kHigh, 12);
  const ImageRenderer renderer2(again.scene, *again.sim.camera);
  renderer2.render(f.t, T, &c, &lc, &two);
  EXPECT_EQ(a, c);
}

// Mean, contrast, corners (the structure tensor of > 150 8×8 blocks has a large smaller
// eigenvalue, as KLT needs), no saturation, black outside the fisheye mask, exposure drift.
TEST(ImageRenderer, ImagesHaveTextureContrastAndAMask) {
  World w(DynamicLevel::kNone, 12);
  ImageRendererOptions o;
  o.mask_radius_px = 300.0;
  const ImageRenderer renderer(w.scene, *w.sim.camera, o);
  GrayImage image, labels;
  for (std::size_t k : {10u, 150u, 300u}) {
    const SimFrame& f = w.sim.frames[k];
    renderer.render(f.t, frame_camera_pose(w.sim, f), &image, &labels);
    double sum = 0, sum2 = 0;
    std::size_t n = 0, saturated = 0;
    for (int y = 0; y < 512; ++y)
      for (int x = 0; x < 512; ++x) {
        const double r = std::hypot(x - 254.93, y - 256.90);
        EXPECT_EQ(labels.at(x, y), 0);
        if (r > 300.5) {
          ASSERT_EQ(image.at(x, y), 0);
          continue;
        }
        if (r > 290.0) continue;
        const double v = image.at(x, y);
        sum += v, sum2 += v * v, ++n;
        saturated += v == 0 || v == 255;
      }
    const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
    EXPECT_GT(mean, 50.0);
    EXPECT_LT(mean, 200.0);
    EXPECT_GT(sd, 20.0);
    EXPECT_LT(saturated, n / 200);
    int blocks = 0, cornery = 0;
    for (int by = 64; by + 8 <= 448; by += 8)
      for (int bx = 64; bx + 8 <= 448; bx += 8) {
        double gxx = 0, gyy = 0, gxy = 0;
        for (int y = by; y < by + 8; ++y)
          for (int x = bx; x < bx + 8; ++x) {
            const double gx = 0.5 * (image.at(x + 1, y) - image.at(x - 1, y));
            const double gy = 0.5 * (image.at(x, y + 1) - image.at(x, y - 1));
            gxx += gx * gx, gyy += gy * gy, gxy += gx * gy;
          }
        const double tr = 0.5 * (gxx + gyy), det = gxx * gyy - gxy * gxy;
        const double lmin = tr - std::sqrt(std::max(0.0, tr * tr - det));
        ++blocks;
        cornery += lmin / 64.0 > 25.0;  // mean smaller eigenvalue per pixel > 25 (gray levels²)
      }
    // At least the front end's budget of 150 features finds strong corners (blocks of 8×8 px).
    EXPECT_GT(cornery, 150) << "frame " << k << ": " << cornery << " of " << blocks << " blocks";
  }
  double lo = 1e9, hi = 0;
  for (const SimFrame& f : w.sim.frames) lo = std::min(lo, renderer.gain(f.t)), hi = std::max(hi, renderer.gain(f.t));
  EXPECT_GT(hi / lo, 1.05);
  EXPECT_LT(hi / lo, std::exp(2 * o.gain_drift) + 1e-9);
}

TEST(ProceduralTexture, TilesMipsAndStaysBandLimited) {
  for (const TextureKind kind : {TextureKind::kValueNoise, TextureKind::kBlobs, TextureKind::kTiles,
                                 TextureKind::kPosters, TextureKind::kClothing}) {
    const ProceduralTexture t(kind, 3, 128);
    EXPECT_EQ(t.levels(), 8);
    double mean = 0, hf = 0, energy = 0;
    for (int y = 0; y < 128; ++y)
      for (int x = 0; x < 128; ++x) {
        mean += t.texel(x, y) / (128.0 * 128.0);
        EXPECT_EQ(t.texel(x, y), t.texel(x + 128, y - 128));  // wraps
        EXPECT_GE(t.texel(x, y), 0.079f);
        EXPECT_LE(t.texel(x, y), 0.921f);
      }
    for (int y = 0; y < 128; ++y)
      for (int x = 0; x < 128; ++x) {
        // Highest-frequency content: the checkerboard component of 2×2 blocks.
        const double d = t.texel(x, y) - t.texel(x + 1, y) - t.texel(x, y + 1) + t.texel(x + 1, y + 1);
        hf += d * d;
        energy += std::pow(t.texel(x, y) - mean, 2);
      }
    EXPECT_LT(hf, 0.05 * energy) << to_string(kind);
    EXPECT_NEAR(t.sample(10.3, 77.9, 20.0), mean, 1e-4) << to_string(kind);  // coarsest level = mean
    EXPECT_NEAR(t.sample(10.5, 20.5, 0.0), t.texel(10, 20), 1e-6);            // texel centres
  }
  EXPECT_THROW(ProceduralTexture(TextureKind::kTiles, 1, 100), std::invalid_argument);
}

}  // namespace
}  // namespace slamkit
