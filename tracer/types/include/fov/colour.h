// The sRGB transfer function (IEC 61966-2-1), per channel: textures are decoded with it,
// displayed images and their metrics encoded with it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

namespace fov {

// Linear light to sRGB-encoded, clamped to [0, 1] first.
inline float srgb_encode(float linear) {
  const float v = std::clamp(linear, 0.0f, 1.0f);
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1 / 2.4f) - 0.055f;
}

inline float srgb_decode(float encoded) {
  return encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

// A linear value as a display shows it: clamped, sRGB-encoded and quantised to a byte (what
// PNGs hold; every metric scores frames this way).
inline uint8_t display_byte(float linear) { return uint8_t(std::lround(255 * srgb_encode(linear))); }

inline glm::vec3 srgb_decode(glm::vec3 c) { return {srgb_decode(c.r), srgb_decode(c.g), srgb_decode(c.b)}; }
// Relative luminance of a linear Rec. 709 colour.
inline float luminance(glm::vec3 c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

}  // namespace fov
