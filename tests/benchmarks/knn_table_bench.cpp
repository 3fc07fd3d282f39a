// Measures the k-NN table choices of docs/benchmarks.md on a real FOVE set:
//  - a weighted gather over a 1280x1440 screen (inverse-square-distance weights, the
//    access pattern of Shepard reconstruction) for each table layout (group size) and
//    each number of neighbours read, beside a plain copy of the same bytes;
//  - on-disk size and load time of each table encoding, and of two rejected ones.
// Set FOV_BENCH_SET to a .fovset (default: precomputed/fove-s1.00.fovset, generated
// in memory with `fovgen --display fove` defaults when missing).
#include <optional>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>

#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <zstd.h>

#include "fov/knn_table.h"
#include "fov/pointset_io.h"

namespace {

std::string set_path() {
  const char* env = std::getenv("FOV_BENCH_SET");
  return env ? env : FOV_SOURCE_DIR "/precomputed/fove-s1.00.fovset";
}

const fov::pointset& bench_set() {
  static const fov::pointset set = [] {
    if (std::filesystem::exists(set_path())) return fov::load_pointset(set_path());
    fov::spacing_model m;
    return fov::generate_pointset(m, {}, {});
  }();
  return set;
}

const fov::knn_table& layout(uint32_t group) {
  static std::map<uint32_t, fov::knn_table> tables;
  static std::mutex lock;
  std::lock_guard<std::mutex> guard(lock);
  auto it = tables.find(group);
  if (it == tables.end()) it = tables.emplace(group, fov::regroup(bench_set().table, group)).first;
  return it->second;
}

struct rgba {
  float r, g, b, a;
};

const std::vector<rgba>& point_colours() {
  static const std::vector<rgba> colours = [] {
    std::vector<rgba> c(bench_set().points.size());
    for (size_t i = 0; i < c.size(); ++i) c[i] = {float(i % 7) / 7, float(i % 11) / 11, float(i % 13) / 13, 1};
    return c;
  }();
  return colours;
}

// args: group size, neighbours read
void BM_WeightedGather(benchmark::State& state) {
  const auto group = uint32_t(state.range(0)), k_used = uint32_t(state.range(1));
  const fov::pointset& set = bench_set();
  if (k_used > set.table.k) return state.SkipWithError("set has fewer neighbours");
  const fov::knn_table& t = layout(group);
  const std::vector<rgba>& colour = point_colours();
  const int w = set.model.display.width, h = set.model.display.height;
  const fov::canvas_offset o = fov::offset_for_gaze(set.model.display, {0.5 * w, 0.5 * h});
  std::vector<rgba> out(size_t(w) * h);
  for (auto _ : state) {
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y < rows.end(); ++y) {
        const uint64_t row = uint64_t(y + o.y) * t.width + uint64_t(o.x);
        for (int x = 0; x < w; ++x) {
          const float px = float(x + o.x) + 0.5f, py = float(y + o.y) + 0.5f;
          rgba acc{0, 0, 0, 0};
          float wsum = 0;
          for (uint32_t j = 0; j < k_used; ++j) {
            const uint32_t i = t.entries[t.offset(row + x, j)];
            const fov::point& p = set.points[i];
            const float dx = p.x - px, dy = p.y - py;
            const float wt = 1.0f / (dx * dx + dy * dy + 1e-4f);
            acc.r += wt * colour[i].r, acc.g += wt * colour[i].g, acc.b += wt * colour[i].b;
            wsum += wt;
          }
          out[size_t(y) * w + x] = {acc.r / wsum, acc.g / wsum, acc.b / wsum, 1};
        }
      }
    });
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.counters["Mpix/s"] = benchmark::Counter(double(w) * h * state.iterations() / 1e6, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_WeightedGather)
    ->ArgNames({"group", "k"})
    ->ArgsProduct({{1, 4, 8, 20}, {1, 5, 10, 20}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The bandwidth yardstick: copy as many bytes as the gather's table reads at this k.
void BM_CopyTableBytes(benchmark::State& state) {
  const auto k_used = uint32_t(state.range(0));
  const fov::pointset& set = bench_set();
  const size_t n = size_t(set.model.display.width) * set.model.display.height * k_used;
  std::vector<uint32_t> src(n, 1), dst(n);
  for (auto _ : state) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1 << 16), [&](const tbb::blocked_range<size_t>& r) {
      std::memcpy(&dst[r.begin()], &src[r.begin()], (r.end() - r.begin()) * 4);
    });
    benchmark::DoNotOptimize(dst.data());
  }
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(n) * 8);
}
BENCHMARK(BM_CopyTableBytes)->ArgName("k")->Arg(5)->Arg(20)->Unit(benchmark::kMillisecond)->UseRealTime();

// The mask of points to trace for a centred gaze (traced_point_mask: the table scan).
void BM_TracedPointMask(benchmark::State& state) {
  const fov::pointset& set = bench_set();
  for (auto _ : state)
    benchmark::DoNotOptimize(
        fov::traced_point_mask(set, {0.5 * set.model.display.width, 0.5 * set.model.display.height}, uint32_t(state.range(0))).data());
  state.counters["band_radius_px"] = set.table.radius_by_rank[size_t(state.range(0) - 1)];
}
BENCHMARK(BM_TracedPointMask)->ArgName("k_used")->Arg(5)->Arg(20)->Unit(benchmark::kMillisecond)->UseRealTime();

// Choosing the points to trace for a gaze (every frame of trace_points): the table scan of
// the screen's border (traced_points) against the index (make_traced_index, once per set
// and k; what the renderer uses). args: k_used, index (0 scan, 1 index), gaze (0 centre,
// 1 bottom-right corner).
void BM_TracedPoints(benchmark::State& state) {
  const fov::pointset& set = bench_set();
  const auto k_used = uint32_t(state.range(0));
  const fov::display_geometry& d = set.model.display;
  const fov::gaze_point gaze = state.range(2) ? fov::gaze_point{double(d.width), double(d.height)}
                                              : fov::gaze_point{0.5 * d.width, 0.5 * d.height};
  const std::optional<fov::traced_index> index =
      state.range(1) ? std::optional<fov::traced_index>(fov::make_traced_index(set, k_used)) : std::nullopt;
  size_t traced = 0;
  for (auto _ : state) {
    const std::vector<uint32_t> v = index ? fov::traced_points(set, *index, gaze) : fov::traced_points(set, gaze, k_used);
    traced = v.size();
    benchmark::DoNotOptimize(v.data());
  }
  state.counters["traced"] = double(traced);
  state.counters["band_radius_px"] = set.table.radius_by_rank[size_t(k_used - 1)];
  if (index) state.counters["index_margin_px"] = index->margin;
}
BENCHMARK(BM_TracedPoints)
    ->ArgNames({"k_used", "index", "gaze"})
    ->ArgsProduct({{5, 20}, {0, 1}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Building the index (once per set and k).
void BM_MakeTracedIndex(benchmark::State& state) {
  const fov::pointset& set = bench_set();
  for (auto _ : state) benchmark::DoNotOptimize(fov::make_traced_index(set, uint32_t(state.range(0))).reaches.data());
}
BENCHMARK(BM_MakeTracedIndex)->ArgName("k_used")->Arg(5)->Arg(20)->Unit(benchmark::kMillisecond)->UseRealTime();

// Load time (read, verify, decode) of the whole set in each stored encoding.
void BM_LoadSet(benchmark::State& state) {
  const auto encoding = fov::table_encoding(state.range(0));
  const std::string path = std::filesystem::temp_directory_path() / fmt::format("fovray-bench-{}.fovset", state.range(0));
  fov::save_params sp;
  sp.encoding = encoding;
  fov::save_pointset(path, bench_set(), sp);
  for (auto _ : state) benchmark::DoNotOptimize(fov::load_pointset(path).table.entries.data());
  state.counters["file_MB"] = double(std::filesystem::file_size(path)) / 1e6;
  state.counters["bits_per_entry"] =
      8.0 * double(std::filesystem::file_size(path)) / double(bench_set().table.entries.size());
  std::filesystem::remove(path);
}
BENCHMARK(BM_LoadSet)->ArgName("encoding")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

// Two codings we did not choose, for the record: zstd over the plain pixel-major
// indices, and zstd over per-pixel index sets (sorted, delta to the left pixel's set),
// which is smaller but loses the rank order, so a loader must re-sort every pixel.
void BM_RejectedEncodingSize(benchmark::State& state) {
  const bool sorted_sets = state.range(0) == 1;
  const fov::knn_table& t = bench_set().table;
  const uint32_t k = t.k;
  std::vector<uint8_t> bytes;
  std::vector<uint32_t> cur(k), prev(k, 0);
  auto varint = [&](uint64_t v) {
    for (; v >= 128; v >>= 7) bytes.push_back(uint8_t(v | 128));
    bytes.push_back(uint8_t(v));
  };
  for (uint64_t p = 0; p < t.pixel_count(); ++p) {
    for (uint32_t j = 0; j < k; ++j) cur[j] = t.entries[t.offset(p, j)];
    if (!sorted_sets) {
      for (uint32_t v : cur) for (int b = 0; b < 4; ++b) bytes.push_back(uint8_t(v >> (8 * b)));
      continue;
    }
    std::sort(cur.begin(), cur.end());
    const bool row_start = p % t.width == 0;
    for (uint32_t j = 0; j < k; ++j) {
      const int64_t d = int64_t(cur[j]) - int64_t(row_start ? 0 : prev[j]);
      varint((uint64_t(d) << 1) ^ uint64_t(d >> 63));
    }
    prev = cur;
  }
  size_t compressed = 0;
  for (auto _ : state) {
    compressed = 0;
    const size_t chunk = bytes.size() / 45 + 1;
    std::vector<uint8_t> z(ZSTD_compressBound(chunk));
    for (size_t at = 0; at < bytes.size(); at += chunk)
      compressed += ZSTD_compress(z.data(), z.size(), &bytes[at], std::min(chunk, bytes.size() - at), 3);
  }
  state.counters["table_MB"] = double(compressed) / 1e6;
  state.counters["bits_per_entry"] = 8.0 * double(compressed) / double(t.entries.size());
}
BENCHMARK(BM_RejectedEncodingSize)->ArgName("sorted_sets")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
