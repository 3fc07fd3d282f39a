// Temporal anti-aliasing on the device: the same three steps as interp/src/taa.cpp
// (reprojection by depth, clipping towards the current 3x3 neighbourhood, blending with
// the focus-lag ramp), one work item per pixel, in float.

// A camera frame: origin, right, up, forward (xyz of float4s) and half extents. The host's
// twin is cl_taa_camera (interp/src/cl_reconstruct.cpp); taa_camera_layout reports this
// side's layout so a test holds the two equal.
typedef struct {
  float4 origin, right, up, forward;
  float half_width, half_height;
} taa_camera;

// sizeof(taa_camera), then the byte offset of each field in declaration order.
__kernel void taa_camera_layout(__global uint* out) {
  taa_camera c;
  __private const char* base = (__private const char*)&c;
  out[0] = (uint)sizeof(taa_camera);
  out[1] = (uint)((__private const char*)&c.origin - base);
  out[2] = (uint)((__private const char*)&c.right - base);
  out[3] = (uint)((__private const char*)&c.up - base);
  out[4] = (uint)((__private const char*)&c.forward - base);
  out[5] = (uint)((__private const char*)&c.half_width - base);
  out[6] = (uint)((__private const char*)&c.half_height - base);
}

inline float3 taa_ray(const taa_camera* c, float sx, float sy, int w, int h) {
  const float u = (2 * sx / (float)w - 1) * c->half_width;
  const float v = (1 - 2 * sy / (float)h) * c->half_height;
  return normalize(c->forward.xyz + u * c->right.xyz + v * c->up.xyz);
}

// The focus-lag ramp: how far (0..1, reaching 1 at focus_lag degrees) the eccentricity of
// pixel (x, y) dropped when the gaze moved from (gx0, gy0) to (gx1, gy1). The drop is
// atan(a) - atan(b) = atan(q), q = (a - b) / (1 + a b); it reaches focus_lag where q reaches
// tan_lag = tan(focus_lag). Below that, for focus_lag up to 20 degrees (q < 0.364), five
// terms of the arctangent's series are exact to 2e-6 rad: PoCL's atan and hypot cost more
// than all the rest of this kernel.
inline float taa_lag(float gx0, float gy0, float gx1, float gy1, int x, int y, float width_v, float focus_lag,
                     float tan_lag) {
  const float px = (float)x + 0.5f, py = (float)y + 0.5f;
  const float a = sqrt((px - gx0) * (px - gx0) + (py - gy0) * (py - gy0)) / width_v;
  const float b = sqrt((px - gx1) * (px - gx1) + (py - gy1) * (py - gy1)) / width_v;
  if (a <= b) return 0.0f;
  const float q = (a - b) / (1 + a * b);
  if (q >= tan_lag) return 1.0f;
  const float q2 = q * q;
  const float angle = tan_lag <= 0.364f ? q * (1 - q2 * (1.0f / 3 - q2 * (1.0f / 5 - q2 * (1.0f / 7 - q2 / 9)))) : atan(q);
  return clamp(degrees(angle) / focus_lag, 0.0f, 1.0f);
}

inline float4 taa_bilinear(__global const float4* f, float x, float y, int w, int h) {
  x = clamp(x, 0.0f, (float)(w - 1));
  y = clamp(y, 0.0f, (float)(h - 1));
  const int x0 = (int)x, y0 = (int)y;
  const int x1 = min(x0 + 1, w - 1), y1 = min(y0 + 1, h - 1);
  const float tx = x - (float)x0, ty = y - (float)y0;
  const float4 a = mix(f[y0 * w + x0], f[y0 * w + x1], tx);
  const float4 b = mix(f[y1 * w + x0], f[y1 * w + x1], tx);
  return mix(a, b, ty);
}

__kernel void taa_resolve(__global const float4* current, __global const float* depth, __global const float4* history,
                          __global float4* out, int w, int h, taa_camera now, taa_camera before, uint still_camera,
                          float gx, float gy, float gx_before, float gy_before, uint still_gaze, float width_v,
                          float alpha, float gamma, float focus_lag, float tan_lag) {
  const int x = get_global_id(0), y = get_global_id(1);
  const int i = y * w + x;
  const float4 c = current[i];
  // 1. Where this pixel's surface was on the previous frame.
  float4 hist;
  if (still_camera) {
    hist = history[i];
  } else {
    const float3 dir = taa_ray(&now, (float)x + 0.5f, (float)y + 0.5f, w, h);
    const float z = isfinite(depth[i]) ? depth[i] : 1e7f;
    const float3 world = now.origin.xyz + dir * (z / dot(dir, now.forward.xyz));
    const float3 d = world - before.origin.xyz;
    const float zb = dot(d, before.forward.xyz);
    const float sx = (dot(d, before.right.xyz) / zb / before.half_width + 1) * 0.5f * (float)w;
    const float sy = (1 - dot(d, before.up.xyz) / zb / before.half_height) * 0.5f * (float)h;
    if (!(zb > 0) || sx < 0 || sy < 0 || sx >= (float)w || sy >= (float)h) {
      out[i] = c;
      return;
    }
    hist = taa_bilinear(history, sx - 0.5f, sy - 0.5f, w, h);
  }
  // 2. Clip the history towards the current colour, into the neighbourhood's box. Row and
  // column indices are clamped once; the clip runs on all four lanes at once (the fourth,
  // alpha, is 1 everywhere and never limits t).
  // The moments are of the differences from c: in a near-flat neighbourhood the plain
  // E[x^2] - E[x]^2 cancels to float noise, whose square root (~1e-3 x) moved the box.
  const int xl = max(x - 1, 0), xr = min(x + 1, w - 1);
  float4 sum = (float4)(0.0f), sum2 = (float4)(0.0f);
  for (int dy = -1; dy <= 1; ++dy) {
    __global const float4* row = current + clamp(y + dy, 0, h - 1) * w;
    const float4 a = row[xl] - c, b = row[x] - c, e = row[xr] - c;
    sum += a + b + e;
    sum2 += a * a + b * b + e * e;
  }
  const float4 offset = sum / 9.0f, mean = c + offset;
  const float4 sigma = sqrt(fmax(sum2 / 9.0f - offset * offset, (float4)(0.0f)));
  const float4 lo = fmin(mean - gamma * sigma, c), hi = fmax(mean + gamma * sigma, c);
  const float4 d = hist - c;
  // Per channel the t at which c + t d leaves the box; channels with d = 0 never do.
  const float4 reach = (select(lo, hi, d > 0.0f) - c) / d;
  const float4 limit = select((float4)(1.0f), reach, d != 0.0f);
  const float t = fmin(1.0f, fmin(limit.x, fmin(limit.y, limit.z)));
  hist = c + fmax(t, 0.0f) * d;
  // 3. Blend; pixels whose eccentricity dropped (the gaze moved towards them) prefer the current frame.
  float lag = 0;
  if (!still_gaze && focus_lag > 0) {
    lag = taa_lag(gx_before, gy_before, gx, gy, x, y, width_v, focus_lag, tan_lag);
  }
  const float a = alpha + (1 - alpha) * lag;
  out[i] = a * c + (1 - a) * hist;
}
