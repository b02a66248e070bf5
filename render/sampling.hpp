// Deterministic sample positions for supersampling: correlated multi-jittered sampling (A. Kensler,
// "Correlated Multi-Jittered Sampling", Pixar Technical Memo 13-01, 2013). For any count N the N samples
// are stratified in both axes (one per 1/N column and one per 1/N row) and jittered inside their cells.
// Every pattern is a pure function of (index, count, seed): no state, so a picture does not depend on the
// order in which threads take its pixels.
#pragma once

#include <cmath>
#include <cstdint>

#include <Eigen/Core>

namespace beadtwin::render {

// A bijection of [0, count) chosen by `seed` (hashing with cycle walking).
inline std::uint32_t permute(std::uint32_t i, std::uint32_t count, std::uint32_t seed) {
  std::uint32_t w = count - 1;
  w |= w >> 1;
  w |= w >> 2;
  w |= w >> 4;
  w |= w >> 8;
  w |= w >> 16;
  do {
    i ^= seed;
    i *= 0xe170893du;
    i ^= seed >> 16;
    i ^= (i & w) >> 4;
    i ^= seed >> 8;
    i *= 0x0929eb3fu;
    i ^= seed >> 23;
    i ^= (i & w) >> 1;
    i *= 1u | seed >> 27;
    i *= 0x6935fa69u;
    i ^= (i & w) >> 11;
    i *= 0x74dcb303u;
    i ^= (i & w) >> 2;
    i *= 0x9e501cc3u;
    i ^= (i & w) >> 2;
    i *= 0xc860a3dfu;
    i &= w;
    i ^= i >> 5;
  } while (i >= count);
  return (i + seed) % count;
}

// A hash of (i, seed) to [0, 1).
inline float hash_float(std::uint32_t i, std::uint32_t seed) {
  i ^= seed;
  i ^= i >> 17;
  i ^= i >> 10;
  i *= 0xb36534e5u;
  i ^= i >> 12;
  i ^= i >> 21;
  i *= 0x93fc4795u;
  i ^= 0xdf6e307fu;
  i ^= i >> 17;
  i *= 1u | seed >> 18;
  return static_cast<float>(i >> 8) * (1.0f / 16777216.0f);  // the top 24 bits: exact in a float, < 1
}

// Sample `index` of `count` (index < count) of pattern `seed`, in the unit square.
inline Eigen::Vector2f cmj_sample(std::uint32_t index, std::uint32_t count, std::uint32_t seed) {
  const auto m = static_cast<std::uint32_t>(std::sqrt(static_cast<double>(count)));  // columns
  const std::uint32_t n = (count + m - 1) / m;                                       // rows
  const std::uint32_t s = permute(index, count, seed * 0x51633e2du);
  const std::uint32_t sx = permute(s % m, m, seed * 0x68bc21ebu);
  const std::uint32_t sy = permute(s / m, n, seed * 0x02e5be93u);
  const float jx = hash_float(s, seed * 0x967a889bu);
  const float jy = hash_float(s, seed * 0x368cc8b7u);
  return {(static_cast<float>(sx) + (static_cast<float>(sy) + jx) / static_cast<float>(n)) /
              static_cast<float>(m),
          (static_cast<float>(s) + jy) / static_cast<float>(count)};
}

// A well-mixed 32-bit seed for pixel (x, y) of an image.
inline std::uint32_t pixel_seed(int x, int y) {
  std::uint32_t h = static_cast<std::uint32_t>(x) * 0x8da6b343u ^ static_cast<std::uint32_t>(y) * 0xd8163841u;
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
  return h;
}

}  // namespace beadtwin::render
