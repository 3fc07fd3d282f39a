#include "fov/weight_cache.h"

#include "fov/delaunay.h"
#include "fov/reconstruct.h"

#include <algorithm>
#include <chrono>
#include <mutex>
#include <stdexcept>

#include <tbb/parallel_for.h>

namespace fov {

weight_cache::weight_cache(const pointset& set, const reconstruct_params& params)
    : set_(set), params_(params) {
  require_neighbours(set);
  if (!cached_weights_method(params.how))
    throw std::invalid_argument("a weight cache needs method rbf, barycentric or natural");
  check_reconstruct_params(params, stored_k(set));
  if (delaunay_method(params.how)) {
    triangulation_ = std::make_unique<const delaunay>(set.points);
    seconds_ = triangulation_->seconds();
  }
  k_ = params.k;
  tiles_x_ = (set.canvas_width() + tile - 1) / tile;
  tiles_y_ = (set.canvas_height() + tile - 1) / tile;
  ready_.assign(size_t(tiles_x_) * tiles_y_, 0);
  data_.resize(ready_.size() * tile_floats());
}

weight_cache::~weight_cache() = default;

bool weight_cache::serves(const reconstruct_params& p) const {
  if (p.how != params_.how || p.k != params_.k) return false;
  return p.how != method::rbf || (p.kernel == params_.kernel && p.shape == params_.shape);
}

size_t weight_cache::triangulation_bytes() const { return triangulation_ ? triangulation_->bytes() : 0; }

size_t weight_cache::tiles_ready() const { return size_t(std::count(ready_.begin(), ready_.end(), 1)); }

std::vector<uint32_t> weight_cache::prepare(canvas_offset o) {
  const uint32_t w = set_.model.display.width, h = set_.model.display.height;
  const uint32_t tx0 = uint32_t(o.x) / tile, tx1 = (uint32_t(o.x) + w - 1) / tile;
  const uint32_t ty0 = uint32_t(o.y) / tile, ty1 = (uint32_t(o.y) + h - 1) / tile;
  std::vector<uint32_t> todo;
  for (uint32_t ty = ty0; ty <= ty1; ++ty)
    for (uint32_t tx = tx0; tx <= tx1; ++tx)
      if (!ready_[size_t(ty) * tiles_x_ + tx]) todo.push_back(ty * tiles_x_ + tx);
  if (todo.empty()) return todo;
  const auto start = std::chrono::steady_clock::now();
  std::mutex lock;
  tbb::parallel_for(size_t(0), todo.size(), [&](size_t n) {
    const uint32_t index = todo[n], tx = index % tiles_x_, ty = index / tiles_x_;
    float* out = data_.data() + size_t(index) * tile_floats();
    weight_stats local;
    double weight[max_knn];
    delaunay_weights row[tile];  // the Delaunay methods: one row of the tile at a time
    double xs[tile], ys[tile];
    for (uint32_t y = 0; y < tile; ++y) {
      if (triangulation_) {
        for (uint32_t x = 0; x < tile; ++x) xs[x] = tx * tile + x + 0.5, ys[x] = ty * tile + y + 0.5;
        triangulation_->weigh(params_.how, xs, ys, tile, row);
      }
      for (uint32_t x = 0; x < tile; ++x) {
        const uint32_t cx = tx * tile + x, cy = ty * tile + y;
        float* dst = out + (size_t(y) * tile + x) * k_;
        if (cx >= set_.canvas_width() || cy >= set_.canvas_height()) {
          std::fill(dst, dst + k_, 0.0f);  // past the canvas edge: never read
          continue;
        }
        pixel_weights(set_, params_, cx, cy, weight, &local, triangulation_ ? &row[x] : nullptr);
        for (uint32_t j = 0; j < k_; ++j) dst[j] = float(weight[j]);
      }
    }
    std::lock_guard<std::mutex> guard(lock);
    stats_ += local;
  });
  for (uint32_t index : todo) ready_[index] = 1;
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return todo;
}

}  // namespace fov
