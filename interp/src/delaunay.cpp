#include "fov/delaunay.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <utility>

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/natural_neighbor_coordinates_2.h>

namespace fov {

namespace {

using kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using vertex_base = CGAL::Triangulation_vertex_base_with_info_2<uint32_t, kernel>;
using tds = CGAL::Triangulation_data_structure_2<vertex_base>;
using triangulation = CGAL::Delaunay_triangulation_2<kernel, tds>;
using cgal_point = kernel::Point_2;
using vertex_handle = triangulation::Vertex_handle;
using face_handle = triangulation::Face_handle;

}  // namespace

struct delaunay::impl {
  triangulation t;
  double seconds = 0;
};

delaunay::delaunay(const std::vector<point>& points) : impl_(std::make_unique<impl>()) {
  const auto start = std::chrono::steady_clock::now();
  // Coincident points: the smallest index stands for all of them (sorted by position, then index).
  std::vector<uint32_t> order(points.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    const point &p = points[a], &q = points[b];
    return p.x != q.x ? p.x < q.x : p.y != q.y ? p.y < q.y : a < b;
  });
  std::vector<std::pair<cgal_point, uint32_t>> kept;
  kept.reserve(points.size());
  for (size_t n = 0; n < order.size(); ++n) {
    const point& p = points[order[n]];
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) throw std::invalid_argument("a point's position is not finite");
    if (n > 0 && points[order[n - 1]].x == p.x && points[order[n - 1]].y == p.y) continue;
    kept.emplace_back(cgal_point(p.x, p.y), order[n]);
  }
  // Back in index order (Morton order for fovgen's sets): CGAL's spatial sort is then
  // deterministic and the result does not depend on the sort above.
  std::sort(kept.begin(), kept.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
  impl_->t.insert(kept.begin(), kept.end());
  impl_->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

delaunay::~delaunay() = default;

int delaunay::dimension() const { return impl_->t.dimension(); }
size_t delaunay::vertices() const { return impl_->t.number_of_vertices(); }
size_t delaunay::faces() const { return impl_->t.dimension() == 2 ? impl_->t.number_of_faces() : 0; }
size_t delaunay::bytes() const {
  // The data structure's own records: a vertex and a face each, with their handles.
  return (impl_->t.number_of_vertices() + 1) * sizeof(tds::Vertex) + impl_->t.tds().number_of_faces() * sizeof(tds::Face);
}
double delaunay::seconds() const { return impl_->seconds; }

namespace {

// Drops weights below the floor, renormalises, and checks the count.
void finish(delaunay_weights& w, double sum) {
  uint32_t kept = 0;
  double kept_sum = 0;
  for (uint32_t i = 0; i < w.n; ++i)
    if (std::fabs(w.weight[i]) >= delaunay_weight_floor * std::fabs(sum)) {
      w.index[kept] = w.index[i];
      w.weight[kept] = w.weight[i];
      kept_sum += w.weight[kept++];
    }
  w.n = kept;
  if (kept == 0 || !(kept_sum > 0)) {
    w.where = delaunay_case::outside, w.n = 0;
    return;
  }
  for (uint32_t i = 0; i < kept; ++i) w.weight[i] /= kept_sum;
}

// Collects CGAL's (vertex, coordinate) pairs into a delaunay_weights, counting past the end.
struct collector {
  delaunay_weights* w;
  size_t seen = 0;
  collector& operator*() { return *this; }
  collector& operator++() { return *this; }
  collector operator++(int) { return *this; }
  collector& operator=(const std::pair<vertex_handle, kernel::FT>& c) {
    if (seen < max_knn) w->index[seen] = c.first->info(), w->weight[seen] = c.second;
    ++seen;
    return *this;
  }
};

}  // namespace

void delaunay::weigh(method how, const double* x, const double* y, size_t count, delaunay_weights* out) const {
  if (how != method::barycentric && how != method::natural)
    throw std::invalid_argument("delaunay::weigh needs method barycentric or natural");
  const triangulation& t = impl_->t;
  face_handle hint;
  for (size_t i = 0; i < count; ++i) {
    delaunay_weights& w = out[i];
    w.where = delaunay_case::outside;
    w.n = 0;
    if (t.dimension() < 2) continue;
    const cgal_point p(x[i], y[i]);
    triangulation::Locate_type lt;
    int li = 0;
    const face_handle f = t.locate(p, lt, li, hint);
    if (lt == triangulation::OUTSIDE_CONVEX_HULL || lt == triangulation::OUTSIDE_AFFINE_HULL) continue;
    hint = f;
    w.where = delaunay_case::inside;
    if (lt == triangulation::VERTEX) {
      w.n = 1, w.index[0] = f->vertex(li)->info(), w.weight[0] = 1;
      continue;
    }
    if (how == method::natural) {
      collector c{&w};
      const auto result = CGAL::natural_neighbor_coordinates_2(t, p, c, CGAL::Identity<std::pair<vertex_handle, kernel::FT>>(), f);
      if (!result.third) {
        w.where = delaunay_case::outside;
        continue;
      }
      if (result.first.seen > max_knn) {
        w.where = delaunay_case::crowded;
        continue;
      }
      w.n = uint32_t(result.first.seen);
      finish(w, result.second);
      continue;
    }
    // Barycentric over the face, or over the edge where the face is the infinite one.
    face_handle face = f;
    if (t.is_infinite(face)) face = face->neighbor(li);  // an edge of the hull: its finite side
    const cgal_point &a = face->vertex(0)->point(), &b = face->vertex(1)->point(), &c = face->vertex(2)->point();
    const double area = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
    const double wa = ((b.x() - p.x()) * (c.y() - p.y()) - (c.x() - p.x()) * (b.y() - p.y())) / area;
    const double wb = ((c.x() - p.x()) * (a.y() - p.y()) - (a.x() - p.x()) * (c.y() - p.y())) / area;
    const double wc = 1 - wa - wb;
    w.n = 3;
    w.index[0] = face->vertex(0)->info(), w.weight[0] = std::max(0.0, wa);
    w.index[1] = face->vertex(1)->info(), w.weight[1] = std::max(0.0, wb);
    w.index[2] = face->vertex(2)->info(), w.weight[2] = std::max(0.0, wc);
    finish(w, 1.0);
  }
}

}  // namespace fov
