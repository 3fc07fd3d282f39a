// Reconstruction kernels (thesis Sec. 4.3): each work item rebuilds one screen pixel from
// the k nearest points of its canvas pixel, listed in the point set's table or ranked from
// its cell's candidates. With a mirrored
// pattern (mirror_x, mirror_y) screen pixel (x, y) reads the table at the mirrored pixel.
// Same rules as the C++ path (interp/include/fov/reconstruct.h), in float.

// Constants shared with C++ come from the host at build time (cl_reconstructor::
// kernel_build_options): FOV_MAX_K = max_knn (knn_table.h), FOV_WEIGHT_TILE =
// weight_cache::tile (weight_cache.h), FOV_CELL_TILE = knn_cells::tile (pointset.h),
// FOV_BLOCK = refinement_block (frame.h), FOV_ON_POINT = on_point_px and FOV_SHEPARD_TIE =
// shepard_tie (reconstruct.h).
#if !defined(FOV_MAX_K) || !defined(FOV_WEIGHT_TILE) || !defined(FOV_CELL_TILE) || !defined(FOV_BLOCK) || \
    !defined(FOV_ON_POINT) || !defined(FOV_SHEPARD_TIE)
#error "build with -DFOV_MAX_K=... -DFOV_WEIGHT_TILE=... -DFOV_CELL_TILE=... -DFOV_BLOCK=... -DFOV_ON_POINT=... -DFOV_SHEPARD_TIE=... (cl_reconstructor::kernel_build_options)"
#endif

// Distances are ranked exactly as the C++ path ranks them (distgen/src/knn_cells.cpp): in
// double where the device has it, with no fused multiply-adds.
#pragma OPENCL FP_CONTRACT OFF
#ifdef cl_khr_fp64
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
typedef double rank_t;
#define FOV_REACH_SLACK 1e-12
#else
typedef float rank_t;
#define FOV_REACH_SLACK 1e-4f  // wider in float: extra candidates cost time, never neighbours
#endif

// Offset of rank j of a canvas pixel in the grouped-plane table (docs/pointset-format.md).
inline ulong table_offset(ulong pixel, uint j, uint k_stored, uint group, ulong pixel_count) {
  const uint g = j / group;
  const uint width_g = min(group, k_stored - g * group);
  return (ulong)g * group * pixel_count + pixel * width_g + (j - g * group);
}

inline rank_t distance2_to(float2 p, rank_t x, rank_t y) {
  const rank_t dx = (rank_t)p.x - x, dy = (rank_t)p.y - y;
  return dx * dx + dy * dy;
}

// The k nearest points of canvas pixel (cx, cy), nearest first (ties: smaller index), into
// idx: read from the table (cells == 0), or ranked from the candidates of the pixel's cell
// (distgen/include/fov/knn_cells.h), packed in `nb` as tiles, then cell offsets from
// cell_start_at, then candidates from candidates_at.
inline void neighbours(__global const uint* nb, uint cells, uint canvas_width, uint k_stored, uint group,
                       ulong pixel_count, uint cell_tiles_x, ulong cell_start_at, ulong candidates_at,
                       __global const float2* position, uint cx, uint cy, uint k, uint* idx) {
  if (!cells) {
    const ulong pixel = (ulong)cy * canvas_width + cx;
    for (uint j = 0; j < k; ++j) idx[j] = nb[table_offset(pixel, j, k_stored, group, pixel_count)];
    return;
  }
  const uint v = nb[(cy / FOV_CELL_TILE) * cell_tiles_x + cx / FOV_CELL_TILE];
  const uint l = v & 7u, side = FOV_CELL_TILE >> l;
  const uint cell = (v >> 3) + ((cy % FOV_CELL_TILE) >> l) * side + ((cx % FOV_CELL_TILE) >> l);
  const rank_t mid = (rank_t)0.5 * (rank_t)(1u << l);
  const rank_t ccx = (rank_t)((cx >> l) << l) + mid, ccy = (rank_t)((cy >> l) << l) + mid;
  const rank_t qx = (rank_t)cx + (rank_t)0.5, qy = (rank_t)cy + (rank_t)0.5;
  const uint a = nb[cell_start_at + cell], b = nb[cell_start_at + cell + 1];
  const rank_t delta = (rank_t)((1u << l) - 1u) * sqrt((rank_t)0.5);
  const rank_t reach = sqrt(distance2_to(position[nb[candidates_at + a + k - 1]], ccx, ccy)) + 2 * delta;
  const rank_t reach2 = reach * reach * (1 + FOV_REACH_SLACK) + FOV_REACH_SLACK;
  rank_t best[FOV_MAX_K];
  uint n = 0;
  for (uint at = a; at < b; ++at) {
    const uint i = nb[candidates_at + at];
    const float2 p = position[i];
    if (distance2_to(p, ccx, ccy) > reach2) break;
    const rank_t d = distance2_to(p, qx, qy);
    if (n == k && !(d < best[k - 1] || (d == best[k - 1] && i < idx[k - 1]))) continue;
    uint j = n < k ? n++ : k - 1;
    for (; j > 0 && (d < best[j - 1] || (d == best[j - 1] && i < idx[j - 1])); --j) best[j] = best[j - 1], idx[j] = idx[j - 1];
    best[j] = d;
    idx[j] = i;
  }
}

// The arguments every kernel takes first: where the neighbours are and where the screen lies;
// then, for an adaptive frame (level_mask in frame.h), its refinement map: with map_on a work
// item whose canvas pixel's block reads another level than map_level writes nothing.
#define FOV_NEIGHBOUR_ARGS                                                                              \
  __global const uint *table, uint cells, uint canvas_width, uint k_stored, uint group, ulong pixel_count, \
      uint cell_tiles_x, ulong cell_start_at, ulong candidates_at, __global const float2 *position,      \
      int offset_x, int offset_y, uint width, uint mirror_x, uint mirror_y, __global const uchar *level_map, \
      uint map_on, uint map_level, uint map_x0, uint map_y0, uint map_blocks_x
#define FOV_OTHER_LEVEL(cx, cy) \
  (map_on && level_map[((cy) - map_y0) / FOV_BLOCK * map_blocks_x + ((cx) - map_x0) / FOV_BLOCK] != map_level)
#define FOV_NEIGHBOURS(cx, cy, k, idx)                                                                  \
  neighbours(table, cells, canvas_width, k_stored, group, pixel_count, cell_tiles_x, cell_start_at, \
             candidates_at, position, cx, cy, k, idx)

__kernel void reconstruct_nn(FOV_NEIGHBOUR_ARGS, __global const float4* colour, __global const float* depth,
                             __global float4* out_rgb, __global float* out_depth) {
  const int sx = get_global_id(0), sy = get_global_id(1);
  const int tx = mirror_x ? (int)width - 1 - sx : sx, ty = mirror_y ? (int)get_global_size(1) - 1 - sy : sy;
  if (FOV_OTHER_LEVEL((uint)(tx + offset_x), (uint)(ty + offset_y))) return;
  uint found[1];
  FOV_NEIGHBOURS((uint)(tx + offset_x), (uint)(ty + offset_y), 1, found);
  const uint i = found[0];
  out_rgb[sy * width + sx] = colour[i];
  out_depth[sy * width + sx] = depth[i];
}

// A point's distance from a pixel centre on the canvas: OpenCL's distance() guards against
// overflow, which canvas coordinates cannot reach, and costs more on a CPU device.
inline float canvas_distance(float2 p, float2 centre) {
  const float2 d = p - centre;
  return sqrt(d.x * d.x + d.y * d.y);
}

// Modified Shepard's v of a neighbour at distance h within radius r: 0 at the radius, within
// the relative tie FOV_SHEPARD_TIE (the C++ path's rule, reconstruct.h shepard_tie).
inline float shepard_v(float h, float r) { return h >= r * (1.0f - FOV_SHEPARD_TIE) ? 0.0f : (r - h) / (r * h); }

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
    float w = shepard_v(h[j], r_hit);
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
__kernel void reconstruct_shepard(FOV_NEIGHBOUR_ARGS, uint k, uint renka, __global const float4* colour,
                                  __global const float* depth, __global float4* out_rgb, __global float* out_depth) {
  const int sx = get_global_id(0), sy = get_global_id(1);
  const int tx = mirror_x ? (int)width - 1 - sx : sx, ty = mirror_y ? (int)get_global_size(1) - 1 - sy : sy;
  if (FOV_OTHER_LEVEL((uint)(tx + offset_x), (uint)(ty + offset_y))) return;
  const float2 centre = (float2)((float)(tx + offset_x) + 0.5f, (float)(ty + offset_y) + 0.5f);
  float h[FOV_MAX_K];
  uint idx[FOV_MAX_K];
  FOV_NEIGHBOURS((uint)(tx + offset_x), (uint)(ty + offset_y), k, idx);
  for (uint j = 0; j < k; ++j) h[j] = canvas_distance(position[idx[j]], centre);
  const size_t at = (size_t)sy * width + sx;

  float4 acc = (float4)(0.0f);
  float wsum = 0.0f;
  int exact = -1;
  const float r = h[k - 1];
  for (uint j = 0; j < k && exact < 0; ++j) {
    if (h[j] < FOV_ON_POINT) { exact = (int)j; break; }
    float w = shepard_v(h[j], r);
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

// Precomputed linear weights (RBF, interp/include/fov/weight_cache.h): colour = sum w_j f_j with
// the canvas pixel's k weights, stored tile-major (FOV_WEIGHT_TILE^2 canvas pixels per tile); depth
// as Shepard's.
__kernel void reconstruct_weighted(FOV_NEIGHBOUR_ARGS, uint k, uint renka, __global const float* weights, uint tiles_x,
                                   __global const float4* colour, __global const float* depth,
                                   __global float4* out_rgb, __global float* out_depth) {
  const int sx = get_global_id(0), sy = get_global_id(1);
  const int tx = mirror_x ? (int)width - 1 - sx : sx, ty = mirror_y ? (int)get_global_size(1) - 1 - sy : sy;
  if (FOV_OTHER_LEVEL((uint)(tx + offset_x), (uint)(ty + offset_y))) return;
  const uint cx = (uint)(tx + offset_x), cy = (uint)(ty + offset_y);
  const float2 centre = (float2)((float)cx + 0.5f, (float)cy + 0.5f);
  __global const float* w = weights +
                            ((ulong)(cy / FOV_WEIGHT_TILE) * tiles_x + cx / FOV_WEIGHT_TILE) *
                                (FOV_WEIGHT_TILE * FOV_WEIGHT_TILE * (ulong)k) +
                            ((ulong)(cy % FOV_WEIGHT_TILE) * FOV_WEIGHT_TILE + cx % FOV_WEIGHT_TILE) * k;
  float h[FOV_MAX_K];
  uint idx[FOV_MAX_K];
  float4 acc = (float4)(0.0f);
  FOV_NEIGHBOURS(cx, cy, k, idx);
  for (uint j = 0; j < k; ++j) {
    h[j] = canvas_distance(position[idx[j]], centre);
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
