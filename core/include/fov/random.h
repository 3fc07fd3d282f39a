// Small, portable, seedable random numbers: identical streams on every platform
// (the standard library's distributions are not), so files are reproducible.
#pragma once

#include <cstdint>
#include <string>

namespace fov {

inline uint64_t splitmix64(uint64_t& state) {
  uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// xoshiro256** (Blackman & Vigna), seeded through splitmix64.
struct rng {
  uint64_t s[4];
  explicit rng(uint64_t seed) {
    for (auto& v : s) v = splitmix64(seed);
  }
  static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  uint64_t next() {
    const uint64_t result = rotl(s[1] * 5, 7) * 9, t = s[1] << 17;
    s[2] ^= s[0]; s[3] ^= s[1]; s[1] ^= s[2]; s[0] ^= s[3];
    s[2] ^= t; s[3] = rotl(s[3], 45);
    return result;
  }
  // Uniform in [0, 1) with 53 random bits.
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }
};

// A stream id from several integers (seed, phase, tile, ...).
inline uint64_t stream_seed(uint64_t a, uint64_t b, uint64_t c = 0) {
  uint64_t st = a;
  uint64_t h = splitmix64(st);
  st = h ^ b;
  h = splitmix64(st);
  st = h ^ c;
  return splitmix64(st);
}

// A stream id from text (FNV-1a: the same on every platform, unlike std::hash).
inline uint64_t text_seed(const std::string& text) {
  uint64_t h = 1469598103934665603ull;
  for (char c : text) h = (h ^ uint8_t(c)) * 1099511628211ull;
  return h;
}

}  // namespace fov
