#include "image_io.h"

#include <cmath>
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include <fmt/format.h>
#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include "fov/colour.h"
#include "fov/pointset_io.h"

namespace fov {

std::string image_format_problem(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext.empty()) return "no extension to choose the image format by";
  if (!OIIO::ImageOutput::create(ext.substr(1))) return fmt::format("unsupported image format '{}'", ext);
  return "";
}

void write_frame(const frame& f, const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (const std::string why = image_format_problem(path); !why.empty()) throw file_error(fmt::format("{}: {}", path, why));
  const bool linear = ext == ".exr" || ext == ".EXR" || ext == ".hdr";
  auto out = OIIO::ImageOutput::create(ext.substr(1));
  temp_output tmp(path, ext);  // OpenImageIO picks the format by the name's extension
  // An EXR keeps the depth too, as channel Z (+inf where no ray hit), when the frame has it.
  const bool depth = (ext == ".exr" || ext == ".EXR") && f.depth.size() == f.rgb.size();
  const int channels = depth ? 4 : 3;
  OIIO::ImageSpec spec(f.width, f.height, channels, linear ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  if (depth) spec.channelnames = {"R", "G", "B", "Z"}, spec.z_channel = 3;
  std::vector<float> px(size_t(f.width) * f.height * channels);
  for (size_t i = 0; i < f.rgb.size(); ++i) {
    for (int c = 0; c < 3; ++c) px[channels * i + c] = linear ? f.rgb[i][c] : srgb_encode(f.rgb[i][c]);
    if (depth) px[channels * i + 3] = f.depth[i];
  }
  if (!linear) spec.attribute("oiio:ColorSpace", "sRGB");
  if (!(out->open(tmp.temp_path(), spec) && out->write_image(OIIO::TypeDesc::FLOAT, px.data()) && out->close()))
    throw file_error(fmt::format("{}: cannot write: {}", path, first_line(out->geterror())));
  tmp.commit();
}

frame read_frame(const std::string& path) {
  if (const std::string why = input_file_problem(path); !why.empty()) throw file_error(fmt::format("{}: {}", path, why));
  const stderr_silenced quiet;  // libpng prints its own line for what OpenImageIO reports below
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw file_error(fmt::format("{}: cannot read image: {}", path, first_line(OIIO::geterror())));
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.nchannels < 3) throw file_error(fmt::format("{}: need an RGB image, got {} channels", path, spec.nchannels));
  // The size the header declares, against memory, before anything is allocated for it.
  const uint64_t bytes = uint64_t(spec.width) * uint64_t(spec.height) * uint64_t(spec.nchannels) * 4 * 2;
  if (const std::string why = memory_problem(bytes, fmt::format("a {} x {} image", spec.width, spec.height)); !why.empty())
    throw file_error(fmt::format("{}: {}", path, why));
  frame f;
  f.width = spec.width;
  f.height = spec.height;
  std::vector<float> px(size_t(spec.width) * spec.height * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()))
    throw file_error(fmt::format("{}: cannot read image: {}", path, first_line(in->geterror())));
  const bool encoded = spec.format.basetype == OIIO::TypeDesc::UINT8 || spec.format.basetype == OIIO::TypeDesc::UINT16;
  f.rgb.resize(size_t(f.width) * f.height);
  for (size_t i = 0; i < f.rgb.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const float v = px[i * spec.nchannels + c];
      f.rgb[i][c] = encoded ? srgb_decode(v) : v;
    }
  const auto z = std::find(spec.channelnames.begin(), spec.channelnames.end(), "Z");
  if (z != spec.channelnames.end() && z - spec.channelnames.begin() >= 3) {
    const size_t zc = size_t(z - spec.channelnames.begin());
    f.depth.resize(f.rgb.size());
    for (size_t i = 0; i < f.depth.size(); ++i) f.depth[i] = px[i * spec.nchannels + zc];
  }
  size_t bad = 0, first = 0;
  for (size_t i = 0; i < f.rgb.size(); ++i) {
    const glm::vec3& c = f.rgb[i];
    const bool colour_ok = c.r >= 0 && c.g >= 0 && c.b >= 0 && c.r <= max_image_value && c.g <= max_image_value &&
                           c.b <= max_image_value;  // false for NaN too
    const bool depth_ok = f.depth.empty() || f.depth[i] >= 0;
    if (!(colour_ok && depth_ok) && bad++ == 0) first = i;
  }
  if (bad)
    throw file_error(fmt::format("{}: {} pixel{} NaN, infinite, negative or above {} (first at x = {}, y = {}): not an image "
                                 "to measure",
                                 path, bad, bad == 1 ? " is" : "s are", max_image_value, first % size_t(f.width),
                                 first / size_t(f.width)));
  return f;
}

}  // namespace fov
