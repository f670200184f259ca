// Procedural textures (procedural_texture.h): generation, low-pass, mip pyramid, trilinear lookup.
#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "slamkit/sim/procedural_texture.h"

namespace slamkit {
namespace {

using Image = std::vector<float>;

std::mt19937_64 texture_rng(std::uint64_t seed, TextureKind kind) {
  std::uint64_t z = seed * 0x9E3779B97F4A7C15ULL + (static_cast<std::uint64_t>(kind) + 11) * 0xD1B54A32D192ED03ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return std::mt19937_64(z ^ (z >> 31));
}

// Periodic value noise: random values on a lattice of `spacing` texels, smoothstep-interpolated.
void add_value_noise(Image* img, int n, int spacing, float amplitude, std::mt19937_64& rng) {
  const int cells = std::max(1, n / spacing);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> lattice(static_cast<std::size_t>(cells * cells));
  for (float& v : lattice) v = u(rng);
  const auto at = [&](int i, int j) { return lattice[static_cast<std::size_t>((j % cells) * cells + (i % cells))]; };
  const float step = static_cast<float>(cells) / n;
  for (int y = 0; y < n; ++y) {
    const float fy = y * step;
    const int j = static_cast<int>(fy);
    float ty = fy - j;
    ty = ty * ty * (3 - 2 * ty);
    for (int x = 0; x < n; ++x) {
      const float fx = x * step;
      const int i = static_cast<int>(fx);
      float tx = fx - i;
      tx = tx * tx * (3 - 2 * tx);
      const float a = at(i, j) + tx * (at(i + 1, j) - at(i, j));
      const float b = at(i, j + 1) + tx * (at(i + 1, j + 1) - at(i, j + 1));
      (*img)[static_cast<std::size_t>(y * n + x)] += amplitude * (a + ty * (b - a));
    }
  }
}

void fill_rect(Image* img, int n, int x0, int y0, int w, int h, float value, float alpha) {
  for (int y = y0; y < y0 + h; ++y)
    for (int x = x0; x < x0 + w; ++x) {
      float& p = (*img)[static_cast<std::size_t>(((y % n + n) % n) * n + ((x % n + n) % n))];
      p += alpha * (value - p);
    }
}

void add_blob(Image* img, int n, double cx, double cy, double r, float value) {
  const int R = static_cast<int>(std::ceil(2.0 * r));
  for (int dy = -R; dy <= R; ++dy)
    for (int dx = -R; dx <= R; ++dx) {
      const int x = static_cast<int>(std::floor(cx)) + dx, y = static_cast<int>(std::floor(cy)) + dy;
      const double ex = x + 0.5 - cx, ey = y + 0.5 - cy;
      const double w = std::exp(-(ex * ex + ey * ey) / (0.5 * r * r));  // soft disc, ~r wide
      float& p = (*img)[static_cast<std::size_t>(((y % n + n) % n) * n + ((x % n + n) % n))];
      p += static_cast<float>(std::min(1.0, 1.5 * w)) * (value - p);
    }
}

// Separable [1 2 1]/4, wrapping.
void low_pass(Image* img, int n) {
  Image tmp(img->size());
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      tmp[static_cast<std::size_t>(y * n + x)] =
          0.25f * ((*img)[static_cast<std::size_t>(y * n + ((x + n - 1) % n))] + 2 * (*img)[static_cast<std::size_t>(y * n + x)] +
                   (*img)[static_cast<std::size_t>(y * n + ((x + 1) % n))]);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      (*img)[static_cast<std::size_t>(y * n + x)] =
          0.25f * (tmp[static_cast<std::size_t>(((y + n - 1) % n) * n + x)] + 2 * tmp[static_cast<std::size_t>(y * n + x)] +
                   tmp[static_cast<std::size_t>(((y + 1) % n) * n + x)]);
}

void stretch(Image* img, float lo, float hi) {
  const auto [mn, mx] = std::minmax_element(img->begin(), img->end());
  const float a = *mn, span = std::max(1e-6f, *mx - *mn);
  for (float& p : *img) p = lo + (hi - lo) * (p - a) / span;
}

Image generate(TextureKind kind, int n, std::mt19937_64& rng) {
  Image img(static_cast<std::size_t>(n) * n, 0.0f);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto uni = [&](double a, double b) { return a + (b - a) * unit(rng); };
  switch (kind) {
    case TextureKind::kValueNoise:
      add_value_noise(&img, n, 64, 1.0f, rng);
      add_value_noise(&img, n, 32, 0.6f, rng);
      add_value_noise(&img, n, 16, 0.45f, rng);
      add_value_noise(&img, n, 8, 0.3f, rng);
      add_value_noise(&img, n, 4, 0.2f, rng);
      break;
    case TextureKind::kBlobs: {
      add_value_noise(&img, n, 32, 0.15f, rng);
      for (float& p : img) p += 0.5f;
      const int count = n * n / 900;
      for (int k = 0; k < count; ++k) add_blob(&img, n, uni(0, n), uni(0, n), uni(3, 24), static_cast<float>(uni(0, 1)));
      break;
    }
    case TextureKind::kTiles: {
      const int cell = std::min(n, 1 << static_cast<int>(uni(4.0, 7.0)));  // 16, 32 or 64 (divides n)
      const int grout = std::max(2, cell / 12);
      for (int ty = 0; ty < n / cell; ++ty)
        for (int tx = 0; tx < n / cell; ++tx) {
          fill_rect(&img, n, tx * cell, ty * cell, cell, cell, static_cast<float>(uni(0.3, 0.9)), 1.0f);
          fill_rect(&img, n, tx * cell, ty * cell, cell, grout, 0.08f, 1.0f);
          fill_rect(&img, n, tx * cell, ty * cell, grout, cell, 0.08f, 1.0f);
        }
      add_value_noise(&img, n, 8, 0.08f, rng);
      break;
    }
    case TextureKind::kPosters: {
      add_value_noise(&img, n, 64, 0.2f, rng);
      add_value_noise(&img, n, 8, 0.08f, rng);
      for (float& p : img) p += 0.55f;
      const int count = n * n / 2500;
      for (int k = 0; k < count; ++k) {
        const int w = static_cast<int>(uni(12, 110)), h = static_cast<int>(uni(12, 110));
        const int x = static_cast<int>(uni(0, n)), y = static_cast<int>(uni(0, n));
        fill_rect(&img, n, x, y, w, h, static_cast<float>(uni(0, 1)), 1.0f);
        if (w > 30 && h > 30) fill_rect(&img, n, x + w / 4, y + h / 4, w / 2, h / 3, static_cast<float>(uni(0, 1)), 1.0f);
      }
      break;
    }
    case TextureKind::kClothing: {
      for (float& p : img) p = 0.5f;
      int y = 0;
      while (y < n) {
        const int h = static_cast<int>(uni(6, 40));
        fill_rect(&img, n, 0, y, n, std::min(h, n - y), static_cast<float>(uni(0.05, 0.95)), 1.0f);
        y += h;
      }
      const int count = n * n / 1600;
      for (int k = 0; k < count; ++k) {
        if (unit(rng) < 0.5)
          add_blob(&img, n, uni(0, n), uni(0, n), uni(3, 12), static_cast<float>(uni(0, 1)));
        else
          fill_rect(&img, n, static_cast<int>(uni(0, n)), static_cast<int>(uni(0, n)), static_cast<int>(uni(6, 30)),
                    static_cast<int>(uni(6, 30)), static_cast<float>(uni(0, 1)), 1.0f);
      }
      add_value_noise(&img, n, 8, 0.06f, rng);
      break;
    }
  }
  low_pass(&img, n);
  low_pass(&img, n);
  stretch(&img, 0.08f, 0.92f);
  return img;
}

}  // namespace

const char* to_string(TextureKind kind) {
  switch (kind) {
    case TextureKind::kValueNoise: return "value-noise";
    case TextureKind::kBlobs: return "blobs";
    case TextureKind::kTiles: return "tiles";
    case TextureKind::kPosters: return "posters";
    case TextureKind::kClothing: return "clothing";
  }
  return "?";
}

ProceduralTexture::ProceduralTexture(TextureKind kind, std::uint64_t seed, int size) : kind_(kind), size_(size) {
  if (size < 8 || (size & (size - 1)) != 0) throw std::invalid_argument("ProceduralTexture: size must be a power of two >= 8");
  std::mt19937_64 rng = texture_rng(seed, kind);
  levels_.push_back(generate(kind, size, rng));
  for (int n = size / 2; n >= 1; n /= 2) {
    const Image& fine = levels_.back();
    const int m = 2 * n;
    Image coarse(static_cast<std::size_t>(n) * n);
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        coarse[static_cast<std::size_t>(y * n + x)] =
            0.25f * (fine[static_cast<std::size_t>(2 * y * m + 2 * x)] + fine[static_cast<std::size_t>(2 * y * m + 2 * x + 1)] +
                     fine[static_cast<std::size_t>((2 * y + 1) * m + 2 * x)] +
                     fine[static_cast<std::size_t>((2 * y + 1) * m + 2 * x + 1)]);
    levels_.push_back(std::move(coarse));
  }
}

float ProceduralTexture::bilinear(int level, double u, double v) const {
  const int n = size_ >> level;
  const double scale = 1.0 / static_cast<double>(1 << level);
  const double fu = u * scale - 0.5, fv = v * scale - 0.5;
  const double x0f = std::floor(fu), y0f = std::floor(fv);
  const float tx = static_cast<float>(fu - x0f), ty = static_cast<float>(fv - y0f);
  // Wrap with a mask (n is a power of two); the casts keep negative coordinates correct.
  const int mask = n - 1;
  const int x0 = static_cast<int>(static_cast<long long>(x0f) & mask), y0 = static_cast<int>(static_cast<long long>(y0f) & mask);
  const int x1 = (x0 + 1) & mask, y1 = (y0 + 1) & mask;
  const float* img = levels_[static_cast<std::size_t>(level)].data();
  const float a = img[y0 * n + x0], b = img[y0 * n + x1], c = img[y1 * n + x0], d = img[y1 * n + x1];
  const float top = a + tx * (b - a), bottom = c + tx * (d - c);
  return top + ty * (bottom - top);
}

float ProceduralTexture::sample(double u, double v, double lod) const {
  const double top = static_cast<double>(levels_.size() - 1);
  if (!(lod > 0.0)) return bilinear(0, u, v);
  if (lod >= top) return levels_.back()[0];
  const int l = static_cast<int>(lod);
  const float f = static_cast<float>(lod - l);
  const float a = bilinear(l, u, v);
  return f == 0.0f ? a : a + f * (bilinear(l + 1, u, v) - a);
}

}  // namespace slamkit
