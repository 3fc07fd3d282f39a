// Reconstruction kernels (thesis Sec. 4.3): each work item rebuilds one screen pixel from
// the k nearest points its canvas pixel lists in the point set's table. With a mirrored
// pattern (mirror_x, mirror_y) screen pixel (x, y) reads the table at the mirrored pixel.
// Same rules as the C++ path (interp/include/fov/reconstruct.h), in float.

// Constants shared with C++ come from the host at build time (cl_reconstructor::
// kernel_build_options): FOV_MAX_K = max_knn (knn_table.h), FOV_RBF_TILE =
// rbf_weight_cache::tile (rbf_cache.h).
#if !defined(FOV_MAX_K) || !defined(FOV_RBF_TILE)
#error "build with -DFOV_MAX_K=... -DFOV_RBF_TILE=... (cl_reconstructor::kernel_build_options)"
#endif

// Offset of rank j of a canvas pixel in the grouped-plane table (docs/pointset-format.md).
inline ulong table_offset(ulong pixel, uint j, uint k_stored, uint group, ulong pixel_count) {
  const uint g = j / group;
  const uint width_g = min(group, k_stored - g * group);
  return (ulong)g * group * pixel_count + pixel * width_g + (j - g * group);
}

__kernel void reconstruct_nn(__global const uint* table, uint canvas_width, uint k_stored, uint group,
                             ulong pixel_count, int offset_x, int offset_y, uint width, uint mirror_x, uint mirror_y,
                             __global const float4* colour, __global const float* depth,
                             __global float4* out_rgb, __global float* out_depth) {
  const int sx = get_global_id(0), sy = get_global_id(1);
  const int tx = mirror_x ? (int)width - 1 - sx : sx, ty = mirror_y ? (int)get_global_size(1) - 1 - sy : sy;
  const ulong pixel = (ulong)(ty + offset_y) * canvas_width + (ulong)(tx + offset_x);
  const uint i = table[table_offset(pixel, 0, k_stored, group, pixel_count)];
  out_rgb[sy * width + sx] = colour[i];
  out_depth[sy * width + sx] = depth[i];
}

// Depth by Shepard over the neighbours that hit something (finite depth), with their own R;
// +inf when none did. A pixel on a point (a grid point) takes its depth, a miss included.
inline float shepard_depth(const float* h, const uint* idx, uint k, uint renka, __global const float* depth) {
  for (uint j = 0; j < k; ++j)
    if (h[j] < FOV_ON_POINT) return depth[idx[j]];
  float r_hit = -1.0f;
  uint hits = 0;
  for (uint j = 0; j < k; ++j)
    if (isfinite(depth[idx[j]])) { r_hit = h[j]; ++hits; }
  if (hits == 0) return INFINITY;
  float dacc = 0.0f, dw = 0.0f, dmean = 0.0f;
  for (uint j = 0; j < k; ++j) {
    const float d = depth[idx[j]];
    if (!isfinite(d)) continue;
    float w = (r_hit - h[j]) / (r_hit * h[j]);
    if (renka) w *= w;
    dacc += w * d;
    dw += w;
    dmean += d;
  }
  return dw > 0.0f ? dacc / dw : dmean / (float)hits;
}

// Modified Shepard: w = (R - h) / (R h), R the k-th neighbour's distance; a pixel on a
// point takes its value; all weights zero gives the mean. Depth uses the neighbours that
// hit something (finite depth), with their own R.
__kernel void reconstruct_shepard(__global const uint* table, uint canvas_width, uint k_stored, uint group,
                                  ulong pixel_count, int offset_x, int offset_y, uint width, uint mirror_x, uint mirror_y,
                                  __global const float2* position, uint k, uint renka,
                                  __global const float4* colour, __global const float* depth,
                                  __global float4* out_rgb, __global float* out_depth) {
  const int sx = get_global_id(0), sy = get_global_id(1);
  const int tx = mirror_x ? (int)width - 1 - sx : sx, ty = mirror_y ? (int)get_global_size(1) - 1 - sy : sy;
  const ulong pixel = (ulong)(ty + offset_y) * canvas_width + (ulong)(tx + offset_x);
  const float2 centre = (float2)((float)(tx + offset_x) + 0.5f, (float)(ty + offset_y) + 0.5f);
  float h[FOV_MAX_K];
  uint idx[FOV_MAX_K];
  for (uint j = 0; j < k; ++j) {
    idx[j] = table[table_offset(pixel, j, k_stored, group, pixel_count)];
    h[j] = distance(position[idx[j]], centre);
  }
  const size_t at = (size_t)sy * width + sx;

  float4 acc = (float4)(0.0f);
  float wsum = 0.0f;
  int exact = -1;
  const float r = h[k - 1];
  for (uint j = 0; j < k && exact < 0; ++j) {
    if (h[j] < FOV_ON_POINT) { exact = (int)j; break; }
    float w = (r - h[j]) / (r * h[j]);
    if (renka) w *= w;
    if (w != 0.0f) acc += w * colour[idx[j]];  // no weight, no term: a NaN there adds nothing (as in C++)
    wsum += w;
  }
  if (exact >= 0) {
    out_rgb[at] = colour[idx[exact]];
  } else if (wsum > 0.0f) {
    out_rgb[at] = acc / wsum;
  } else {
    float4 mean = (float4)(0.0f);
    for (uint j = 0; j < k; ++j) mean += colour[idx[j]];
    out_rgb[at] = mean / (float)k;
  }

  out_depth[at] = shepard_depth(h, idx, k, renka, depth);
}

// Precomputed linear weights (RBF, interp/include/fov/rbf_cache.h): colour = sum w_j f_j with
// the canvas pixel's k weights, stored tile-major (FOV_RBF_TILE^2 canvas pixels per tile); depth
// as Shepard's.
__kernel void reconstruct_weighted(__global const uint* table, uint canvas_width, uint k_stored, uint group,
                                   ulong pixel_count, int offset_x, int offset_y, uint width, uint mirror_x, uint mirror_y,
                                   __global const float2* position, uint k, uint renka, __global const float* weights,
                                   uint tiles_x, __global const float4* colour, __global const float* depth,
                                   __global float4* out_rgb, __global float* out_depth) {
  const int sx = get_global_id(0), sy = get_global_id(1);
  const int tx = mirror_x ? (int)width - 1 - sx : sx, ty = mirror_y ? (int)get_global_size(1) - 1 - sy : sy;
  const uint cx = (uint)(tx + offset_x), cy = (uint)(ty + offset_y);
  const ulong pixel = (ulong)cy * canvas_width + cx;
  const float2 centre = (float2)((float)cx + 0.5f, (float)cy + 0.5f);
  __global const float* w = weights +
                            ((ulong)(cy / FOV_RBF_TILE) * tiles_x + cx / FOV_RBF_TILE) *
                                (FOV_RBF_TILE * FOV_RBF_TILE * (ulong)k) +
                            ((ulong)(cy % FOV_RBF_TILE) * FOV_RBF_TILE + cx % FOV_RBF_TILE) * k;
  float h[FOV_MAX_K];
  uint idx[FOV_MAX_K];
  float4 acc = (float4)(0.0f);
  for (uint j = 0; j < k; ++j) {
    idx[j] = table[table_offset(pixel, j, k_stored, group, pixel_count)];
    h[j] = distance(position[idx[j]], centre);
    if (w[j] != 0.0f) acc += w[j] * colour[idx[j]];
  }
  const size_t at = (size_t)sy * width + sx;
  out_rgb[at] = acc;
  out_depth[at] = shepard_depth(h, idx, k, renka, depth);
}

// The bandwidth yardstick: a plain copy, one float4 per work item.
__kernel void copy_float4(__global const float4* in, __global float4* out) {
  const size_t i = get_global_id(0);
  out[i] = in[i];
}
