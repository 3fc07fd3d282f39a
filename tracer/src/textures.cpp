// Images in memory as MIP pyramids: material textures and the environment image.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>
#include <stdexcept>

#include <fmt/format.h>
#include <OpenImageIO/imageio.h>

#include "fov/colour.h"
#include "fov/files.h"
#include "scene_impl.h"

namespace fov {

namespace {

// An image's texels as float (a MIP level, or a whole file).
struct float_level {
  int width = 0, height = 0, channels = 0;
  std::vector<float> values;  // row-major, channels interleaved
};

// A whole image read as float, with its file's pixel format. Through an ImageInput of its
// own, never OpenImageIO's shared image cache: the cache keeps a file's header by name, so
// an image rewritten with another size in the same process was read into a buffer sized by
// the stale header (a heap overflow the env_image fuzz target found). Images past
// max_image_texels are refused before their pixels are allocated. Throws std::runtime_error
// naming the file and `what` it is.
struct float_image {
  float_level texels;
  OIIO::TypeDesc format;  // the file's
};
float_image read_float_image(const std::string& file, const char* what) {
  // Colour as the file stores it: glTF's colours are not premultiplied by alpha, and
  // OpenImageIO would multiply PNG's colour by alpha when it reads (its texture system did).
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(file, &config);
  float_image out;
  bool read = false;
  if (in) {
    const OIIO::ImageSpec& s = in->spec();
    if (s.width <= 0 || s.height <= 0 || s.nchannels <= 0 ||
        uint64_t(s.width) * uint64_t(s.height) > max_image_texels)
      throw std::runtime_error(fmt::format("{}: cannot read {}: it is {} x {} texels, more than the {} a {} may have",
                                           file, what, s.width, s.height, max_image_texels, what));
    if (s.width > max_image_side || s.height > max_image_side)
      throw std::runtime_error(fmt::format("{}: cannot read {}: it is {} x {} texels, and neither side may exceed {}", file,
                                           what, s.width, s.height, max_image_side));
    out.format = s.format;
    out.texels = {s.width, s.height, s.nchannels, {}};
    out.texels.values.resize(size_t(s.width) * size_t(s.height) * size_t(s.nchannels));
    read = in->read_image(0, 0, 0, s.nchannels, OIIO::TypeDesc::FLOAT, out.texels.values.data());
  }
  if (!read)
    throw std::runtime_error(
        fmt::format("{}: cannot read {}: {}", file, what, first_line(in ? in->geterror() : OIIO::geterror())));
  return out;
}

// One MIP level from the one above: half its size each way (rounded down, at least 1),
// each texel the mean of the source area it covers (2 x 2 texels where the size is even;
// where it is odd, partly covered texels count by the part covered). Separable box filter.
float_level halve(const float_level& in) {
  auto weights = [](int from, int to) {  // per output texel: (first source texel, weights)
    std::vector<std::pair<int, std::vector<float>>> out(static_cast<size_t>(to));
    const double ratio = double(from) / double(to);
    for (int i = 0; i < to; ++i) {
      const double a = i * ratio, b = (i + 1) * ratio;
      const int first = int(std::floor(a)), last = std::min(from - 1, int(std::ceil(b)) - 1);
      out[size_t(i)].first = first;
      for (int k = first; k <= last; ++k)
        out[size_t(i)].second.push_back(float((std::min(b, double(k + 1)) - std::max(a, double(k))) / ratio));
    }
    return out;
  };
  const int c = in.channels;
  float_level out{std::max(1, in.width / 2), std::max(1, in.height / 2), c, {}};
  const auto wx = weights(in.width, out.width), wy = weights(in.height, out.height);
  std::vector<float> rows(size_t(out.width) * size_t(in.height) * size_t(c), 0.0f);  // halved along x
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      float* o = rows.data() + (size_t(y) * size_t(out.width) + size_t(x)) * size_t(c);
      for (size_t k = 0; k < wx[size_t(x)].second.size(); ++k) {
        const float* p = in.values.data() + (size_t(y) * size_t(in.width) + size_t(wx[size_t(x)].first) + k) * size_t(c);
        for (int ch = 0; ch < c; ++ch) o[ch] += wx[size_t(x)].second[k] * p[ch];
      }
    }
  out.values.assign(size_t(out.width) * size_t(out.height) * size_t(c), 0.0f);
  for (int y = 0; y < out.height; ++y)
    for (size_t k = 0; k < wy[size_t(y)].second.size(); ++k) {
      const float w = wy[size_t(y)].second[k];
      const float* p = rows.data() + size_t(wy[size_t(y)].first + int(k)) * size_t(out.width) * size_t(c);
      float* o = out.values.data() + size_t(y) * size_t(out.width) * size_t(c);
      for (size_t i = 0; i < size_t(out.width) * size_t(c); ++i) o[i] += w * p[i];
    }
  return out;
}

// Calls take(level) for `finest` and each level below it (halve), down to 1 x 1.
template <typename Take>
void for_each_level(float_level finest, Take&& take) {
  for (;;) {
    take(finest);
    if (finest.width == 1 && finest.height == 1) return;
    finest = halve(finest);
  }
}

// The two texels a bilinear tap reads along one axis of `size` texels at texel coordinate
// x (texel centres at i + 0.5), and the weight of the second; periodic or clamped.
struct axis_taps {
  int i0, i1;
  float a;
};
// A coordinate that is not finite (a NaN uv from a degenerate triangle) reads the first
// texel; it is never converted to int, where it would be undefined.
axis_taps periodic_taps(float x, int size) {
  if (!std::isfinite(x)) return {0, 0, 0.0f};
  const float f = std::floor(x);
  int i0 = int(std::fmod(f, float(size)));  // (exact for the integers a float holds)
  if (i0 < 0) i0 += size;
  i0 = std::clamp(i0, 0, size - 1);
  const int i1 = i0 + 1 == size ? 0 : i0 + 1;
  return {i0, i1, x - f};
}
axis_taps clamped_taps(float x, int size) {
  if (!std::isfinite(x)) return {0, 0, 0.0f};
  const float y = std::clamp(x, 0.0f, float(size - 1));
  const float f = std::floor(y);
  const int i0 = std::clamp(int(f), 0, size - 1);
  return {i0, std::min(i0 + 1, size - 1), y - f};
}

// Trilinear: bilinear(level) at the two MIP levels around a footprint of `texels` texels of
// the finest level, blended linearly between them.
template <typename Level, typename Bilinear>
auto trilinear(const std::vector<Level>& levels, float texels, Bilinear&& bilinear) {
  // (A NaN footprint reads the finest level: the comparison is false for it.)
  const float lod = std::clamp(std::log2(texels > 1e-6f ? texels : 1e-6f), 0.0f, float(levels.size() - 1));
  const int l0 = int(lod);
  const int l1 = std::min(l0 + 1, int(levels.size()) - 1);
  const auto a = bilinear(levels[size_t(l0)]);
  return l1 == l0 ? a : glm::mix(a, bilinear(levels[size_t(l1)]), lod - float(l0));
}

}  // namespace

glm::vec4 texture_pyramid::lookup(glm::vec2 uv, float duv) const {
  const level& top = levels.front();
  return trilinear(levels, duv * float(std::max(top.width, top.height)), [&](const level& m) {
    const axis_taps x = periodic_taps(uv.x * float(m.width) - 0.5f, m.width);
    const axis_taps y = periodic_taps(uv.y * float(m.height) - 0.5f, m.height);
    const size_t r0 = size_t(y.i0) * size_t(m.width), r1 = size_t(y.i1) * size_t(m.width);
    auto at = [&](size_t i) {
      if (!m.bytes.empty()) {
        const uint8_t* b = m.bytes.data() + 4 * i;
        return glm::vec4(b[0], b[1], b[2], b[3]) * (1.0f / 255);
      }
      const float* f = m.floats.data() + 4 * i;
      return glm::vec4(f[0], f[1], f[2], f[3]);
    };
    return glm::mix(glm::mix(at(r0 + size_t(x.i0)), at(r0 + size_t(x.i1)), x.a),
                    glm::mix(at(r1 + size_t(x.i0)), at(r1 + size_t(x.i1)), x.a), y.a);
  });
}

texture_pyramid load_texture_pyramid(const std::string& file) {
  float_image image = read_float_image(file, "texture");
  const float_level& file_texels = image.texels;
  // Four channels: grey is replicated to RGB, a missing alpha is 1.
  const int n = file_texels.channels;
  const int rgb[3] = {0, n >= 3 ? 1 : 0, n >= 3 ? 2 : 0};
  const int alpha = n == 2 ? 1 : (n >= 4 ? 3 : -1);
  float_level rgba{file_texels.width, file_texels.height, 4, {}};
  {
    const size_t texels = size_t(rgba.width) * size_t(rgba.height);
    rgba.values.resize(4 * texels);
    const float* in = file_texels.values.data();
    float* out = rgba.values.data();
    for (size_t i = 0; i < texels; ++i) {
      for (int c = 0; c < 3; ++c) out[4 * i + size_t(c)] = in[i * size_t(n) + size_t(rgb[c])];
      out[4 * i + 3] = alpha < 0 ? 1.0f : in[i * size_t(n) + size_t(alpha)];
      for (int c = 0; c < 4; ++c)
        if (!std::isfinite(out[4 * i + size_t(c)])) out[4 * i + size_t(c)] = 0;  // (float files only)
    }
  }
  image.texels = {};
  // 8-bit files keep 8 bits a channel (a quarter of the memory), every level rounded to them
  // (each filtered from the float values of the one above); deeper files keep floats.
  const bool bytes = image.format == OIIO::TypeDesc::UINT8;
  texture_pyramid out;
  for_each_level(std::move(rgba), [&](const float_level& level) {
    texture_pyramid::level l;
    l.width = level.width, l.height = level.height;
    if (bytes) {
      l.bytes.resize(level.values.size());
      for (size_t i = 0; i < level.values.size(); ++i)
        l.bytes[i] = uint8_t(std::clamp(level.values[i], 0.0f, 1.0f) * 255 + 0.5f);
    } else {
      l.floats = level.values;
    }
    out.levels.push_back(std::move(l));
  });
  return out;
}

glm::vec3 env_pyramid::lookup(float s, float t, float ds, float dt) const {
  const level& top = levels.front();
  // The levels whose texels match the footprint (the larger of its two extents).
  return trilinear(levels, std::max(ds * float(top.width), dt * float(top.height)), [&](const level& m) {
    const axis_taps x = periodic_taps(s * float(m.width) - 0.5f, m.width);
    const axis_taps y = clamped_taps(t * float(m.height) - 0.5f, m.height);
    const glm::vec3* r0 = m.texels.data() + size_t(y.i0) * size_t(m.width);
    const glm::vec3* r1 = m.texels.data() + size_t(y.i1) * size_t(m.width);
    return glm::mix(glm::mix(r0[x.i0], r0[x.i1], x.a), glm::mix(r1[x.i0], r1[x.i1], x.a), y.a);
  });
}

env_pyramid load_env_pyramid(const std::string& file) {
  float_image image;
  {
    const stderr_silenced quiet;  // libpng prints its own line for what OpenImageIO reports
    image = read_float_image(file, "environment image");
  }
  const OIIO::TypeDesc f = image.format;  // the file's pixel format says sRGB or linear
  const bool srgb = !(f == OIIO::TypeDesc::FLOAT || f == OIIO::TypeDesc::HALF || f == OIIO::TypeDesc::DOUBLE);
  // The finest level, cleaned and (from 8-bit files) decoded to linear; every coarser one
  // is filtered from it.
  const int n = image.texels.channels;
  env_pyramid out;
  float_level linear{image.texels.width, image.texels.height, 3, {}};
  {
    const size_t texels = size_t(linear.width) * size_t(linear.height);
    linear.values.resize(3 * texels);
    const float* in = image.texels.values.data();
    for (size_t i = 0; i < texels; ++i)
      for (int c = 0; c < 3; ++c) {
        float v = in[i * size_t(n) + size_t(std::min(c, n - 1))];
        if (!std::isfinite(v)) v = 0, ++out.non_finite;
        if (v < 0) v = 0, ++out.negative;
        if (v > max_env_value) v = max_env_value, ++out.too_bright;
        linear.values[3 * i + size_t(c)] = srgb ? srgb_decode(v) : v;
      }
  }
  image.texels = {};
  for_each_level(std::move(linear), [&](const float_level& level) {
    env_pyramid::level l;
    l.width = level.width, l.height = level.height;
    l.texels.resize(size_t(level.width) * size_t(level.height));
    std::memcpy(static_cast<void*>(l.texels.data()), level.values.data(), level.values.size() * sizeof(float));
    out.levels.push_back(std::move(l));
  });
  return out;
}

}  // namespace fov
