#include "fov/knn_table.h"
#include "fov/files.h"

#include <algorithm>
#include <stdexcept>

#include <flann/flann.hpp>
#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "knn_rank.h"

namespace fov {

namespace {

using knn_rank::distance2;
using knn_rank::extra_candidates;
using knn_rank::ranked;

}  // namespace

struct knn_builder::impl {
  flann::Matrix<float> dataset;
  flann::Index<flann::L2_Simple<float>> index;
  explicit impl(const std::vector<point>& points)
      // FLANN reads the x, y floats of each point in place (stride = sizeof(point)).
      : dataset(const_cast<float*>(&points[0].x), points.size(), 2, sizeof(point)),
        index(dataset, flann::KDTreeSingleIndexParams(10)) {
    index.buildIndex();
  }
};

knn_builder::knn_builder(const std::vector<point>& points, uint32_t canvas_width, uint32_t canvas_height,
                         uint32_t k)
    : points_(points), width_(canvas_width), height_(canvas_height), k_(k) {
  if (k < 1 || k > max_knn) throw std::invalid_argument(fmt::format("k must lie in 1..{} (got {})", max_knn, k));
  if (points.size() < k)
    throw std::invalid_argument(fmt::format("k = {} exceeds the {} points of the set; lower k", k, points.size()));
  if (points.size() >= (uint64_t(1) << 32)) throw std::invalid_argument("more than 2^32 points");
  impl_ = std::make_unique<impl>(points);
}

knn_builder::~knn_builder() = default;

void knn_builder::rows(uint32_t y0, uint32_t y1, uint32_t* out) const {
  const uint32_t kq = uint32_t(std::min<size_t>(points_.size(), k_ + extra_candidates));
  tbb::parallel_for(tbb::blocked_range<uint32_t>(y0, y1, 2), [&](const tbb::blocked_range<uint32_t>& band) {
    std::vector<float> queries(size_t(width_) * 2);
    std::vector<size_t> found(size_t(width_) * kq);
    std::vector<float> dists(size_t(width_) * kq);
    std::vector<ranked> rank(kq);
    flann::SearchParams search(flann::FLANN_CHECKS_UNLIMITED, 0, true);
    search.cores = 1;
    for (uint32_t y = band.begin(); y < band.end(); ++y) {
      for (uint32_t x = 0; x < width_; ++x) {
        queries[2 * x] = float(x) + 0.5f;
        queries[2 * x + 1] = float(y) + 0.5f;
      }
      flann::Matrix<float> q(queries.data(), width_, 2);
      flann::Matrix<size_t> idx(found.data(), width_, kq);
      flann::Matrix<float> dst(dists.data(), width_, kq);
      impl_->index.knnSearch(q, idx, dst, kq, search);
      uint32_t* row = out + size_t(y - y0) * width_ * k_;
      for (uint32_t x = 0; x < width_; ++x) {
        for (uint32_t j = 0; j < kq; ++j) {
          const auto i = uint32_t(found[size_t(x) * kq + j]);
          rank[j] = {distance2(points_[i], queries[2 * x], queries[2 * x + 1]), i};
        }
        std::partial_sort(rank.begin(), rank.begin() + k_, rank.end());
        for (uint32_t j = 0; j < k_; ++j) row[size_t(x) * k_ + j] = rank[j].index;
      }
    }
  });
}

std::string knn_table_memory_problem(const display_geometry& d, uint32_t k) {
  return memory_problem(knn_table_bytes(d, k), fmt::format("the k-NN table of a {}x{} display's set (k = {})", d.width, d.height, k));
}

knn_table build_knn_table(const std::vector<point>& points, uint32_t canvas_width, uint32_t canvas_height,
                          const knn_params& params) {
  knn_builder builder(points, canvas_width, canvas_height, params.k);
  knn_table table;
  table.width = canvas_width;
  table.height = canvas_height;
  table.k = params.k;
  table.group = std::clamp<uint32_t>(params.group, 1, params.k);
  table.entries.resize(table.pixel_count() * params.k);
  const uint32_t band = 64;
  std::vector<uint32_t> rows(size_t(band) * canvas_width * params.k);
  for (uint32_t y0 = 0; y0 < canvas_height; y0 += band) {
    const uint32_t y1 = std::min(canvas_height, y0 + band);
    builder.rows(y0, y1, rows.data());
    tbb::parallel_for(tbb::blocked_range<uint32_t>(y0, y1), [&](const tbb::blocked_range<uint32_t>& r) {
      for (uint32_t y = r.begin(); y < r.end(); ++y)
        for (uint32_t x = 0; x < canvas_width; ++x) {
          const uint64_t pixel = uint64_t(y) * canvas_width + x;
          const uint32_t* src = &rows[(size_t(y - y0) * canvas_width + x) * params.k];
          for (uint32_t j = 0; j < params.k; ++j) table.entries[table.offset(pixel, j)] = src[j];
        }
    });
  }
  set_knn_radii(table, points);
  return table;
}

std::vector<uint32_t> brute_force_knn(const std::vector<point>& points, float qx, float qy, uint32_t k) {
  std::vector<ranked> all(points.size());
  for (size_t i = 0; i < points.size(); ++i) all[i] = {distance2(points[i], qx, qy), uint32_t(i)};
  k = uint32_t(std::min<size_t>(k, all.size()));
  std::partial_sort(all.begin(), all.begin() + k, all.end());
  std::vector<uint32_t> out(k);
  for (uint32_t j = 0; j < k; ++j) out[j] = all[j].index;
  return out;
}

knn_table regroup(const knn_table& table, uint32_t group) {
  if (std::clamp<uint32_t>(group, 1, table.k) == table.group) return table;
  knn_table out;
  out.max_radius = table.max_radius;
  out.radius_by_rank = table.radius_by_rank;
  out.radius_by_tile = table.radius_by_tile;
  out.width = table.width;
  out.height = table.height;
  out.k = table.k;
  out.group = std::clamp<uint32_t>(group, 1, table.k);
  out.entries.resize(table.entries.size());
  const uint64_t n = table.pixel_count();
  tbb::parallel_for(tbb::blocked_range<uint64_t>(0, n, 4096), [&](const tbb::blocked_range<uint64_t>& r) {
    for (uint64_t p = r.begin(); p < r.end(); ++p)
      for (uint32_t j = 0; j < table.k; ++j) out.entries[out.offset(p, j)] = table.entries[table.offset(p, j)];
  });
  return out;
}

}  // namespace fov
