// Procedural, band-limited, tileable grayscale textures with a mip pyramid, for the rendered
// room (rendered_scene.h). Every texture is a square power-of-two image of albedo in [0, 1]
// that wraps around (u, v are taken modulo the size), generated from a seed:
//   value noise  Σ_o a_o · lerp_smooth(lattice_o) over lattice spacings 64, 32, 16, 8, 4 texels
//   blobs        Gaussian discs (radius 3–24 texels) of random albedo on low-contrast noise
//   tiles        a grid of tiles (cell 16, 32 or 64 texels) of random albedo with dark grout lines
//   posters      overlapping rectangles (12–110 texels) with inner frames and noise
//   clothing     horizontal bands and patches (people)
// then low-passed (two passes of the separable [1 2 1]/4 filter: no energy above ~1/4 cycle per
// texel, so a texel footprint of ≥ 1 px does not alias) and stretched to albedo [0.08, 0.92].
// Level k + 1 of the pyramid is the 2×2 box average of level k (wrapping), down to 1×1.
// sample() is trilinear: bilinear on levels ⌊λ⌋ and ⌊λ⌋ + 1, blended by the fraction of λ.
#pragma once

#include <cstdint>
#include <vector>

namespace slamkit {

enum class TextureKind { kValueNoise, kBlobs, kTiles, kPosters, kClothing };
const char* to_string(TextureKind kind);

class ProceduralTexture {
 public:
  /// size: a power of two ≥ 8 (std::invalid_argument otherwise).
  ProceduralTexture(TextureKind kind, std::uint64_t seed, int size = 512);

  int size() const { return size_; }
  int levels() const { return static_cast<int>(levels_.size()); }
  TextureKind kind() const { return kind_; }
  /// Texel (x, y) of level 0 (wrapping).
  float texel(int x, int y) const { return levels_[0][static_cast<std::size_t>((y & (size_ - 1)) * size_ + (x & (size_ - 1)))]; }
  /// Albedo at (u, v) in level-0 texels (texel centres at integers + 0.5), level of detail
  /// λ = log2(footprint in texels) clamped to [0, levels − 1].
  float sample(double u, double v, double lod) const;

 private:
  float bilinear(int level, double u, double v) const;
  TextureKind kind_;
  int size_;
  std::vector<std::vector<float>> levels_;
};

}  // namespace slamkit
