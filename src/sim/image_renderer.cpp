// ImageRenderer (image_renderer.h): ray casting of the rendered scene through a camera model.
#include "slamkit/sim/image_renderer.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace slamkit {
namespace {

std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

// splitmix64 stream: a counter-based generator, cheap to seed per row.
struct RowRandom {
  std::uint64_t state;
  std::uint64_t next() {
    state += 0x9E3779B97F4A7C15ULL;
    return mix64(state);
  }
};

// N(0, 1) by inverse-CDF lookup: the quantiles Φ⁻¹((i + 0.5) / 4096), i = 0..4095, found by
// bisection on erfc; a uniform 12-bit index draws a (discretized, ±3.5σ) Gaussian sample.
constexpr int kGaussBits = 12;
std::vector<float> gaussian_quantiles() {
  std::vector<float> q(1u << kGaussBits);
  for (std::size_t i = 0; i < q.size(); ++i) {
    const double p = (static_cast<double>(i) + 0.5) / static_cast<double>(q.size());
    double lo = -10.0, hi = 10.0;
    for (int it = 0; it < 80; ++it) {
      const double mid = 0.5 * (lo + hi);
      (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p ? lo : hi) = mid;
    }
    q[i] = static_cast<float>(0.5 * (lo + hi));
  }
  return q;
}

// Light direction (towards the light) and the ambient/diffuse split of the face shading.
const Eigen::Vector3d kLight = Eigen::Vector3d(0.35, 0.55, 0.76).normalized();
constexpr double kAmbient = 0.55, kDiffuse = 0.45;
double shade_of(const Eigen::Vector3d& normal) { return kAmbient + kDiffuse * std::max(0.0, normal.dot(kLight)); }

}  // namespace

struct ImageRenderer::FrameBox {
  Eigen::Vector3d centre, half;
  double c = 1.0, s = 0.0;  // cos, sin of yaw
  double radius = 0.0;      // bounding sphere
  Eigen::Vector2d texture_offset;
  int texture = 0;
  std::uint8_t label = 0;
};

SE3 frame_camera_pose(const VisualInertialSim& sim, const SimFrame& frame) {
  return SE3(SO3(frame.truth.q_world_imu), frame.truth.p_world) * sim.T_cam_imu.inverse();
}

ImageRenderer::ImageRenderer(const RenderedScene& scene, const CameraModel& camera, const ImageRendererOptions& options)
    : scene_(scene), camera_(camera.with_intrinsics(camera.intrinsics())), options_(options), width_(camera.width()),
      height_(camera.height()) {
  if (scene.textures.empty()) throw std::invalid_argument("ImageRenderer: scene without textures");
  if (options.supersample < 1 || options.supersample > 8) throw std::invalid_argument("ImageRenderer: supersample must be 1..8");
  const int S = options.supersample;
  const std::size_t n = static_cast<std::size_t>(width_) * height_;
  rays_.assign(n * S * S, Eigen::Vector3f::Zero());
  pixel_angle_.assign(n, 0.0f);
  vignette_.assign(n, 1.0f);
  valid_.assign(n, 0);
  const Eigen::VectorXd K = camera.intrinsics();
  const Eigen::Vector2d principal(K(2), K(3));
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * width_ + x;
      const Eigen::Vector2d uv(x, y);
      if (options.mask_radius_px > 0.0 && (uv - principal).norm() > options.mask_radius_px) continue;
      Eigen::Vector3d b, bx, by;
      if (!camera.unproject(uv, &b) || !camera.unproject(uv + Eigen::Vector2d(1, 0), &bx) ||
          !camera.unproject(uv + Eigen::Vector2d(0, 1), &by))
        continue;
      bool ok = true;
      for (int sy = 0; sy < S && ok; ++sy)
        for (int sx = 0; sx < S && ok; ++sx) {
          Eigen::Vector3d r;
          const Eigen::Vector2d sub = uv + Eigen::Vector2d((sx + 0.5) / S - 0.5, (sy + 0.5) / S - 0.5);
          ok = camera.unproject(sub, &r);
          rays_[i * S * S + static_cast<std::size_t>(sy * S + sx)] = r.normalized().cast<float>();
        }
      if (!ok) continue;
      valid_[i] = 1;
      const double ax = std::acos(std::clamp(b.normalized().dot(bx.normalized()), -1.0, 1.0));
      const double ay = std::acos(std::clamp(b.normalized().dot(by.normalized()), -1.0, 1.0));
      pixel_angle_[i] = static_cast<float>(0.5 * (ax + ay));
      const double theta = std::acos(std::clamp(b.normalized().z(), -1.0, 1.0));
      vignette_[i] = static_cast<float>(std::max(0.0, 1.0 - options.vignetting * std::pow(theta / (M_PI / 2), 2)));
    }
  // Tiles: the cone (axis, half-angle) around all rays of the tile.
  tiles_x_ = (width_ + kTile - 1) / kTile, tiles_y_ = (height_ + kTile - 1) / kTile;
  tiles_.assign(static_cast<std::size_t>(tiles_x_) * tiles_y_, Tile{});
  for (int ty = 0; ty < tiles_y_; ++ty)
    for (int tx = 0; tx < tiles_x_; ++tx) {
      Tile& tile = tiles_[static_cast<std::size_t>(ty) * tiles_x_ + tx];
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      const auto for_rays = [&](auto&& fn) {
        for (int y = ty * kTile; y < std::min(height_, (ty + 1) * kTile); ++y)
          for (int x = tx * kTile; x < std::min(width_, (tx + 1) * kTile); ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * width_ + x;
            if (!valid_[i]) continue;
            for (int s = 0; s < S * S; ++s) fn(rays_[i * S * S + static_cast<std::size_t>(s)].template cast<double>(), i);
          }
      };
      for_rays([&](const Eigen::Vector3d& r, std::size_t) { sum += r; });
      if (sum.norm() < 1e-9) continue;
      const Eigen::Vector3d axis = sum.normalized();
      double half = 0.0;
      for_rays([&](const Eigen::Vector3d& r, std::size_t i) {
        half = std::max(half, std::acos(std::clamp(axis.dot(r), -1.0, 1.0)) + pixel_angle_[i]);
      });
      tile.axis = axis.cast<float>();
      tile.half_angle = static_cast<float>(half + 1e-3);
      tile.any = true;
    }
  gauss_ = gaussian_quantiles();
  for (int k = 0; k < 3; ++k)
    phase_[k] = 2.0 * M_PI * static_cast<double>(mix64(options.seed * 0x9E3779B97F4A7C15ULL + 101 + k) >> 11) / 9007199254740992.0;
}

double ImageRenderer::gain(double t) const {
  return std::exp(options_.gain_drift *
                  (0.6 * std::sin(2 * M_PI * t / 7.3 + phase_[0]) + 0.4 * std::sin(2 * M_PI * t / 2.9 + phase_[1])));
}
double ImageRenderer::offset(double t) const { return options_.offset_drift * std::sin(2 * M_PI * t / 11.0 + phase_[2]); }

std::vector<ImageRenderer::FrameBox> ImageRenderer::frame_boxes(double t) const {
  std::vector<FrameBox> out;
  for (const SceneBox& b : scene_.boxes_at(t)) {
    FrameBox f;
    f.centre = b.centre, f.half = b.half;
    f.c = std::cos(b.yaw), f.s = std::sin(b.yaw);
    f.radius = b.half.norm();
    f.texture_offset = b.texture_offset;
    f.texture = b.texture;
    f.label = b.label;
    out.push_back(f);
  }
  return out;
}

// Nearest hit of c + s·d (d unit): room exit, then the candidate boxes (all if null).
RayHit ImageRenderer::trace(const std::vector<FrameBox>& boxes, const std::vector<int>* candidates,
                            const Eigen::Vector3d& c, const Eigen::Vector3d& d, Eigen::Vector2d* face_uv,
                            double* cos_incidence, int* texture, double* shade) const {
  RayHit hit;
  double best = 1e300;
  int axis = -1, side = 0;
  for (int i = 0; i < 3; ++i) {
    double s;
    int sd;
    if (d(i) > 1e-12) s = (scene_.room_hi(i) - c(i)) / d(i), sd = 1;
    else if (d(i) < -1e-12) s = (scene_.room_lo(i) - c(i)) / d(i), sd = 0;
    else continue;
    if (s < best) best = s, axis = i, side = sd;
  }
  if (axis < 0 || !(best > 0.0)) return hit;  // camera outside the room: nothing to see
  hit.hit = true;
  hit.distance = best;
  hit.face = 2 * axis + side;
  const Eigen::Vector3d p = c + best * d;
  static constexpr int kU[3] = {1, 0, 0}, kV[3] = {2, 2, 1};
  *face_uv = Eigen::Vector2d(p(kU[axis]), p(kV[axis]));
  *cos_incidence = std::abs(d(axis));
  *texture = scene_.room_texture[hit.face];
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  normal(axis) = side == 0 ? 1.0 : -1.0;  // inward
  *shade = shade_of(normal);
  const std::size_t count = candidates ? candidates->size() : boxes.size();
  for (std::size_t k = 0; k < count; ++k) {
    const int bi = candidates ? (*candidates)[k] : static_cast<int>(k);
    const FrameBox& b = boxes[static_cast<std::size_t>(bi)];
    const Eigen::Vector3d q = c - b.centre;
    // Box frame: Rz(yaw)ᵀ.
    const Eigen::Vector3d o(b.c * q.x() + b.s * q.y(), -b.s * q.x() + b.c * q.y(), q.z());
    const Eigen::Vector3d dl(b.c * d.x() + b.s * d.y(), -b.s * d.x() + b.c * d.y(), d.z());
    double s_in = -1e300, s_out = 1e300;
    int in_axis = 0;
    bool miss = false;
    for (int i = 0; i < 3; ++i) {
      if (std::abs(dl(i)) < 1e-12) {
        if (std::abs(o(i)) > b.half(i)) { miss = true; break; }
        continue;
      }
      const double inv = 1.0 / dl(i);
      double s0 = (-b.half(i) - o(i)) * inv, s1 = (b.half(i) - o(i)) * inv;
      if (s0 > s1) std::swap(s0, s1);
      if (s0 > s_in) s_in = s0, in_axis = i;
      s_out = std::min(s_out, s1);
    }
    if (miss || !(s_in > 0.0) || s_in > s_out || s_in >= best) continue;
    best = s_in;
    hit.distance = best;
    hit.face = -1;
    hit.box = bi;
    hit.label = b.label;
    const Eigen::Vector3d pl = o + s_in * dl + b.half;  // from the box corner
    *face_uv = Eigen::Vector2d(pl(kU[in_axis]), pl(kV[in_axis])) + b.texture_offset;
    *cos_incidence = std::abs(dl(in_axis));
    *texture = b.texture;
    Eigen::Vector3d nl = Eigen::Vector3d::Zero();
    nl(in_axis) = dl(in_axis) > 0.0 ? -1.0 : 1.0;  // outward face normal
    *shade = shade_of(Eigen::Vector3d(b.c * nl.x() - b.s * nl.y(), b.s * nl.x() + b.c * nl.y(), nl.z()));
  }
  hit.point = c + hit.distance * d;
  return hit;
}

RayHit ImageRenderer::cast(double t, const SE3& T_world_cam, const Eigen::Vector2d& uv) const {
  Eigen::Vector3d b;
  if (!camera_->unproject(uv, &b)) return RayHit{};
  const std::vector<FrameBox> boxes = frame_boxes(t);
  Eigen::Vector2d fuv;
  double cos_inc = 1.0, shade = 1.0;
  int texture = 0;
  // The same float bearing and matrix product as render(), so cast() and render() agree bit for bit.
  const Eigen::Vector3d d = T_world_cam.rotation().matrix() * b.normalized().cast<float>().cast<double>();
  return trace(boxes, nullptr, T_world_cam.translation(), d, &fuv, &cos_inc, &texture, &shade);
}

void ImageRenderer::render(double t, const SE3& T_world_cam, GrayImage* image, GrayImage* labels,
                           const ThreadPool* pool) const {
  if (image->width != width_ || image->height != height_) *image = GrayImage(width_, height_);
  if (labels && (labels->width != width_ || labels->height != height_)) *labels = GrayImage(width_, height_);
  const std::vector<FrameBox> boxes = frame_boxes(t);
  const Eigen::Matrix3d R = T_world_cam.rotation().matrix();
  const Eigen::Vector3d c = T_world_cam.translation();
  // Boxes per tile: bounding sphere against the tile's cone.
  std::vector<std::vector<int>> candidates(tiles_.size());
  for (std::size_t bi = 0; bi < boxes.size(); ++bi) {
    const Eigen::Vector3d w = R.transpose() * (boxes[bi].centre - c);
    const double dist = w.norm();
    const bool around = dist <= boxes[bi].radius;
    const double spread = around ? 0.0 : std::asin(boxes[bi].radius / dist);
    for (std::size_t ti = 0; ti < tiles_.size(); ++ti) {
      const Tile& tile = tiles_[ti];
      if (!tile.any) continue;
      if (around || std::acos(std::clamp(tile.axis.cast<double>().dot(w) / dist, -1.0, 1.0)) <= tile.half_angle + spread)
        candidates[ti].push_back(static_cast<int>(bi));
    }
  }
  const int S = options_.supersample;
  const double g = gain(t) * options_.brightness, off = offset(t);
  const std::uint64_t t_ns = static_cast<std::uint64_t>(std::llround(t * 1e9));
  const double inv_texel = 1.0 / scene_.texel_size;
  const auto rows = [&](std::size_t y0, std::size_t y1) {
    std::vector<std::uint8_t> sub_labels(static_cast<std::size_t>(S * S));
    for (std::size_t yy = y0; yy < y1; ++yy) {
      const int y = static_cast<int>(yy);
      RowRandom rnd{mix64(options_.seed * 0xD1B54A32D192ED03ULL ^ mix64(t_ns) ^ (static_cast<std::uint64_t>(y) * 0x9E3779B97F4A7C15ULL))};
      std::uint8_t* out = image->row(y);
      std::uint8_t* lab = labels ? labels->row(y) : nullptr;
      for (int x = 0; x < width_; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * width_ + x;
        if (!valid_[i]) {
          out[x] = 0;
          if (lab) lab[x] = 0;
          continue;
        }
        const std::vector<int>& cand = candidates[static_cast<std::size_t>(y / kTile) * tiles_x_ + x / kTile];
        double sum = 0.0;
        for (int s = 0; s < S * S; ++s) {
          const Eigen::Vector3d d = R * rays_[i * S * S + static_cast<std::size_t>(s)].cast<double>();
          Eigen::Vector2d fuv;
          double cos_inc = 1.0, shade = 1.0;
          int texture = 0;
          const RayHit h = trace(boxes, &cand, c, d, &fuv, &cos_inc, &texture, &shade);
          sub_labels[static_cast<std::size_t>(s)] = h.label;
          if (!h.hit) continue;
          const double footprint = h.distance * pixel_angle_[i] * inv_texel / (S * std::max(cos_inc, 0.02));
          const double lod = std::log2(std::max(footprint, 1e-6)) + options_.lod_bias;
          sum += shade * scene_.textures[static_cast<std::size_t>(texture)]->sample(fuv.x() * inv_texel, fuv.y() * inv_texel, lod);
        }
        const double n = gauss_[static_cast<std::size_t>(rnd.next() >> (64 - kGaussBits))];
        const double value = g * vignette_[i] * sum / (S * S) + off + options_.noise_sigma * n;
        out[x] = static_cast<std::uint8_t>(std::clamp(std::lround(value), 0L, 255L));
        if (lab) {
          std::uint8_t best = sub_labels[0];
          if (S > 1) {
            int best_count = 0;
            for (int a = 0; a < S * S; ++a) {
              const int count = static_cast<int>(std::count(sub_labels.begin(), sub_labels.end(), sub_labels[static_cast<std::size_t>(a)]));
              if (count > best_count) best_count = count, best = sub_labels[static_cast<std::size_t>(a)];
            }
          }
          lab[x] = best;
        }
      }
    }
  };
  if (pool) pool->parallel_for(static_cast<std::size_t>(height_), rows, 8);
  else rows(0, static_cast<std::size_t>(height_));
}

}  // namespace slamkit
