#include "fov/trace.h"

#include <algorithm>
#include <iterator>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include "fov/brdf.h"
#include "fov/random.h"
#include "scene_impl.h"

namespace fov {

namespace {

constexpr float infinity = std::numeric_limits<float>::infinity();
constexpr float pi = 3.14159265358979323846f;
constexpr float inv_pi = 1 / pi;

// Adds the time since the previous mark to a stage, when timing is on.
class stage_timer {
 public:
  using clock = std::chrono::steady_clock;
  explicit stage_timer(bool on) : on_(on), last_(on ? clock::now() : clock::time_point()) {}
  bool on() const { return on_; }
  void mark(double& stage) {
    if (!on_) return;
    const clock::time_point now = clock::now();
    stage += std::chrono::duration<double>(now - last_).count();
    last_ = now;
  }

 private:
  bool on_;
  clock::time_point last_;
};

// The rays a task casts: counted, and kept when the trace records them.
struct ray_tally {
  ray_counts cast;
  std::vector<recorded_ray>* record = nullptr;
  bool timed = false;       // time the rays cast one at a time (trace_timing::bounce_rays)
  double ray_seconds = 0;
  // Casts one ray through cast(), timing it when asked.
  template <class Cast>
  void time(Cast&& cast) {
    if (!timed) return cast();
    const auto t0 = std::chrono::steady_clock::now();
    cast();
    ray_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  void add(recorded_ray::kind how, const glm::vec3& origin, const glm::vec3& dir, float tfar, bool starts_packet) {
    switch (how) {
      case recorded_ray::kind::primary: ++cast.primary; break;
      case recorded_ray::kind::bounce: ++cast.bounce; break;
      default: ++cast.shadow;
    }
    if (record) record->push_back({origin, dir, tfar, how, starts_packet});
  }
};

// A task's stage times and rays, added to the trace's stats once at the end of the task.
struct task_stats {
  trace_timing local;
  stage_timer timer;
  ray_tally tally;
  std::vector<recorded_ray> record;
  trace_stats* total;
  task_stats(trace_stats* t, const trace_params& p) : timer(p.time_stages), total(t) {
    if (p.record_rays) tally.record = &record;
    tally.timed = p.time_stages;
  }
  ~task_stats() {
    static std::mutex lock;
    std::lock_guard<std::mutex> guard(lock);
    ray_counts& c = total->cast;
    c.primary += tally.cast.primary, c.shadow += tally.cast.shadow, c.bounce += tally.cast.bounce;
    if (tally.record) total->recorded.push_back(std::move(record));
    if (!timer.on()) return;
    trace_timing& t = total->timing;
    t.setup += local.setup, t.intersect += local.intersect;
    t.shade += local.shade, t.shadow += local.shadow, t.bounce += local.bounce;
    t.bounce_rays += tally.ray_seconds;
  }
};

// One primary ray: screen position, footprint radius (pixels) and who owns the result.
struct sample_ray {
  float sx, sy, radius_px;
  uint32_t owner;
};

struct shaded {
  glm::vec3 colour{0};     // everything but the lights' direct contributions
  glm::vec3 origin{0};     // shadow-ray origin
  float depth = infinity;  // camera-space depth, +inf on a miss
};

// What a surface point reflects with: its normals (the shading one facing the viewer's side
// of the geometric one) and BRDF inputs.
struct hit_material {
  glm::vec3 position{0}, n{0}, ng{0};
  brdf_inputs brdf;
  bool lambert = true;
  float occlusion = 1;
};

// The light's direction and irradiance at `p` (its distance, +inf for a directional light).
struct light_at {
  glm::vec3 to_light{0}, irradiance{0};
  float distance = infinity;
};
// A light with its spot cone's cosines worked out once per task, not at every vertex.
struct ready_light {
  light l;
  float cos_inner = 1, cos_outer = 0;
  explicit ready_light(const light& from) : l(from), cos_inner(std::cos(from.inner_cone)), cos_outer(std::cos(from.outer_cone)) {}
};
light_at sample_light(const ready_light& rl, const glm::vec3& p) {
  const light& l = rl.l;
  light_at out;
  out.irradiance = l.colour;
  if (l.type == light::kind::directional) {
    out.to_light = glm::normalize(l.direction);
  } else {
    const glm::vec3 v = l.position - p;
    out.distance = glm::length(v);
    out.to_light = v / std::max(out.distance, 1e-6f);
    out.irradiance /= std::max(out.distance * out.distance, 1e-6f);
    if (l.type == light::kind::spot) {  // KHR_lights_punctual's falloff between the cones
      const float inner = rl.cos_inner, outer = rl.cos_outer;
      const float ramp = std::clamp((glm::dot(l.axis, -out.to_light) - outer) / std::max(inner - outer, 1e-4f), 0.0f, 1.0f);
      out.irradiance *= ramp * ramp;
    }
  }
  return out;
}

// The light's unshadowed contribution towards wo: pi f(wo, wi) E cos, so that a white
// Lambertian surface facing the light reflects E (the light's colour is what such a surface
// shows, docs/tracer.md). Lambert keeps the form it always had, albedo E cos, bit for bit.
glm::vec3 reflected_light(const hit_material& h, const glm::vec3& wo, const light_at& l) {
  const float cos_n = glm::dot(h.n, l.to_light);
  if (cos_n <= 0 || glm::dot(h.ng, l.to_light) <= 0) return glm::vec3(0);
  if (h.lambert) return h.brdf.base_colour * l.irradiance * cos_n;
  return pi * brdf_eval(h.brdf, h.n, wo, l.to_light) * l.irradiance * cos_n;
}

// What the direct integrator's ambient term reflects: the albedo for Lambert; for the
// metallic-roughness model the diffuse colour plus the specular reflectance at normal
// incidence (an approximation that ignores roughness), times the occlusion texture.
glm::vec3 ambient_albedo(const hit_material& h) {
  if (h.lambert) return h.brdf.base_colour;
  const glm::vec3 f0 = glm::mix(glm::vec3(0.04f), h.brdf.base_colour, h.brdf.metallic);
  return (h.brdf.base_colour * (1 - h.brdf.metallic) * 0.96f + f0) * h.occlusion;
}

// A shading normal bent by the normal map, facing the side of the geometric normal `ng`
// that `dir` arrives from; ng flipped to that side too.
void orient(const glm::vec3& dir, glm::vec3& ng, glm::vec3& n) {
  if (glm::dot(ng, dir) > 0) ng = -ng;
  if (glm::dot(n, ng) < 0) n = -n;
}
glm::vec3 mapped_normal(const scene::impl& d, const surface& s, float duv) {
  if (s.tangent.w == 0 || s.mat->normal_texture.file.empty()) return s.normal;
  const glm::vec3 tn = d.normal_map(*s.mat, s.uv, duv);
  const glm::vec3 n = s.normal;
  const glm::vec3 tangent = glm::normalize(glm::vec3(s.tangent) - n * glm::dot(n, glm::vec3(s.tangent)));
  const glm::vec3 bitangent = glm::cross(n, tangent) * s.tangent.w;
  return glm::normalize(tn.x * tangent + tn.y * bitangent + tn.z * n);
}
// A shadow or bounce ray's origin: off the surface along its geometric normal.
// How far: grows with the coordinates, so that float rounding there stays below it.
float offset_distance(const glm::vec3& p) {
  return 1e-4f * (1 + std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)}));
}
glm::vec3 offset_origin(const glm::vec3& p, const glm::vec3& ng) { return p + ng * offset_distance(p); }

// Shades the hit lanes of a packet. Texture by texture across the lanes (every base
// colour, then every normal map, then every emission), so that consecutive lookups read
// the same texture near the same texels: OpenImageIO's per-thread tile cache then hits,
// where a lane-by-lane order cycled through three textures' tiles. The direct integrator
// adds the ambient term; the path integrator leaves it to the bounces (mat[] keeps what they
// start from).
void shade_hits(const scene::impl& d, const camera_frame* const* frames, const RTCRayHit16& rh, const bool* hit,
                const glm::vec3* dirs, const float* radius_px, bool ambient, shaded* out, hit_material* mat) {
  surface s[16];
  float duv[16];
  glm::vec4 base[16];
  for (int i = 0; i < 16; ++i) {
    if (!hit[i]) continue;
    d.surface_at(rh.hit.instID[0][i], rh.hit.primID[i], rh.hit.u[i], rh.hit.v[i], s[i]);
    const float t = rh.ray.tfar[i];
    out[i].depth = t * glm::dot(dirs[i], frames[i]->forward);
    duv[i] = 2 * radius_px[i] * frames[i]->pixel_angle * t * s[i].uv_per_world;
  }
  for (int i = 0; i < 16; ++i)
    if (hit[i]) base[i] = d.base_colour(*s[i].mat, s[i].uv, duv[i]);
  for (int i = 0; i < 16; ++i)
    if (hit[i]) mat[i].n = mapped_normal(d, s[i], duv[i]);
  for (int i = 0; i < 16; ++i)
    if (hit[i]) out[i].colour = d.emission(*s[i].mat, s[i].uv, duv[i]);
  for (int i = 0; i < 16; ++i) {
    if (!hit[i] || s[i].mat->model == shading_model::lambert) continue;
    const glm::vec2 mr = d.metallic_roughness(*s[i].mat, s[i].uv, duv[i]);
    mat[i].brdf.metallic = mr.x, mat[i].brdf.roughness = mr.y, mat[i].lambert = false;
    if (ambient) mat[i].occlusion = d.occlusion(*s[i].mat, s[i].uv, duv[i]);
  }
  for (int i = 0; i < 16; ++i) {
    if (!hit[i]) continue;
    hit_material& h = mat[i];
    h.position = s[i].position;
    h.ng = s[i].geometric_normal;
    orient(dirs[i], h.ng, h.n);
    h.brdf.base_colour = glm::vec3(base[i]);
    shaded& o = out[i];
    if (ambient) o.colour += ambient_albedo(h) * d.env_mean * d.desc.env.ambient;
    o.origin = offset_origin(h.position, h.ng);
  }
}

// A ray's own random numbers for its bounces: drawn from the seed and the ray (its owner
// and screen position), the same whichever thread traces it.
rng path_rng(uint64_t seed, const sample_ray& r) {
  uint32_t x, y;
  std::memcpy(&x, &r.sx, 4), std::memcpy(&y, &r.sy, 4);
  return rng(stream_seed(seed ^ 0x70617468ull, r.owner, (uint64_t(x) << 32) | y));
}

// Whether nothing lies between `origin` and `tfar` along `dir` (one shadow ray).
bool unoccluded(const scene::impl& d, const glm::vec3& origin, const glm::vec3& dir, float tfar,
                RTCIntersectContext& context, ray_tally& tally) {
  tally.add(recorded_ray::kind::shadow, origin, dir, tfar, false);
  RTCRay shadow;
  shadow.org_x = origin.x, shadow.org_y = origin.y, shadow.org_z = origin.z;
  shadow.dir_x = dir.x, shadow.dir_y = dir.y, shadow.dir_z = dir.z;
  shadow.tnear = 0, shadow.tfar = tfar, shadow.time = 0;
  shadow.mask = 0xFFFFFFFFu, shadow.id = 0, shadow.flags = 0;
  tally.time([&] {
    rtcInitIntersectContext(&context);
    rtcOccluded1(d.top, &context, &shadow);
  });
  return shadow.tfar >= 0;  // -inf when occluded
}

// Power-heuristic weight of a technique drawing with density a against one drawing with b.
float power_heuristic(float a, float b) { return a * a / std::max(a * a + b * b, 1e-30f); }

// The BRDF's value at h (1/sr) and the density the path integrator draws wi with.
glm::vec3 brdf_at(const hit_material& h, const glm::vec3& wo, const glm::vec3& wi, float& density) {
  if (h.lambert) {
    density = std::max(0.0f, glm::dot(h.n, wi)) * inv_pi;
    return h.brdf.base_colour * inv_pi;
  }
  density = brdf_pdf(h.brdf, h.n, wo, wi);
  return brdf_eval(h.brdf, h.n, wo, wi);
}

// The environment image as a light at vertex h (seen along -wo): one direction drawn by its
// luminance (env_sampler), through a shadow ray to infinity, weighted against the BRDF's
// own sampling by the power heuristic. Always draws two numbers from r.
glm::vec3 environment_light(const scene::impl& d, const hit_material& h, const glm::vec3& wo, bool shadows, rng& r,
                            RTCIntersectContext& context, ray_tally& tally) {
  float pdf_env = 0;
  const float u1 = float(r.uniform()), u2 = float(r.uniform());
  const glm::vec3 wi = d.env_light.sample(u1, u2, pdf_env);
  const float cos_n = glm::dot(h.n, wi);
  if (!(pdf_env > 0) || cos_n <= 0 || glm::dot(h.ng, wi) <= 0) return glm::vec3(0);
  float pdf_brdf = 0;
  const glm::vec3 f = brdf_at(h, wo, wi, pdf_brdf);
  if (f == glm::vec3(0)) return glm::vec3(0);
  if (shadows && !unoccluded(d, offset_origin(h.position, h.ng), wi, infinity, context, tally)) return glm::vec3(0);
  return f * cos_n * d.environment_radiance(wi, 0) * (power_heuristic(pdf_env, pdf_brdf) / pdf_env);
}

// The scene's emissive triangles as a light at vertex h (seen along -wo): one point drawn
// (emitter_set), through a shadow ray that stops short of it, weighted against the BRDF's
// own sampling by the power heuristic (both as densities per steradian). Emission is
// two-sided, as a hit sees it. Always draws three numbers from r.
glm::vec3 emitter_light(const scene::impl& d, const hit_material& h, const glm::vec3& wo, bool shadows, rng& r,
                        RTCIntersectContext& context, ray_tally& tally) {
  const float u0 = float(r.uniform()), u1 = float(r.uniform()), u2 = float(r.uniform());
  const emitter_set::sample e = d.emitters.draw(u0, u1, u2);
  const emitter_set::triangle& tri = d.emitters.triangles[e.triangle];
  const glm::vec3 p = tri.p0 + e.u * tri.e1 + e.v * tri.e2;
  glm::vec3 wi = p - h.position;
  const float dist2 = glm::dot(wi, wi);
  if (!(dist2 > 0)) return glm::vec3(0);
  const float dist = std::sqrt(dist2);
  wi /= dist;
  const float cos_n = glm::dot(h.n, wi);
  if (cos_n <= 0 || glm::dot(h.ng, wi) <= 0) return glm::vec3(0);
  const float cos_l = std::fabs(glm::dot(tri.normal, wi));
  if (!(cos_l > 1e-6f)) return glm::vec3(0);
  float pdf_brdf = 0;
  const glm::vec3 f = brdf_at(h, wo, wi, pdf_brdf);
  if (f == glm::vec3(0)) return glm::vec3(0);
  surface s;
  d.surface_at(tri.inst, tri.prim, e.u, e.v, s);
  const glm::vec3 emitted = d.emission(*s.mat, s.uv, 0);
  if (emitted == glm::vec3(0)) return glm::vec3(0);
  if (shadows) {
    // Stops short of the emitter by twice the offset either end of the ray moves off its surface.
    const glm::vec3 o = offset_origin(h.position, h.ng);
    const float tfar = glm::length(p - o) - 2 * std::max(offset_distance(p), offset_distance(h.position));
    if (tfar > 0 && !unoccluded(d, o, wi, tfar, context, tally)) return glm::vec3(0);
  }
  const float pdf_light = e.area_pdf * dist2 / cos_l;
  return f * cos_n * emitted * (power_heuristic(pdf_light, pdf_brdf) / pdf_light);
}

// The path integrator past the first hit `h` (seen along -wo with throughput 1): up to
// `bounces` BRDF-sampled bounces, each vertex lit by the lights through shadow rays, misses
// seeing the environment and hits adding their emission; Russian roulette from the fourth
// bounce on. With `sample_env`, every vertex a bounce leaves (the first too) also samples
// the environment image as a light, and misses count with multiple importance sampling's
// weight; with `sample_emitters`, the emissive triangles likewise. Returns what this adds to
// the first hit's emission and lights.
glm::vec3 bounce_radiance(const scene::impl& d, const std::vector<ready_light>& lights, hit_material h, glm::vec3 wo,
                          uint32_t bounces, bool shadows, bool sample_env, bool sample_emitters, rng& r,
                          ray_tally& tally) {
  glm::vec3 sum(0), throughput(1);
  RTCIntersectContext context;
  for (uint32_t bounce = 1; bounce <= bounces; ++bounce) {
    // The environment and the emitters are sampled as lights where a bounce also leaves the
    // vertex, so that each pair of techniques' weights adds to one.
    if (sample_env) sum += throughput * environment_light(d, h, wo, shadows, r, context, tally);
    if (sample_emitters) sum += throughput * emitter_light(d, h, wo, shadows, r, context, tally);
    const glm::vec3 u(float(r.uniform()), float(r.uniform()), float(r.uniform()));
    glm::vec3 wi, weight;
    float pdf_brdf = 0;
    if (h.lambert) {  // cosine-weighted: weight = albedo
      const float radius = std::sqrt(u.x), phi = 2 * pi * u.y, cos_n = std::sqrt(std::max(0.0f, 1 - u.x));
      const glm::vec3 t = glm::normalize(glm::cross(h.n, std::fabs(h.n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0)));
      wi = radius * std::cos(phi) * t + radius * std::sin(phi) * glm::cross(h.n, t) + cos_n * h.n;
      weight = h.brdf.base_colour;
      pdf_brdf = cos_n * inv_pi;
    } else {
      const brdf_sample b = sample_brdf(h.brdf, h.n, wo, u);
      wi = b.wi, weight = b.weight, pdf_brdf = b.pdf;
    }
    if (weight == glm::vec3(0) || glm::dot(wi, h.ng) <= 0) break;  // below the geometric surface: lost
    throughput *= weight;
    if (bounce > 3) {  // Russian roulette
      const float keep = std::min(0.95f, std::max({throughput.r, throughput.g, throughput.b}));
      if (float(r.uniform()) >= keep) break;
      throughput /= keep;
    }
    RTCRayHit ray;
    const glm::vec3 o = offset_origin(h.position, h.ng);
    ray.ray.org_x = o.x, ray.ray.org_y = o.y, ray.ray.org_z = o.z;
    ray.ray.dir_x = wi.x, ray.ray.dir_y = wi.y, ray.ray.dir_z = wi.z;
    ray.ray.tnear = 0, ray.ray.tfar = infinity, ray.ray.time = 0;
    ray.ray.mask = 0xFFFFFFFFu, ray.ray.id = 0, ray.ray.flags = 0;
    ray.hit.geomID = ray.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    tally.add(recorded_ray::kind::bounce, o, wi, infinity, false);
    tally.time([&] {
      rtcInitIntersectContext(&context);
      rtcIntersect1(d.top, &context, &ray);
    });
    if (ray.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
      const float mis = sample_env ? power_heuristic(pdf_brdf, d.env_light.pdf(wi)) : 1.0f;
      sum += throughput * d.environment_radiance(wi, 0) * mis;
      break;
    }
    surface s;
    d.surface_at(ray.hit.instID[0], ray.hit.primID, ray.hit.u, ray.hit.v, s);
    const float duv = 0.0f;  // the finest texture level: a bounce's footprint is not tracked
    h = hit_material();
    h.position = s.position, h.ng = s.geometric_normal, h.n = mapped_normal(d, s, duv);
    orient(wi, h.ng, h.n);
    h.brdf.base_colour = glm::vec3(d.base_colour(*s.mat, s.uv, duv));
    if (s.mat->model == shading_model::metallic_roughness) {
      const glm::vec2 mr = d.metallic_roughness(*s.mat, s.uv, duv);
      h.brdf.metallic = mr.x, h.brdf.roughness = mr.y, h.lambert = false;
    }
    wo = -wi;
    glm::vec3 emitted = d.emission(*s.mat, s.uv, duv);
    if (sample_emitters && emitted != glm::vec3(0)) {
      const float area_pdf = d.emitters.area_pdf(ray.hit.instID[0], ray.hit.primID);
      const float cos_l = std::fabs(glm::dot(h.ng, wi));
      if (area_pdf > 0 && cos_l > 1e-6f)
        emitted *= power_heuristic(pdf_brdf, area_pdf * ray.ray.tfar * ray.ray.tfar / cos_l);
    }
    sum += throughput * emitted;
    for (const ready_light& l : lights) {
      const light_at at = sample_light(l, h.position);
      const glm::vec3 direct = reflected_light(h, wo, at);
      if (direct == glm::vec3(0)) continue;
      if (shadows && !unoccluded(d, offset_origin(h.position, h.ng), at.to_light, at.distance, context, tally)) continue;
      sum += throughput * direct;
    }
  }
  return sum;
}

// Adds one light's direct contribution to a packet's hit lanes, each through its shadow ray
// (a packet of them) unless shadows are off.
void add_light(const scene::impl& d, const ready_light& l, const hit_material* mat, const bool* hit, const glm::vec3* dirs,
               int n, bool shadows, RTCIntersectContext& context, task_stats& timing, shaded* result) {
  trace_timing& t = timing.local;
  glm::vec3 direct[16];
  alignas(64) int shadow_valid[16];
  alignas(64) RTCRay16 shadow;
  bool any_shadow = false;
  for (int i = 0; i < 16; ++i) {
    // Every lane holds a well-formed ray, active or not: Debian's Embree checks the
    // lanes of its 8-wide halves with assertions on (an unset lane aborted on AVX2).
    shadow_valid[i] = 0;
    shadow.org_x[i] = shadow.org_y[i] = shadow.org_z[i] = 0;
    shadow.dir_x[i] = shadow.dir_y[i] = 0, shadow.dir_z[i] = 1;
    shadow.tnear[i] = 0, shadow.tfar[i] = 0, shadow.time[i] = 0;
    shadow.mask[i] = 0xFFFFFFFFu, shadow.id[i] = unsigned(i), shadow.flags[i] = 0;
    direct[i] = glm::vec3(0);
    if (i >= n || !hit[i]) continue;
    const light_at at = sample_light(l, mat[i].position);
    direct[i] = reflected_light(mat[i], -dirs[i], at);
    if (direct[i] == glm::vec3(0)) continue;
    if (!shadows) {
      result[i].colour += direct[i];
      continue;
    }
    shadow_valid[i] = -1;
    shadow.org_x[i] = result[i].origin.x, shadow.org_y[i] = result[i].origin.y, shadow.org_z[i] = result[i].origin.z;
    shadow.dir_x[i] = at.to_light.x, shadow.dir_y[i] = at.to_light.y, shadow.dir_z[i] = at.to_light.z;
    shadow.tfar[i] = at.distance;
    timing.tally.add(recorded_ray::kind::packet_shadow, result[i].origin, at.to_light, at.distance, !any_shadow);
    any_shadow = true;
  }
  timing.timer.mark(t.shade);
  if (!any_shadow) return;
  rtcInitIntersectContext(&context);
  rtcOccluded16(shadow_valid, d.top, &context, &shadow);
  for (int i = 0; i < n; ++i)
    if (shadow_valid[i] == -1 && shadow.tfar[i] >= 0) result[i].colour += direct[i];  // tfar = -inf when occluded
  timing.timer.mark(t.shadow);
}

// Lane i of a packet: a camera ray from `origin` along `dir` to infinity, not yet hit.
void set_camera_ray(RTCRayHit16& rh, int i, const glm::vec3& origin, const glm::vec3& dir) {
  rh.ray.org_x[i] = origin.x, rh.ray.org_y[i] = origin.y, rh.ray.org_z[i] = origin.z;
  rh.ray.dir_x[i] = dir.x, rh.ray.dir_y[i] = dir.y, rh.ray.dir_z[i] = dir.z;
  rh.ray.tnear[i] = 0, rh.ray.tfar[i] = infinity, rh.ray.time[i] = 0;
  rh.ray.mask[i] = 0xFFFFFFFFu, rh.ray.id[i] = unsigned(i), rh.ray.flags[i] = 0;
  rh.hit.geomID[i] = rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
}

// The camera frames a trace casts from: the frame's, or one per screen line (trace_params::lines).
struct view_frames {
  camera_frame global;
  std::vector<camera_frame> lines;
  bool columns = false;
  // The frame a ray through screen position (sx, sy) is cast from.
  const camera_frame& at(float sx, float sy) const {
    if (lines.empty()) return global;
    const float s = columns ? sx : sy;
    const float last = float(lines.size() - 1);
    return lines[size_t(s >= 0 ? std::min(std::floor(s), last) : 0.0f)];
  }
};
// Throws std::invalid_argument when params.lines does not hold one camera per line.
view_frames make_view(const camera& cam, int width, int height, const trace_params& params) {
  view_frames v;
  v.global = make_frame(cam, width, height);
  const line_cameras& l = params.lines;
  if (l.empty()) return v;
  const size_t n = size_t(l.columns ? width : height);
  if (l.cameras.size() != n)
    throw std::invalid_argument(fmt::format("{} line cameras for a screen of {} {}", l.cameras.size(), n,
                                            l.columns ? "columns" : "rows"));
  v.columns = l.columns;
  v.lines.reserve(n);
  for (const camera& c : l.cameras) v.lines.push_back(make_frame(c, width, height));
  return v;
}

// Traces rays[begin, end) in packets of 16 and hands each result to sink(ray, colour, depth, hit).
template <class Sink>
void trace_rays(const scene::impl& d, const trace_params& params, const view_frames& view, const sample_ray* rays,
                size_t count, task_stats& timing, Sink&& sink) {
  std::vector<ready_light> lights;
  if (params.sun) lights.emplace_back(*params.sun);
  else
    for (const light& l : d.desc.lights) lights.emplace_back(l);
  const bool shadows = params.shadows, path = params.method == integrator::path;
  const bool sample_env = path && params.sample_environment && !d.env_light.empty();
  const bool sample_emitters = path && params.sample_emitters && !d.emitters.empty();
  trace_timing& t = timing.local;
  RTCIntersectContext context;
  for (size_t base = 0; base < count; base += 16) {
    const int n = int(std::min<size_t>(16, count - base));
    alignas(64) int valid[16];
    alignas(64) RTCRayHit16 rh;
    glm::vec3 dirs[16];
    const camera_frame* frames[16];
    for (int i = 0; i < 16; ++i) {
      valid[i] = i < n ? -1 : 0;
      const sample_ray& r = rays[base + std::min(i, n - 1)];
      const camera_frame& f = *(frames[i] = &view.at(r.sx, r.sy));
      dirs[i] = ray_direction(f, r.sx, r.sy);
      set_camera_ray(rh, i, f.origin, dirs[i]);
      if (i < n) timing.tally.add(recorded_ray::kind::primary, f.origin, dirs[i], infinity, i == 0);
    }
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    timing.timer.mark(t.setup);
    rtcIntersect16(valid, d.top, &context, &rh);
    timing.timer.mark(t.intersect);

    shaded result[16];
    hit_material mat[16];
    bool hit[16];
    float radius[16];
    for (int i = 0; i < 16; ++i) {
      hit[i] = i < n && rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
      radius[i] = rays[base + std::min(i, n - 1)].radius_px;
    }
    shade_hits(d, frames, rh, hit, dirs, radius, !path, result, mat);
    for (int i = 0; i < n; ++i)
      if (!hit[i]) result[i].colour = d.environment_radiance(dirs[i], 2 * radius[i] * frames[i]->pixel_angle);
    timing.timer.mark(t.shade);
    for (const ready_light& l : lights) add_light(d, l, mat, hit, dirs, n, shadows, context, timing, result);
    if (path && params.bounces > 0) {
      for (int i = 0; i < n; ++i) {
        if (!hit[i]) continue;
        rng r = path_rng(params.seed, rays[base + i]);
        result[i].colour += bounce_radiance(d, lights, mat[i], -dirs[i], params.bounces, shadows, sample_env,
                                            sample_emitters, r, timing.tally);
      }
      timing.timer.mark(t.bounce);
    }
    for (int i = 0; i < n; ++i)
      sink(rays[base + i], result[i].colour, result[i].depth, result[i].depth != infinity);
  }
}

// A ray sink for trace_rays: averages each run of `spp` consecutive rays, which belong to
// one owner (a point or a pixel), and hands emit(owner, mean colour, mean depth of the
// rays that hit or +inf, hits) the result, its colour times `exposure`.
// `count(owner)` gives each owner's run length (a falloff's pixels differ).
template <class Count, class Emit>
auto per_owner_mean_by(Count count, float exposure, Emit emit) {
  return [count, exposure, emit, sum = glm::vec3(0), depth_sum = 0.0, hits = uint32_t(0), seen = uint32_t(0)](
             const sample_ray& ray, glm::vec3 c, float depth, bool hit) mutable {
    sum += c;
    if (hit) depth_sum += depth, ++hits;
    const uint32_t n = count(ray.owner);
    if (++seen < n) return;
    emit(ray.owner, sum * (exposure / float(n)), hits ? float(depth_sum / hits) : infinity, hits);
    sum = glm::vec3(0);
    depth_sum = 0;
    hits = seen = 0;
  };
}

// Calls emit(x, y) with the screen positions of samples [first, first + count) of
// pixel (x, y)'s rays, as params.sampler says: sobol (owen_sobol_2d, scrambles seeded by
// (seed, pixel index)) or random (uniform, from a stream seeded by (seed, pixel index)).
// A full-resolution pixel casts samples [0, spp); so does a grid point in pattern 0. (x, y)
// may lie off the screen (a grid point some border pixel reads): it seeds as the index
// y * width + x would, modulo 2^32.
template <class Emit>
void pixel_rays(int x, int y, int width, const trace_params& params, uint32_t first, uint32_t count, Emit&& emit) {
  const uint32_t pixel = uint32_t(int64_t(y) * width + x);
  if (params.sampler == pixel_sampler::sobol) {
    uint64_t h = stream_seed(params.seed, 0x736f626f6cull, pixel);
    const uint64_t scrambles = splitmix64(h);
    for (uint32_t s = first; s < first + count; ++s) {
      const glm::vec2 u = owen_sobol_2d(s, uint32_t(scrambles), uint32_t(scrambles >> 32));
      emit(float(x) + u.x, float(y) + u.y);
    }
    return;
  }
  rng random(stream_seed(params.seed, 0x706978656Cull, pixel));
  for (uint64_t s = 0; s < 2 * uint64_t(first); ++s) random.uniform();
  for (uint32_t s = 0; s < count; ++s) {
    const float u = float(random.uniform());
    const float v = float(random.uniform());
    emit(float(x) + u, float(y) + v);
  }
}

// The TAA pattern m = mirror_x + 2 mirror_y: a grid point, and a full-grid pixel, cast their
// samples m n .. (m + 1) n - 1 in it.
uint32_t pattern_of(const trace_params& params) { return (params.mirror_x ? 1u : 0u) + (params.mirror_y ? 2u : 0u); }


// Calls emit(x, y) with the screen position of each of point i's first n rays (n <= params.spp). A grid
// point (grid_point: is_grid_point, asked once by the caller) stands for the screen pixel it lands on and casts that pixel's rays
// (pixel_rays), samples [pattern * n, (pattern + 1) * n) with pattern = mirror_x +
// 2 mirror_y: pattern 0 casts exactly the full-resolution frame's rays, and the four
// mirrored patterns together a 4 n-sample stratified set for TAA to average. Any other
// point casts rays inside the disc of radius p around it, as params.disc_sampler says:
// random (uniform, rejection from the square: one splitmix64 draw gives both coordinates,
// 24 bits each, from a stream seeded by (seed, i)) or sobol (the scrambled Sobol points of
// owen_sobol_2d, scrambles seeded by (seed, i), mapped to the disc by Shirley and Chiu's
// concentric map, which keeps areas and so the strata). The point gets the same rays every
// frame. The set is placed at `offset` and mirrored as trace_params says (the disc too).
template <class Emit>
void point_rays(const pointset& set, bool grid_point, uint32_t i, canvas_offset offset, const trace_params& params,
                uint32_t n, Emit&& emit) {
  const display_geometry& disp = set.model.display;
  const point& p = set.points[i];
  uint64_t random = stream_seed(params.seed, 0x7261797375ull, i);
  const glm::vec2 at = placed_position(disp, p, offset, params.mirror_x, params.mirror_y);
  const float cx = at.x, cy = at.y;
  if (grid_point) {
    pixel_rays(int(std::floor(cx)), int(std::floor(cy)), disp.width, params, pattern_of(params) * n, n, emit);
    return;
  }
  const float sx = params.mirror_x ? -p.spacing : p.spacing, sy = params.mirror_y ? -p.spacing : p.spacing;
  if (params.disc_sampler == pixel_sampler::sobol) {
    const uint64_t scrambles = splitmix64(random);
    for (uint32_t s = 0; s < n; ++s) {
      const glm::vec2 q = owen_sobol_2d(s, uint32_t(scrambles), uint32_t(scrambles >> 32));
      const glm::vec2 d = concentric_disc(q);
      emit(cx + sx * d.x, cy + sy * d.y);
    }
    return;
  }
  for (uint32_t s = 0; s < n; ++s) {
    float u, v;
    do {
      const uint64_t bits = splitmix64(random);
      u = float(bits >> 40) * 0x1.0p-23f - 1;
      v = float((bits >> 8) & 0xFFFFFFu) * 0x1.0p-23f - 1;
    } while (u * u + v * v > 1);
    emit(cx + sx * u, cy + sy * v);
  }
}

uint32_t reverse_bits(uint32_t x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
  x = ((x >> 8) & 0x00FF00FFu) | ((x & 0x00FF00FFu) << 8);
  return (x >> 16) | (x << 16);
}

// Nested uniform (Owen) scrambling of a 32-bit fixed-point coordinate by a hash: each
// bit is flipped by a function of the seed and the bits above it only (a hash that
// carries only from low to high bits, applied to the bit-reversed value).
uint32_t owen_scramble(uint32_t v, uint32_t seed) {
  uint32_t x = reverse_bits(v);
  x ^= x * 0x3d20adeau;
  x += seed;
  x *= (seed >> 16) | 1u;
  x ^= x * 0x05526c56u;
  x ^= x * 0x53a22864u;
  return reverse_bits(x);
}

float exposure_factor(const trace_params& p) { return std::exp2(p.exposure_ev); }

void check(const trace_params& p, int width, int height) {
  if (p.spp < 1 || p.spp > max_spp) throw std::invalid_argument(fmt::format("spp must lie in 1..{}", max_spp));
  if (p.ray_floor > p.spp)
    throw std::invalid_argument(fmt::format("the ray floor must lie in 1..spp = {} (got {})", p.spp, p.ray_floor));
  if (!(std::fabs(p.exposure_ev) <= 20)) throw std::invalid_argument("exposure must lie in -20..20 EV");
  if (width < 1 || height < 1) throw std::invalid_argument("screen size must be positive");
}

}  // namespace

const char* texture_footprint_name(texture_footprint f) { return label_of(texture_footprint_labels, f); }

glm::vec2 concentric_disc(glm::vec2 u) {
  const float a = 2 * u.x - 1, b = 2 * u.y - 1;
  if (a == 0 && b == 0) return {0, 0};
  constexpr float quarter_pi = 0.78539816339744831f;
  float r, phi;
  if (std::fabs(a) > std::fabs(b)) r = a, phi = quarter_pi * (b / a);
  else r = b, phi = 2 * quarter_pi - quarter_pi * (a / b);
  return {r * std::cos(phi), r * std::sin(phi)};
}

glm::vec2 owen_sobol_2d(uint32_t s, uint32_t sx, uint32_t sy) {
  // Dimension 0 is the van der Corput sequence (bit reversal); dimension 1 is Sobol's
  // second, generator matrix the Pascal triangle mod 2: v_0 = 2^31, v_k = v_(k-1) ^ (v_(k-1) >> 1).
  uint32_t x = reverse_bits(s), y = 0;
  for (uint32_t v = 1u << 31, i = s; i; i >>= 1, v ^= v >> 1)
    if (i & 1) y ^= v;
  // 24 bits: exact in a float, and below 1.
  return {float(owen_scramble(x, sx) >> 8) * 0x1.0p-24f, float(owen_scramble(y, sy) >> 8) * 0x1.0p-24f};
}

namespace {

// Where a trace places the set for `gaze`: a mirrored pattern is the set placed for the
// mirrored gaze, then mirrored on screen.
gaze_point placed_gaze(const display_geometry& disp, gaze_point gaze, const trace_params& params) {
  return {params.mirror_x ? disp.width - gaze.x : gaze.x, params.mirror_y ? disp.height - gaze.y : gaze.y};
}

// Throws unless `points` ascend and name points of a set of n (`who` names the caller).
void check_listed(const std::vector<uint32_t>& points, size_t n, const char* who) {
  for (size_t j = 0; j < points.size(); ++j)
    if (points[j] >= n || (j > 0 && points[j] <= points[j - 1]))
      throw std::invalid_argument(fmt::format("{}: indices must ascend and name points of the set", who));
}

// The rays of each of `points` (indexed like it): spp, or point_ray_rule's n(d) at the
// point's screen position (placed and mirrored as `placement` says).
std::vector<uint16_t> listed_point_rays(const pointset& set, const std::vector<uint32_t>& points,
                                        const point_samples& placement, gaze_point gaze, const trace_params& params) {
  std::vector<uint16_t> n(points.size(), uint16_t(params.spp));
  if (params.ray_floor == 0) return n;
  const falloff_rule rule = point_ray_rule(set, gaze, params.spp, params.ray_floor);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k < r.end(); ++k) {
      const glm::vec2 at = placed_position(set.model.display, set.points[points[k]], placement.offset,
                                           placement.mirror_x, placement.mirror_y);
      n[k] = uint16_t(rule.rays_at(std::hypot(double(at.x) - gaze.x, double(at.y) - gaze.y)));
    }
  });
  return n;
}
std::vector<uint16_t> traced_point_rays(const pointset& set, const point_samples& samples, gaze_point gaze,
                                        const trace_params& params) {
  return listed_point_rays(set, samples.traced, samples, gaze, params);
}

// Casts the rays of `points` (placed as `out` says) and writes their samples into `out`'s
// per-point arrays, which hold the whole set; returns the rays cast.
uint64_t cast_points(const scene::impl& d, const view_frames& f, const pointset& set, const std::vector<uint32_t>& points,
                     gaze_point gaze, const trace_params& params, point_samples& out, trace_stats& stats) {
  const uint32_t spp = params.spp;
  // Rays per point; a ray's owner is its point's place in `points`.
  const std::vector<uint16_t> rays_of = listed_point_rays(set, points, out, gaze, params);
  const bool pixel_footprint = params.footprint == texture_footprint::pixel;
  const grid_test on_grid(set);
  const size_t chunk = std::max<size_t>(1, 256 / spp);  // points per task: about 256 rays at the gaze
  tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size(), chunk), [&](const tbb::blocked_range<size_t>& r) {
    task_stats timing(&stats, params);
    std::vector<sample_ray> rays;
    rays.reserve((r.end() - r.begin()) * spp);
    for (size_t k = r.begin(); k < r.end(); ++k) {
      const uint32_t i = points[k];
      const uint32_t rays_here = rays_of[k];
      // A grid point's rays are a pixel's: they filter textures as a full-resolution pixel's do.
      const bool grid_point = on_grid(set.points[i]);
      const float radius = (pixel_footprint || grid_point ? 0.5f : set.points[i].spacing) * (1.0f / std::sqrt(float(rays_here)));
      point_rays(set, grid_point, i, out.offset, params, rays_here,
                 [&](float x, float y) { rays.push_back({x, y, radius, uint32_t(k)}); });
    }
    trace_rays(d, params, f, rays.data(), rays.size(), timing,
               per_owner_mean_by([&](uint32_t k) { return uint32_t(rays_of[k]); }, exposure_factor(params),
                                 [&](uint32_t k, glm::vec3 c, float depth, uint32_t hits) {
                                   const uint32_t i = points[k];
                                   out.colour[i] = c;
                                   out.depth[i] = depth;
                                   out.hits[i] = uint16_t(hits);
                                 }));
  });
  uint64_t cast = 0;
  for (uint16_t r : rays_of) cast += r;
  return cast;
}

// trace_points, its traced points found with `index` where there is one, or given (`listed`).
points_trace trace_selected(const scene& sc, const camera& cam, const pointset& set, const traced_index* index,
                            gaze_point gaze, const trace_params& params, std::vector<uint32_t>* listed = nullptr) {
  const display_geometry& disp = set.model.display;
  check(params, disp.width, disp.height);
  const scene::impl& d = sc.internals();
  const view_frames f = make_view(cam, disp.width, disp.height, params);
  points_trace result;
  point_samples& out = result.samples;
  trace_timing* timing_total = params.time_stages ? &result.stats.timing : nullptr;
  stage_timer choose(timing_total != nullptr);
  const gaze_point placed = placed_gaze(disp, gaze, params);
  out.offset = offset_for_gaze(disp, placed);
  out.mirror_x = params.mirror_x, out.mirror_y = params.mirror_y;
  // Choosing the points and clearing the per-point arrays, side by side: on a short frame
  // (1 spp, a sparse set) these serial steps are a visible share of its time.
  const size_t n = set.points.size();
  tbb::parallel_invoke(
      [&] {
        out.traced = listed ? std::move(*listed) : index ? traced_points(set, *index, placed) : traced_points(set, placed, params.k);
      },
      [&] { out.colour.assign(n, glm::vec3(0)); },
      [&] {
        out.depth.assign(n, infinity);
        out.hits.assign(n, 0);
      });
  if (timing_total) choose.mark(timing_total->setup);
  out.rays = cast_points(d, f, set, out.traced, gaze, params, out, result.stats);
  return result;
}

}  // namespace

points_trace trace_points(const scene& sc, const camera& cam, const pointset& set, gaze_point gaze,
                          const trace_params& params) {
  return trace_selected(sc, cam, set, nullptr, gaze, params);
}

points_trace trace_listed_points(const scene& sc, const camera& cam, const pointset& set, std::vector<uint32_t> points,
                                 gaze_point gaze, const trace_params& params) {
  check_listed(points, set.points.size(), "trace_listed_points");
  return trace_selected(sc, cam, set, nullptr, gaze, params, &points);
}

point_probe probe_points(const scene& sc, const camera& cam, const pointset& set, const traced_index& index, gaze_point gaze,
                         const trace_params& params) {
  require_neighbours(set);
  const display_geometry& disp = set.model.display;
  check(params, disp.width, disp.height);
  const scene::impl& d = sc.internals();
  const view_frames view = make_view(cam, disp.width, disp.height, params);
  point_probe out;
  const gaze_point placed = placed_gaze(disp, gaze, params);
  out.offset = offset_for_gaze(disp, placed);
  out.mirror_x = params.mirror_x, out.mirror_y = params.mirror_y;
  out.points = traced_points(set, index, placed);
  const size_t n = out.points.size();
  out.screen.resize(n);
  out.where.resize(n);
  out.distance.resize(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const tbb::blocked_range<size_t>& r) {
    RTCIntersectContext context;
    for (size_t base = r.begin(); base < r.end(); base += 16) {
      const int m = int(std::min<size_t>(16, r.end() - base));
      alignas(64) int valid[16];
      alignas(64) RTCRayHit16 rh;
      glm::vec3 dirs[16], origins[16];
      for (int i = 0; i < 16; ++i) {
        const size_t k = base + size_t(std::min(i, m - 1));
        const glm::vec2 at = placed_position(disp, set.points[out.points[k]], out.offset, out.mirror_x, out.mirror_y);
        out.screen[k] = at;
        const camera_frame& f = view.at(at.x, at.y);
        dirs[i] = ray_direction(f, at.x, at.y);
        origins[i] = f.origin;
        valid[i] = i < m ? -1 : 0;
        set_camera_ray(rh, i, f.origin, dirs[i]);
      }
      rtcInitIntersectContext(&context);
      context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
      rtcIntersect16(valid, d.top, &context, &rh);
      for (int i = 0; i < m; ++i) {
        const bool hit = rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
        out.distance[base + size_t(i)] = hit ? rh.ray.tfar[i] : infinity;
        out.where[base + size_t(i)] = hit ? origins[i] + dirs[i] * rh.ray.tfar[i] : dirs[i];
      }
    }
  });
  out.rays = n;
  return out;
}

uint64_t trace_more_points(const scene& sc, const camera& cam, const pointset& set, const std::vector<uint32_t>& points,
                           gaze_point gaze, const trace_params& params, points_trace& into) {
  const display_geometry& disp = set.model.display;
  check(params, disp.width, disp.height);
  point_samples& out = into.samples;
  const size_t n = set.points.size();
  const canvas_offset o = offset_for_gaze(disp, placed_gaze(disp, gaze, params));
  if (out.colour.size() != n || out.depth.size() != n || out.hits.size() != n || out.offset.x != o.x ||
      out.offset.y != o.y || out.mirror_x != params.mirror_x || out.mirror_y != params.mirror_y)
    throw std::invalid_argument("trace_more_points: `into` was not traced from this set at this gaze and pattern");
  check_listed(points, n, "trace_more_points");
  // None of them may be traced already (both lists ascend).
  for (size_t a = 0, b = 0; a < points.size() && b < out.traced.size();) {
    if (points[a] == out.traced[b]) throw std::invalid_argument("trace_more_points: a point is already traced");
    points[a] < out.traced[b] ? ++a : ++b;
  }
  if (points.empty()) return 0;
  const uint64_t cast = cast_points(sc.internals(), make_view(cam, disp.width, disp.height, params), set, points, gaze, params,
                                    out, into.stats);
  std::vector<uint32_t> merged;
  merged.reserve(out.traced.size() + points.size());
  std::merge(out.traced.begin(), out.traced.end(), points.begin(), points.end(), std::back_inserter(merged));
  out.traced.swap(merged);
  out.rays += cast;
  return cast;
}

points_trace trace_points(const scene& sc, const camera& cam, const pointset& set, const traced_index& index,
                          gaze_point gaze, const trace_params& params) {
  require_neighbours(set);
  if (index.k_used != std::min(params.k, stored_k(set)))
    throw std::invalid_argument(fmt::format("the traced-point index is for k = {}, the trace reads k = {}", index.k_used,
                                            std::min(params.k, stored_k(set))));
  return trace_selected(sc, cam, set, &index, gaze, params);
}

std::vector<glm::vec2> point_ray_positions(const pointset& set, const point_samples& samples, gaze_point gaze,
                                          const trace_params& params) {
  check(params, set.model.display.width, set.model.display.height);
  const std::vector<uint16_t> rays_of = traced_point_rays(set, samples, gaze, params);
  std::vector<glm::vec2> out;
  out.reserve(samples.traced.size() * params.spp);
  trace_params placed = params;  // the placement trace_points used
  placed.mirror_x = samples.mirror_x, placed.mirror_y = samples.mirror_y;
  const grid_test on_grid(set);
  for (size_t k = 0; k < samples.traced.size(); ++k) {
    const uint32_t i = samples.traced[k];
    point_rays(set, on_grid(set.points[i]), i, samples.offset, placed, rays_of[k], [&](float x, float y) { out.emplace_back(x, y); });
  }
  return out;
}

reference_trace trace_reference(const scene& sc, const camera& cam, int width, int height, const trace_params& params) {
  check(params, width, height);
  const scene::impl& d = sc.internals();
  const view_frames f = make_view(cam, width, height, params);
  reference_trace result;
  frame& out = result.image;
  std::vector<double>* tile_seconds = params.tile_costs ? &result.stats.tile_seconds : nullptr;
  out.width = width;
  out.height = height;
  out.rgb.assign(size_t(width) * height, glm::vec3(0));
  out.depth.assign(size_t(width) * height, infinity);
  const uint32_t spp = params.spp;
  // Rays per pixel: spp, or the falloff's n(d) (stored per pixel: the mean divides by it).
  std::vector<uint16_t> rays_of;
  falloff_rule rule;
  if (params.falloff) {
    if (const std::string why = falloff_problem(*params.falloff, spp); !why.empty()) throw std::invalid_argument(why);
    if (params.falloff->model.display.width != width || params.falloff->model.display.height != height)
      throw std::invalid_argument("the falloff's display is not the frame's size");
    rule = make_falloff_rule(*params.falloff, spp);
    rays_of.resize(size_t(width) * height);
  }
  const gaze_point gaze = params.falloff ? params.falloff->gaze : gaze_point{};
  // The TAA pattern, as a grid point's (point_rays): four frames together cast a stratified
  // 4 n-sample set.
  const uint32_t pattern = pattern_of(params);
  auto rays_at = [&](int x, int y) {
    return params.falloff ? rule.rays_at(std::hypot(x + 0.5 - gaze.x, y + 0.5 - gaze.y)) : spp;
  };
  // 8x8-pixel tiles keep each packet's rays close together.
  constexpr int t = reference_tile;
  const int tiles_x = (width + t - 1) / t, tiles_y = (height + t - 1) / t;
  if (tile_seconds) tile_seconds->assign(size_t(tiles_x) * tiles_y, 0.0);
  tbb::parallel_for(tbb::blocked_range<int>(0, tiles_x * tiles_y), [&](const tbb::blocked_range<int>& r) {
    task_stats timing(&result.stats, params);
    std::vector<sample_ray> rays;
    for (int tile = r.begin(); tile < r.end(); ++tile) {
      const auto tile_start = tile_seconds ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point();
      const int x0 = (tile % tiles_x) * t, y0 = (tile / tiles_x) * t;
      rays.clear();
      for (int y = y0; y < std::min(height, y0 + t); ++y)
        for (int x = x0; x < std::min(width, x0 + t); ++x) {
          const uint32_t pixel = uint32_t(y) * uint32_t(width) + uint32_t(x);
          const uint32_t n = rays_at(x, y);
          if (!rays_of.empty()) rays_of[pixel] = uint16_t(n);
          const float radius = 0.5f / std::sqrt(float(n));
          pixel_rays(x, y, width, params, pattern * n, n,
                     [&](float sx, float sy) { rays.push_back({sx, sy, radius, pixel}); });
        }
      trace_rays(d, params, f, rays.data(), rays.size(), timing,
                 per_owner_mean_by([&](uint32_t pixel) { return rays_of.empty() ? spp : uint32_t(rays_of[pixel]); },
                                   exposure_factor(params), [&](uint32_t pixel, glm::vec3 c, float depth, uint32_t) {
                                     out.rgb[pixel] = c;
                                     out.depth[pixel] = depth;
                                   }));
      if (tile_seconds)
        (*tile_seconds)[size_t(tile)] =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - tile_start).count();
    }
  });
  out.rays = 0;
  if (rays_of.empty()) out.rays = uint64_t(width) * height * spp;
  else
    for (uint16_t n : rays_of) out.rays += n;
  return result;
}

std::string falloff_problem(const ray_falloff& f, uint32_t spp) {
  if (f.floor < 1 || f.floor > spp) return fmt::format("the ray floor must lie in 1..spp = {} (got {})", spp, f.floor);
  if (const std::string why = validate(f.model); !why.empty()) return why;
  if (!std::isfinite(f.gaze.x) || !std::isfinite(f.gaze.y)) return "the falloff's gaze is not finite";
  return "";
}

falloff_rule make_falloff_rule(const ray_falloff& f, uint32_t spp) {
  falloff_rule r;
  r.floor = f.floor;
  const double p0 = point_spacing_px(f.model, 0);
  auto rays = [&](double d) {
    const double q = p0 / point_spacing_px(f.model, d);
    return std::clamp(std::llround(double(spp) * q * q), (long long)f.floor, (long long)spp);
  };
  // Farthest a pixel can be from a gaze on (or at the edge of) the screen.
  const double far = std::hypot(2.0 * f.model.display.width, 2.0 * f.model.display.height);
  for (uint32_t n = f.floor + 1; n <= spp; ++n) {  // rays(0) is spp: every n is reached at the gaze
    double lo = 0, hi = far;
    if (rays(hi) >= n) {
      r.thresholds.push_back(hi);
      continue;
    }
    for (int i = 0; i < 80 && hi - lo > 1e-9; ++i) {
      const double mid = 0.5 * (lo + hi);
      (rays(mid) >= n ? lo : hi) = mid;
    }
    r.thresholds.push_back(lo);
  }
  return r;
}

falloff_rule point_ray_rule(const pointset& set, gaze_point gaze, uint32_t spp, uint32_t floor) {
  ray_falloff f;
  f.model = set.model, f.gaze = gaze, f.floor = floor;
  if (const std::string why = falloff_problem(f, spp); !why.empty()) throw std::invalid_argument(why);
  return make_falloff_rule(f, spp);
}

uint32_t falloff_rule::rays_at(double d) const {
  // thresholds is non-increasing: count the entries that still reach d.
  const auto reach = std::partition_point(thresholds.begin(), thresholds.end(), [d](double t) { return t >= d; });
  return floor + uint32_t(reach - thresholds.begin());
}

glm::vec2 placed_position(const display_geometry& disp, const point& p, canvas_offset offset, bool mirror_x, bool mirror_y) {
  float cx = p.x - float(offset.x), cy = p.y - float(offset.y);
  if (mirror_x) cx = float(disp.width) - cx;
  if (mirror_y) cy = float(disp.height) - cy;
  return {cx, cy};
}

glm::vec2 canvas_position(const display_geometry& disp, glm::vec2 s, canvas_offset offset, bool mirror_x, bool mirror_y) {
  return {(mirror_x ? float(disp.width) - s.x : s.x) + float(offset.x),
          (mirror_y ? float(disp.height) - s.y : s.y) + float(offset.y)};
}

}  // namespace fov
