// Geometry-only weights, computed once per canvas pixel: RBF's (thesis Eqs. 7-10 made cheap),
// barycentric and natural-neighbour (delaunay.h).
//
// A canvas pixel's k neighbours never change, only their colours do, and these interpolants
// are linear in those colours: s(x) = sum_i w_i(x) f_i with weights that depend on the points'
// positions (and, for RBF, spacings) alone. Computing them once per canvas pixel (RBF: solving
// the (k+1) x (k+1) system) and keeping the k weights, by rank of the pixel's k nearest,
// turns every later frame into a weighted sum, the same work as Shepard. Weights are computed
// per 64 x 64 canvas tile the first time a screen covers it, so a gaze that moves only pays
// for the tiles it uncovers. The Delaunay methods triangulate the whole set when the cache is
// made (memory linear in the points: triangulation_bytes()).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "fov/pointset.h"
#include "fov/reconstruct_params.h"

namespace fov {

class delaunay;

class weight_cache {
 public:
  static constexpr uint32_t tile = 64;  // canvas pixels per tile side

  // Weights for `params` (method rbf: its k, kernel and shape; barycentric, natural: k) over
  // the set's canvas. No pixel's weights are computed yet (the Delaunay methods' triangulation
  // is). Throws std::invalid_argument as check_reconstruct_inputs, or for another method.
  weight_cache(const pointset& set, const reconstruct_params& params);
  ~weight_cache();
  weight_cache(const weight_cache&) = delete;
  weight_cache& operator=(const weight_cache&) = delete;

  // True when this cache holds the weights `params` asks for.
  bool serves(const reconstruct_params& params) const;

  // Computes every tile the screen at offset `o` covers that is not computed yet (in
  // parallel) and returns their indices. Statistics of the solves accumulate in stats().
  std::vector<uint32_t> prepare(canvas_offset o);

  // The k weights of canvas pixel (cx, cy), nearest neighbour first; its tile must be ready.
  const float* weights(uint32_t cx, uint32_t cy) const {
    return data_.data() + (size_t(cy / tile) * tiles_x_ + cx / tile) * tile_floats() +
           (size_t(cy % tile) * tile + cx % tile) * k_;
  }

  uint32_t k() const { return k_; }
  uint32_t tiles_x() const { return tiles_x_; }
  size_t tile_floats() const { return size_t(tile) * tile * k_; }
  size_t tiles_ready() const;
  const float* data() const { return data_.data(); }  // tile-major: tile, pixel in tile, rank
  size_t floats() const { return data_.size(); }
  const weight_stats& stats() const { return stats_; }
  double seconds() const { return seconds_; }  // wall time spent computing tiles (and triangulating) so far
  size_t triangulation_bytes() const;           // 0 for RBF

 private:
  const pointset& set_;
  reconstruct_params params_;
  std::unique_ptr<const class delaunay> triangulation_;  // barycentric and natural
  uint32_t k_ = 0, tiles_x_ = 0, tiles_y_ = 0;
  std::vector<uint8_t> ready_;
  std::vector<float, table_allocator<float>> data_;  // pages are touched only for computed tiles
  weight_stats stats_;
  double seconds_ = 0;
};

}  // namespace fov
