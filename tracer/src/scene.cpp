#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "fov/files.h"
#include "fov/scene.h"
#include "fov/usage_error.h"
#include "fov/random.h"
#include "scene_impl.h"

namespace fov {

namespace {

constexpr float pi = 3.14159265358979323846f;

// A number in [0, 1) fixed by the ray (its origin and direction) and the surface point it
// met (instance, triangle): a blended surface's coin for this ray.
float blend_coin(const RTCFilterFunctionNArguments* args, unsigned i) {
  const float values[6] = {RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                           RTCRayN_org_z(args->ray, args->N, i), RTCRayN_dir_x(args->ray, args->N, i),
                           RTCRayN_dir_y(args->ray, args->N, i), RTCRayN_dir_z(args->ray, args->N, i)};
  uint32_t bits[6];
  std::memcpy(bits, values, sizeof bits);
  const uint64_t ray = stream_seed((uint64_t(bits[0]) << 32) | bits[1], (uint64_t(bits[2]) << 32) | bits[3],
                                   (uint64_t(bits[4]) << 32) | bits[5]);
  const uint64_t where = (uint64_t(RTCHitN_instID(args->hit, args->N, i, 0)) << 32) | RTCHitN_primID(args->hit, args->N, i);
  return float(stream_seed(ray, where) >> 40) * 0x1.0p-24f;
}

// Drops hits by the material's alpha: below its cutoff (glTF MASK), or with probability
// 1 - alpha (glTF BLEND, stochastic transparency). Alpha is read at the finest texture
// level: a hit-or-miss decision per ray.
void alpha_filter(const RTCFilterFunctionNArguments* args) {
  const auto* g = static_cast<const geometry_data*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
    const float u = RTCHitN_u(args->hit, args->N, i), v = RTCHitN_v(args->hit, args->N, i);
    glm::vec2 uv(0);
    if (!g->m->uvs.empty()) {
      const glm::uvec3 t = g->m->triangles[prim];
      uv = (1 - u - v) * g->m->uvs[t.x] + u * g->m->uvs[t.y] + v * g->m->uvs[t.z];
    }
    const float alpha = g->owner->base_colour(*g->mat, uv, 0).a;
    const bool kept = g->mat->alpha == alpha_mode::mask ? alpha >= g->mat->alpha_cutoff : blend_coin(args, i) < alpha;
    if (!kept) args->valid[i] = 0;
  }
}

double square_wave_integral(double x) {  // integral of a 0/1 square wave of period 2, high on [1, 2)
  const double f = std::floor(x / 2);
  return f + std::max(x - 2 * f - 1, 0.0);
}

// The box-filtered square wave, in [0, 1]. In double: both integrals grow with x while their
// difference is about w, so in float a small footprint far along the pattern cancelled to
// noise outside [0, 1] (negative colours on the built-in floor at 256+ rays a pixel, 70 ppd).
float filtered_square(float x, float w) {
  if (w < 1e-6f) return std::fmod(std::floor(x), 2.0f) != 0 ? 1.0f : 0.0f;
  const double half = 0.5 * double(w);
  return float(std::clamp((square_wave_integral(double(x) + half) - square_wave_integral(double(x) - half)) / double(w), 0.0, 1.0));
}

uint32_t hash2(int x, int y) {
  uint32_t h = uint32_t(x) * 0x8da6b343u ^ uint32_t(y) * 0xd8163841u;
  h ^= h >> 13;
  h *= 0x85ebca6bu;
  return h ^ (h >> 16);
}

}  // namespace

float filtered_checker(glm::vec2 p, float w) {
  const float sx = filtered_square(p.x, w), sy = filtered_square(p.y, w);
  return sx * (1 - sy) + (1 - sx) * sy;
}

// Text-like rows of 5x7-dot glyphs (random bitmaps), one glyph per pattern cell with
// margins; fades to its mean coverage once a dot is smaller than the footprint.
float filtered_glyphs(glm::vec2 p, float w) {
  const float mean = 0.5f * (5.0f * 7.0f) / (7.0f * 9.0f);  // half the dots lit, glyph box 5x7 of 7x9
  const int cx = int(std::floor(p.x)), cy = int(std::floor(p.y));
  const float fx = p.x - float(cx), fy = p.y - float(cy);
  const int gx = int(std::floor(fx * 7)) - 1, gy = int(std::floor(fy * 9)) - 1;
  float sharp = 0;
  if (gx >= 0 && gx < 5 && gy >= 0 && gy < 7 && (cy % 3 != 2)) {  // every third row is line spacing
    const uint32_t bits = hash2(cx, cy);
    const uint32_t more = hash2(cy, cx + 7919);
    const int bit = gy * 5 + gx;
    sharp = float(((bit < 32 ? bits >> bit : more >> (bit - 32)) & 1u));
  }
  const float row_mean = mean * 2.0f / 3.0f;
  const float t = std::clamp((w - 1.0f / 9) / (0.5f - 1.0f / 9), 0.0f, 1.0f);
  return sharp * (1 - t) + row_mean * t;
}

float leaf_alpha(glm::vec2 uv) {
  // A pointed leaf along v: half-width 0.45 sin(pi v)^0.7 around u = 0.5.
  if (uv.y <= 0 || uv.y >= 1) return 0;
  const float half = 0.45f * std::pow(std::sin(pi * uv.y), 0.7f);
  return std::fabs(uv.x - 0.5f) < half ? 1.0f : 0.0f;
}

glm::vec4 scene::impl::base_colour(const material& mat, glm::vec2 uv, float duv) const {
  glm::vec4 c = mat.base_colour;
  if (const texture_pyramid* image = textures_of(mat).base) {
    const glm::vec4 t = image->lookup(uv, duv);
    glm::vec3 rgb(t);
    if (mat.base_texture.srgb) rgb = srgb_decode(rgb);
    c *= glm::vec4(rgb, t.a);
  }
  const glm::vec2 p = uv * mat.pattern_repeats;
  const float w = duv * mat.pattern_repeats;
  switch (mat.procedural) {
    case pattern::none: break;
    case pattern::checker: {
      const float f = filtered_checker(p, w);
      c = glm::vec4(glm::mix(glm::vec3(c), mat.pattern_colour, f), c.a);
      break;
    }
    case pattern::glyphs: {
      const float f = filtered_glyphs(p, w);
      c = glm::vec4(glm::mix(glm::vec3(c), mat.pattern_colour, f), c.a);
      break;
    }
    case pattern::leaf: c.a *= leaf_alpha(uv); break;
  }
  return c;
}

glm::vec2 scene::impl::metallic_roughness(const material& mat, glm::vec2 uv, float duv) const {
  glm::vec2 mr(mat.metallic, mat.roughness);
  if (const texture_pyramid* image = textures_of(mat).metallic_roughness) {
    const glm::vec4 t = image->lookup(uv, duv);
    mr *= glm::vec2(t.b, t.g);
  }
  return glm::clamp(mr, 0.0f, 1.0f);
}

float scene::impl::occlusion(const material& mat, glm::vec2 uv, float duv) const {
  const texture_pyramid* image = textures_of(mat).occlusion;
  if (!image) return 1;
  return std::clamp(1 + mat.occlusion_strength * (image->lookup(uv, duv).r - 1), 0.0f, 1.0f);
}

glm::vec3 scene::impl::emission(const material& mat, glm::vec2 uv, float duv) const {
  glm::vec3 e = mat.emissive;
  if (const texture_pyramid* image = textures_of(mat).emissive; image && e != glm::vec3(0))
    e *= srgb_decode(glm::vec3(image->lookup(uv, duv)));
  return e;
}

glm::vec3 scene::impl::normal_map(const material& mat, glm::vec2 uv, float duv) const {
  const texture_pyramid* image = textures_of(mat).normal;
  if (!image) return {0, 0, 1};
  const glm::vec3 n = 2.0f * glm::vec3(image->lookup(uv, duv)) - 1.0f;
  const float len = glm::length(n);
  return len > 1e-6f ? n / len : glm::vec3(0, 0, 1);
}

glm::vec3 scene::impl::environment_radiance(const glm::vec3& dir, float angle) const {
  const environment& env = desc.env;
  if (!has_env_map) return env.colour * env.intensity;
  // Lat-long: u = 0.5 + atan2(x, -z) / 2 pi (so -z is the image centre), v = acos(y) / pi (+y is the top row).
  const float s = 0.5f + std::atan2(dir.x, -dir.z) / (2 * pi);
  const float t = std::acos(std::clamp(dir.y, -1.0f, 1.0f)) / pi;
  return env_map.lookup(s, t, angle / (2 * pi), angle / pi) * env.intensity;
}

env_sampler make_env_sampler(const env_pyramid& p) {
  env_sampler out;
  size_t l = 0;
  while (l + 1 < p.levels.size() && p.levels[l].width > 1024) ++l;
  const env_pyramid::level& m = p.levels[l];
  out.width = m.width, out.height = m.height;
  const size_t w = size_t(m.width), h = size_t(m.height);
  out.texel.resize(w * h);
  double total = 0;
  for (size_t y = 0; y < h; ++y) {
    const float sin_theta = std::sin(pi * (float(y) + 0.5f) / float(h));
    for (size_t x = 0; x < w; ++x) {
      const glm::vec3 c = m.texels[y * w + x];
      out.texel[y * w + x] = std::max(0.0f, luminance(c)) * sin_theta;
      total += out.texel[y * w + x];
    }
  }
  const float floor = total > 0 ? float(0.01 * total / double(w * h)) : 1.0f;
  total = 0;
  for (float& t : out.texel) total += (t += floor);
  out.rows.assign(h + 1, 0);
  out.columns.assign(h * (w + 1), 0);
  double running = 0;
  for (size_t y = 0; y < h; ++y) {
    double row = 0;
    for (size_t x = 0; x < w; ++x) row += out.texel[y * w + x];
    double in_row = 0;
    for (size_t x = 0; x < w; ++x) {
      in_row += out.texel[y * w + x];
      out.columns[y * (w + 1) + x + 1] = float(in_row / row);
    }
    out.columns[y * (w + 1) + w] = 1;
    running += row;
    out.rows[y + 1] = float(running / total);
  }
  out.rows[h] = 1;
  for (float& t : out.texel) t = float(t / total);
  return out;
}

glm::vec3 env_sampler::sample(float u1, float u2, float& density) const {
  // The row, then the column within it, by their cumulative probabilities; then a uniform
  // position in the texel.
  const auto row_it = std::upper_bound(rows.begin() + 1, rows.end(), u1);
  const int y = std::clamp(int(row_it - rows.begin()) - 1, 0, height - 1);
  const float row_lo = rows[size_t(y)], row_hi = rows[size_t(y) + 1];
  const float fy = row_hi > row_lo ? (u1 - row_lo) / (row_hi - row_lo) : 0.5f;
  const auto c0 = columns.begin() + std::ptrdiff_t(size_t(y) * size_t(width + 1));
  const auto col_it = std::upper_bound(c0 + 1, c0 + width + 1, u2);
  const int x = std::clamp(int(col_it - c0) - 1, 0, width - 1);
  const float col_lo = c0[x], col_hi = c0[x + 1];
  const float fx = col_hi > col_lo ? (u2 - col_lo) / (col_hi - col_lo) : 0.5f;
  const float s = (float(x) + std::clamp(fx, 0.0f, 1.0f)) / float(width);
  const float t = (float(y) + std::clamp(fy, 0.0f, 1.0f)) / float(height);
  // The lookup's mapping inverted: s = 0.5 + atan2(x, -z) / 2 pi, t = acos(y) / pi.
  const float phi = (s - 0.5f) * 2 * pi, theta = t * pi;
  const glm::vec3 dir(std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi));
  density = pdf(dir);
  return dir;
}

float env_sampler::pdf(const glm::vec3& dir) const {
  const float s = 0.5f + std::atan2(dir.x, -dir.z) / (2 * pi);
  const float t = std::acos(std::clamp(dir.y, -1.0f, 1.0f)) / pi;
  const int x = std::clamp(int(s * float(width)), 0, width - 1), y = std::clamp(int(t * float(height)), 0, height - 1);
  const float sin_theta = std::sin(t * pi);
  if (sin_theta <= 0) return 0;
  return texel[size_t(y) * size_t(width) + size_t(x)] * float(width) * float(height) / (2 * pi * pi * sin_theta);
}

void scene::impl::surface_at(unsigned inst, unsigned prim, float u, float v, surface& s) const {
  const instance& in = desc.instances[inst];
  const geometry_data& g = geometry[in.mesh];
  const mesh& m = *g.m;
  const glm::uvec3 t = m.triangles[prim];
  const float w = 1 - u - v;
  const bool identity = identity_instance[inst];
  auto place = [&](const glm::vec3& p) { return identity ? p : glm::vec3(in.transform * glm::vec4(p, 1)); };
  const glm::vec3 p0 = place(m.positions[t.x]), p1 = place(m.positions[t.y]), p2 = place(m.positions[t.z]);
  s.position = w * p0 + u * p1 + v * p2;
  const glm::vec3 ng = glm::cross(p1 - p0, p2 - p0);
  const float area2 = glm::length(ng);
  s.geometric_normal = area2 > 0 ? ng / area2 : glm::vec3(0, 1, 0);
  s.normal = s.geometric_normal;
  if (!m.normals.empty()) {
    const glm::vec3 interpolated = w * m.normals[t.x] + u * m.normals[t.y] + v * m.normals[t.z];
    const glm::vec3 n = identity ? interpolated : normal_matrix[inst] * interpolated;
    const float len = glm::length(n);
    if (len > 1e-12f) s.normal = n / len;
  }
  s.uv = glm::vec2(0);
  s.uv_per_world = 0;
  if (!m.uvs.empty()) {
    const glm::vec2 a = m.uvs[t.x], b = m.uvs[t.y], c = m.uvs[t.z];
    s.uv = w * a + u * b + v * c;
    const float uv_area2 = std::fabs((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y));
    s.uv_per_world = area2 > 0 ? std::sqrt(uv_area2 / area2) : 0;
  }
  s.tangent = glm::vec4(0);
  if (!m.tangents.empty()) {
    const glm::vec4 tg = w * m.tangents[t.x] + u * m.tangents[t.y] + v * m.tangents[t.z];
    s.tangent = glm::vec4(identity ? glm::vec3(tg) : glm::mat3(in.transform) * glm::vec3(tg), tg.w < 0 ? -1.0f : 1.0f);
  }
  s.mat = g.mat;
  s.m = &m;
}

namespace {

// One Embree device for the process: a device holds
// thread pools and allocators, and a process that makes scene after scene (a sweep, a fuzz
// run) failed to make one after a few thousand. Each scene holds a reference.
RTCDevice shared_device() {
  static const RTCDevice device = rtcNewDevice(nullptr);
  if (!device) throw std::runtime_error(fmt::format("Embree device: error {}", int(rtcGetDeviceError(nullptr))));
  rtcRetainDevice(device);
  return device;
}

// Reads every texture file the materials name, each once and side by side on the task
// pool, into d.texture_images, and points each material's slots at them. A file that cannot
// be read leaves its slots empty (the material's factors) with one warning naming it.
void load_textures(scene::impl& d) {
  std::vector<std::string> files;
  std::unordered_map<std::string, size_t> index;
  auto slot = [&](const texture_ref& t) {
    if (!t.file.empty() && index.emplace(t.file, files.size()).second) files.push_back(t.file);
  };
  for (const material& m : d.desc.materials)
    for (const texture_ref* t : {&m.base_texture, &m.emissive_texture, &m.normal_texture, &m.metallic_roughness_texture,
                                 &m.occlusion_texture})
      slot(*t);
  d.texture_images.resize(files.size());
  std::vector<std::string> problems(files.size());
  {
    const stderr_silenced quiet;  // libpng prints its own line for what the problem names
    tbb::parallel_for(size_t(0), files.size(), [&](size_t i) {
      try {
        d.texture_images[i] = std::make_unique<texture_pyramid>(load_texture_pyramid(files[i]));
      } catch (const std::exception& e) {
        problems[i] = e.what();
      }
    });
  }
  for (const std::string& p : problems)
    if (!p.empty()) d.desc.warnings.push_back(fmt::format("{}; using the material's factors", p));
  auto image = [&](const texture_ref& t) -> const texture_pyramid* {
    return t.file.empty() ? nullptr : d.texture_images[index.at(t.file)].get();
  };
  for (const material& m : d.desc.materials)
    d.textures.push_back({image(m.base_texture), image(m.emissive_texture), image(m.normal_texture),
                          image(m.metallic_roughness_texture), image(m.occlusion_texture)});
}

}  // namespace

scene::scene(scene_description description) : impl_(std::make_unique<impl>()) {
  impl& d = *impl_;
  if (const std::string why = geometry_problem(description); !why.empty()) throw std::invalid_argument(why);
  d.desc = std::move(description);
  if (d.desc.materials.empty()) d.desc.materials.push_back({});
  d.device = shared_device();
  load_textures(d);
  if (!d.desc.env.latlong_file.empty()) {
    d.env_map = load_env_pyramid(d.desc.env.latlong_file);
    if (d.env_map.non_finite)
      d.desc.warnings.push_back(fmt::format("{}: {} texel values are NaN or infinite; read as 0", d.desc.env.latlong_file,
                                            d.env_map.non_finite));
    if (d.env_map.negative)
      d.desc.warnings.push_back(fmt::format("{}: {} texel values are negative; read as 0", d.desc.env.latlong_file,
                                            d.env_map.negative));
    if (d.env_map.too_bright)
      d.desc.warnings.push_back(fmt::format("{}: {} texel values exceed {}; read as {}", d.desc.env.latlong_file,
                                            d.env_map.too_bright, max_env_value, max_env_value));
  }
  d.top = rtcNewScene(d.device);
  rtcSetSceneBuildQuality(d.top, RTC_BUILD_QUALITY_HIGH);

  d.geometry.resize(d.desc.meshes.size());
  d.mesh_scenes.resize(d.desc.meshes.size(), nullptr);
  for (size_t i = 0; i < d.desc.meshes.size(); ++i) {
    mesh& m = d.desc.meshes[i];
    if (m.material >= d.desc.materials.size()) m.material = 0;
    d.geometry[i] = {&m, &d.desc.materials[m.material], &d};
    RTCScene child = rtcNewScene(d.device);
    rtcSetSceneBuildQuality(child, RTC_BUILD_QUALITY_HIGH);
    if (!m.triangles.empty()) {
      RTCGeometry g = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_TRIANGLE);
      auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                            3 * sizeof(float), m.positions.size()));
      for (size_t k = 0; k < m.positions.size(); ++k)
        v[3 * k] = m.positions[k].x, v[3 * k + 1] = m.positions[k].y, v[3 * k + 2] = m.positions[k].z;
      auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(unsigned), m.triangles.size()));
      std::memcpy(idx, m.triangles.data(), m.triangles.size() * sizeof(glm::uvec3));
      rtcSetGeometryUserData(g, &d.geometry[i]);
      if (d.geometry[i].mat->alpha != alpha_mode::opaque) {
        rtcSetGeometryIntersectFilterFunction(g, alpha_filter);
        rtcSetGeometryOccludedFilterFunction(g, alpha_filter);
      }
      rtcCommitGeometry(g);
      rtcAttachGeometryByID(child, g, 0);
      rtcReleaseGeometry(g);
    }
    rtcCommitScene(child);
    d.mesh_scenes[i] = child;
  }

  d.bmin = glm::vec3(INFINITY);
  d.bmax = glm::vec3(-INFINITY);
  d.normal_matrix.resize(d.desc.instances.size());
  d.identity_instance.resize(d.desc.instances.size());
  for (size_t i = 0; i < d.desc.instances.size(); ++i) {
    const instance& in = d.desc.instances[i];
    d.normal_matrix[i] = glm::transpose(glm::inverse(glm::mat3(in.transform)));
    d.identity_instance[i] = in.transform == glm::mat4(1.0f);
    RTCGeometry g = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(g, d.mesh_scenes[in.mesh]);
    rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &in.transform[0][0]);
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(d.top, g, unsigned(i));
    rtcReleaseGeometry(g);
    for (const glm::vec3& p : d.desc.meshes[in.mesh].positions) {
      const glm::vec3 w = glm::vec3(in.transform * glm::vec4(p, 1));
      d.bmin = glm::min(d.bmin, w);
      d.bmax = glm::max(d.bmax, w);
    }
  }
  rtcCommitScene(d.top);
  if (d.desc.instances.empty()) d.bmin = d.bmax = glm::vec3(0);
  d.emitters = make_emitter_set(d.desc);

  // Ambient light: the environment's mean colour (sampled over the sphere).
  d.has_env_map = !d.desc.env.latlong_file.empty();
  if (d.has_env_map) {
    glm::vec3 sum(0);
    const int n = 32;
    float weight = 0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < 2 * n; ++i) {
        const float theta = pi * (j + 0.5f) / n, phi = 2 * pi * (i + 0.5f) / (2 * n);
        const glm::vec3 dir(std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi));
        sum += std::sin(theta) * d.environment_radiance(dir, pi / n);
        weight += std::sin(theta);
      }
    d.env_mean = sum / weight;
    d.env_light = make_env_sampler(d.env_map);
  } else {
    d.env_mean = d.desc.env.colour * d.desc.env.intensity;
  }
}

scene::~scene() {
  impl& d = *impl_;
  for (RTCScene s : d.mesh_scenes)
    if (s) rtcReleaseScene(s);
  if (d.top) rtcReleaseScene(d.top);
  if (d.device) rtcReleaseDevice(d.device);
}

const scene_description& scene::description() const { return impl_->desc; }
glm::vec3 scene::bounds_min() const { return impl_->bmin; }
glm::vec3 scene::bounds_max() const { return impl_->bmax; }

camera scene::default_camera(float hfov_deg) const {
  if (impl_->desc.scene_camera) return *impl_->desc.scene_camera;
  const glm::vec3 centre = 0.5f * (impl_->bmin + impl_->bmax);
  const float radius = std::max(1e-3f, 0.5f * glm::length(impl_->bmax - impl_->bmin));
  // Back off along +z until the bounding sphere fits the horizontal field of view.
  const float distance = radius / std::sin(0.5f * glm::radians(std::min(hfov_deg, 170.0f)));
  return look_at(centre + glm::vec3(0, 0, distance), centre, hfov_deg);
}

namespace {
bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
}  // namespace

placement_scale classify_placement(const glm::mat4& t) {
  const glm::mat3 linear(t), inverse = glm::inverse(linear);
  bool finite = true, linear_within = true, inverse_within = true;  // (NaN fails each)
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) {
      finite = finite && std::isfinite(linear[c][r]);
      linear_within = linear_within && std::fabs(linear[c][r]) <= max_transform_scale;
      inverse_within = inverse_within && std::fabs(inverse[c][r]) <= max_transform_scale;
    }
  if (!finite) return placement_scale::out_of_range;
  if (!inverse_within) return placement_scale::vanishing;
  return linear_within ? placement_scale::within : placement_scale::out_of_range;
}

std::string geometry_problem(const scene_description& d) {
  auto point_problem = [](const glm::vec3& p) { return world_point_problem(p.x, p.y, p.z); };
  for (size_t m = 0; m < d.meshes.size(); ++m)
    for (const glm::vec3& p : d.meshes[m].positions)
      if (const std::string why = point_problem(p); !why.empty())
        return fmt::format("mesh {}: a vertex out of range ({}; refused)", m, why);
  for (const instance& in : d.instances) {
    const std::string name = in.node.empty() ? "an instance" : fmt::format("node '{}'", printable(in.node));
    if (in.mesh >= d.meshes.size()) return fmt::format("{}: places a mesh that does not exist", name);
    const glm::mat4& t = in.transform;
    bool ok = true;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) ok = ok && std::isfinite(t[c][r]);
    if (!ok) return fmt::format("{}: its transform is not finite (refused)", name);
    if (t[0][3] != 0 || t[1][3] != 0 || t[2][3] != 0 || t[3][3] != 1)
      return fmt::format("{}: its transform is projective, not affine (refused)", name);
    if (classify_placement(t) != placement_scale::within)
      return fmt::format("{}: its transform scales its mesh by more than {:g} or less than {:g} (refused)", name,
                         max_transform_scale, 1 / max_transform_scale);
    for (const glm::vec3& p : d.meshes[in.mesh].positions)
      if (const std::string why = point_problem(glm::vec3(t * glm::vec4(p, 1))); !why.empty())
        return fmt::format("{}: places a vertex out of range ({}; refused)", name, why);
  }
  return "";
}

std::string validate(const camera_overrides& o) {
  if (o.hfov_deg != 0 && !(o.hfov_deg > 0 && o.hfov_deg < 180))
    return fmt::format("--hfov: the field of view must lie in (0, 180) degrees (got {})", o.hfov_deg);
  for (const auto& [flag, point] : {std::pair{"--eye", &o.eye}, std::pair{"--look-at", &o.target}})
    if (*point)
      if (const std::string why = world_point_problem((**point).x, (**point).y, (**point).z); !why.empty())
        return fmt::format("{}: {}", flag, why);
  if (o.up && !(finite(*o.up) && glm::length(*o.up) > 0)) return "--up: not a finite, non-zero direction";
  if (o.eye && o.target && glm::length(*o.target - *o.eye) <= 1e-6f * std::max(1.0f, glm::length(*o.eye)))
    return "--look-at: the target is the eye";
  return "";
}

camera setup_camera(const scene& s, const camera_overrides& o) {
  const std::string problem = validate(o);
  if (!problem.empty()) throw usage_error(problem);
  camera cam = s.default_camera(o.hfov_deg > 0 ? o.hfov_deg : 90.0f);
  if (o.hfov_deg > 0) cam.hfov_deg = o.hfov_deg, cam.vfov_deg = 0;
  if (o.eye) cam.position = *o.eye;
  if (o.target) {
    const glm::vec3 d = *o.target - cam.position;
    if (!(glm::length(d) > 1e-6f * std::max(1.0f, glm::length(cam.position))))
      throw usage_error("--look-at: the target is the camera's position");
    cam.forward = glm::normalize(d);
  }
  if (o.up) cam.up = glm::normalize(*o.up);
  // The scene's own camera (or the one framing its bounds) within range too.
  if (const std::string why = world_point_problem(cam.position.x, cam.position.y, cam.position.z); !why.empty())
    throw std::runtime_error(fmt::format("the scene's camera: {}; place it with --eye", why));
  if ((o.target || o.up) && glm::length(glm::cross(cam.forward, cam.up)) < 1e-4f)
    throw usage_error("--up: parallel to the view direction (give another --up)");
  return cam;
}

}  // namespace fov
