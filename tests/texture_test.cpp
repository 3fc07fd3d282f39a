// Material textures as in-memory MIP pyramids (tracer/src/textures.cpp): exact texels at
// their centres, periodic wrap, the mean at a wide footprint for any size, channels as the
// file has them, and unreadable files warned about, not traced with.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>

#include "../tracer/src/scene_impl.h"
#include "fov/trace.h"

namespace fs = std::filesystem;
using namespace fov;


namespace {

// Writes a w x h image of n channels, value(x, y, c) each, in `type` (UINT8 or UINT16).
template <typename Value>
std::string write_image(const fs::path& file, int w, int h, int n, OIIO::TypeDesc type, Value&& value) {
  std::vector<float> px(size_t(w) * size_t(h) * size_t(n));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < n; ++c) px[(size_t(y) * size_t(w) + size_t(x)) * size_t(n) + size_t(c)] = value(x, y, c);
  auto out = OIIO::ImageOutput::create(file.string());
  OIIO::ImageSpec spec(w, h, n, type);
  spec.attribute("oiio:UnassociatedAlpha", 1);  // the values as given, not divided by alpha
  out->open(file.string(), spec);
  out->write_image(OIIO::TypeDesc::FLOAT, px.data());
  out->close();
  return file.string();
}

struct scratch {
  fs::path dir = fs::temp_directory_path() / ("fovray-textures-" + std::to_string(getpid()));
  scratch() { fs::create_directories(dir); }
  ~scratch() { fs::remove_all(dir); }
};

float byte(int x, int y, int c) { return float((37 * x + 101 * y + 59 * c) % 256) / 255; }

}  // namespace

TEST(Textures, TexelCentresReadTheirTexelAndWrapPeriodically) {
  const scratch s;
  const int w = 8, h = 4;
  const texture_pyramid t = load_texture_pyramid(write_image(s.dir / "rgba.png", w, h, 4, OIIO::TypeDesc::UINT8, byte));
  ASSERT_EQ(t.levels.size(), 4u);  // 8 x 4, 4 x 2, 2 x 1, 1 x 1
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const glm::vec2 centre((float(x) + 0.5f) / w, (float(y) + 0.5f) / h);
      for (const glm::vec2 shift : {glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(-2, 3)}) {
        const glm::vec4 v = t.lookup(centre + shift, 0);
        for (int c = 0; c < 4; ++c) EXPECT_NEAR(v[c], byte(x, y, c), 1e-6f) << x << "," << y << " shift " << shift.x;
      }
    }
  // Halfway between the last column and the first: both, half each (the wrap is periodic).
  const glm::vec4 edge = t.lookup({0.0f, 0.5f / h}, 0);
  for (int c = 0; c < 4; ++c) EXPECT_NEAR(edge[c], 0.5f * (byte(w - 1, 0, c) + byte(0, 0, c)), 1e-6f);
  // A coordinate or footprint that is not finite reads the finest level's first texel.
  const float nan = std::nanf(""), inf = INFINITY;
  for (const auto& [uv, duv] : std::vector<std::pair<glm::vec2, float>>{
           {{nan, 0.5f / h}, 0}, {{0.5f / w, inf}, 0}, {{-inf, nan}, 0}, {{0.5f / w, 0.5f / h}, nan}}) {
    const glm::vec4 v = t.lookup(uv, duv);
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(v[c], byte(0, 0, c), 1e-6f) << uv.x << "," << uv.y << " footprint " << duv;
  }
}

TEST(Textures, AWideFootprintReadsTheMeanForEverySize) {
  // Odd sizes too: each level keeps the mean (partly covered texels count by their part).
  const scratch s;
  for (const glm::ivec2 size : {glm::ivec2(8, 8), glm::ivec2(5, 3), glm::ivec2(7, 1), glm::ivec2(1, 9)}) {
    const std::string file = write_image(s.dir / "odd.png", size.x, size.y, 3, OIIO::TypeDesc::UINT8, byte);
    const texture_pyramid t = load_texture_pyramid(file);
    EXPECT_EQ(t.levels.back().width, 1);
    EXPECT_EQ(t.levels.back().height, 1);
    for (int c = 0; c < 3; ++c) {
      double mean = 0;
      for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x) mean += byte(x, y, c);
      mean /= double(size.x * size.y);
      // Each level is rounded to 8 bits: half a step per level at most.
      const float slack = 0.5f / 255 * float(t.levels.size());
      EXPECT_NEAR(t.lookup({0.3f, 0.7f}, 4.0f)[c], mean, slack) << size.x << " x " << size.y << " channel " << c;
    }
    EXPECT_EQ(t.lookup({0.3f, 0.7f}, 4.0f).a, 1.0f) << "no alpha channel: alpha 1";
  }
}

TEST(Textures, ChannelsAreReadAsTheFileHasThem) {
  const scratch s;
  auto grey = [](int x, int, int c) { return c == 0 ? float(x * 80) / 255 : 0.25f; };
  const texture_pyramid g = load_texture_pyramid(write_image(s.dir / "g.png", 4, 1, 1, OIIO::TypeDesc::UINT8, grey));
  const glm::vec4 v = g.lookup({2.5f / 4, 0.5f}, 0);
  EXPECT_EQ(v, glm::vec4(160.0f / 255, 160.0f / 255, 160.0f / 255, 1)) << "grey replicated, alpha 1";
  const texture_pyramid ga = load_texture_pyramid(write_image(s.dir / "ga.png", 4, 1, 2, OIIO::TypeDesc::UINT8, grey));
  const glm::vec4 a = ga.lookup({2.5f / 4, 0.5f}, 0);
  EXPECT_EQ(a, glm::vec4(160.0f / 255, 160.0f / 255, 160.0f / 255, 64.0f / 255)) << "grey and alpha";
  EXPECT_FALSE(g.levels[0].bytes.empty()) << "8-bit files keep 8 bits";
  // 16-bit files keep their precision (floats): a value between two 8-bit steps stays there.
  auto fine = [](int, int, int) { return 1000.0f / 65535; };
  const texture_pyramid d = load_texture_pyramid(write_image(s.dir / "d.png", 2, 2, 3, OIIO::TypeDesc::UINT16, fine));
  EXPECT_TRUE(d.levels[0].bytes.empty());
  EXPECT_NEAR(d.lookup({0.25f, 0.25f}, 0).r, 1000.0f / 65535, 1e-6f);
}

TEST(Textures, ATextureThatDoesNotDecodeWarnsAndFallsBackToTheFactors) {
  // Its header reads, its pixels do not: the loader's check passes, the read warns. (TGA: a
  // truncated PNG makes OpenImageIO 2.4 leak its error message, a longjmp out of libpng.)
  const scratch s;
  const std::string whole = write_image(s.dir / "whole.tga", 64, 64, 3, OIIO::TypeDesc::UINT8,
                                        [](int x, int y, int) { return float((x * 7 + y * 13) % 256) / 255; });
  fs::copy_file(whole, s.dir / "cut.tga");
  fs::resize_file(s.dir / "cut.tga", fs::file_size(whole) / 2);
  std::ofstream(s.dir / "quad.mtl") << "newmtl a\nKd 0.2 0.4 0.6\nmap_Kd cut.tga\n";
  std::ofstream(s.dir / "quad.obj") << "mtllib quad.mtl\nv -1 -1 -3\nv 1 -1 -3\nv 1 1 -3\nv -1 1 -3\n"
                                       "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl a\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
  const auto sc = load_scene((s.dir / "quad.obj").string());
  int warned = 0;
  for (const std::string& w : sc->warnings()) {
    warned += w.find("cut.tga") != std::string::npos && w.find("cannot read texture") != std::string::npos &&
              w.find("using the material's factors") != std::string::npos;
    EXPECT_EQ(w.find('\n'), std::string::npos) << "one line: " << w;
  }
  EXPECT_EQ(warned, 1);
  trace_params tp;
  tp.spp = 1;
  const frame f = trace_reference(*sc, look_at({0, 0, 0}, {0, 0, -1}, 60), 5, 5, tp).image;
  EXPECT_GT(f.rgb[12].b, 2 * f.rgb[12].r) << "the factors (0.2, 0.4, 0.6)";
  EXPECT_GT(f.rgb[12].g, 1.5f * f.rgb[12].r);
}
