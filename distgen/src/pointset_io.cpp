#include "fov/pointset_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <chrono>
#include <cstring>
#include <fstream>
#include <vector>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <zstd.h>

#include "fov/checksum.h"
#include "fov/files.h"
#include "fov/knn_cells.h"
#include "fov/knn_table.h"

namespace fov {

namespace {

constexpr char magic[8] = {'F', 'O', 'V', 'S', 'E', 'T', '\r', '\n'};
constexpr uint64_t section_alignment = 64;

// Everything in the 512-byte header, in file order (docs/pointset-format.md).
struct header {
  char magic[8];
  uint32_t version, header_bytes;
  uint32_t width, height;
  double viewing_distance, scale;
  uint32_t acuity_model, fovea;  // fovea: fovea_layout (version 1: reserved, 0 = darts)
  double ct0, alpha, e2;
  uint64_t seed;
  uint32_t saturation_rejections, free_area_probes;
  double central_fraction;
  uint64_t phase1_points, phase2_points, darts_thrown, free_probes_accepted;
  double free_fraction;
  uint64_t point_count;
  uint32_t canvas_width, canvas_height, k, group, encoding, chunk_rows;
  uint64_t points_offset, points_bytes, table_offset, table_bytes;
  uint32_t points_crc, table_crc;
  double grid_spacing;  // version 2
  uint64_t grid_points;  // version 2
  // Version 3 (nested sets; 0 elsewhere): levels, their scales coarsest first, and the
  // levels section (one byte per point) placed after the table.
  uint32_t level_count, reserved;
  double level_scales[max_levels];
  uint64_t levels_offset, levels_bytes;
  uint32_t levels_crc;
  // Version 4 (acuity models other than the thesis's CSF; 0 elsewhere): the model's own
  // parameters, the other models' fields 0 (the CSF's ct0, alpha and e2 too).
  double mar_slope, mar_fovea_deg, mar_dead_zone_deg;  // linear_mar
  double pivot_cpd[5];                                 // piecewise_mar
  uint32_t sampler, reserved4;  // point_sampler (0 = poisson, written as versions 2 and 3 do)
  uint32_t header_crc;  // CRC-32C of bytes [0, 508) with this field excluded
};

// One list of fields serves both directions: f(value) for each, in file order.
template <class H, class F>
void visit_fields(H& h, F&& f) {
  for (auto& c : h.magic) f(c);
  f(h.version); f(h.header_bytes);
  f(h.width); f(h.height); f(h.viewing_distance); f(h.scale);
  f(h.acuity_model); f(h.fovea); f(h.ct0); f(h.alpha); f(h.e2);
  f(h.seed); f(h.saturation_rejections); f(h.free_area_probes); f(h.central_fraction);
  f(h.phase1_points); f(h.phase2_points); f(h.darts_thrown); f(h.free_probes_accepted);
  f(h.free_fraction);
  f(h.point_count);
  f(h.canvas_width); f(h.canvas_height); f(h.k); f(h.group); f(h.encoding); f(h.chunk_rows);
  f(h.points_offset); f(h.points_bytes); f(h.table_offset); f(h.table_bytes);
  f(h.points_crc); f(h.table_crc);
  f(h.grid_spacing); f(h.grid_points);
  f(h.level_count); f(h.reserved);
  for (auto& v : h.level_scales) f(v);
  f(h.levels_offset); f(h.levels_bytes); f(h.levels_crc);
  f(h.mar_slope); f(h.mar_fovea_deg); f(h.mar_dead_zone_deg);
  for (auto& v : h.pivot_cpd) f(v);
  f(h.sampler); f(h.reserved4);
}
constexpr size_t header_crc_offset = pointset_header_bytes - 4;

// A stored checksum against the computed one. Fuzz builds (FOV_FUZZ) accept any, so that
// mutated files reach the checks behind the checksums; every other build compares.
bool checksum_matches(uint32_t computed, uint32_t stored) {
#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
  (void)computed, (void)stored;
  return true;
#else
  return computed == stored;
#endif
}

// Little-endian byte copies of arithmetic values (this code targets little-endian hosts).
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "fovray assumes a little-endian host");

std::vector<uint8_t> encode_header(const header& h) {
  std::vector<uint8_t> bytes(pointset_header_bytes, 0);
  size_t at = 0;
  visit_fields(h, [&](const auto& v) {
    if (at + sizeof(v) > header_crc_offset) throw std::logic_error("point-set header fields overflow 508 bytes");
    std::memcpy(&bytes[at], &v, sizeof(v));
    at += sizeof(v);
  });
  const uint32_t crc = crc32c(bytes.data(), header_crc_offset);
  std::memcpy(&bytes[header_crc_offset], &crc, 4);
  return bytes;
}

header decode_header(const uint8_t* bytes) {
  header h{};
  size_t at = 0;
  visit_fields(h, [&](auto& v) {
    std::memcpy(&v, &bytes[at], sizeof(v));
    at += sizeof(v);
  });
  std::memcpy(&h.header_crc, &bytes[header_crc_offset], 4);
  return h;
}

// The acuity model and its own parameters as the header stores them (the other models'
// fields keep their defaults); the loader checks that those fields are 0.
acuity_params acuity_from_header(const header& h) {
  acuity_params a;
  a.model = acuity_model(h.acuity_model);
  switch (a.model) {
    case acuity_model::wang_csf: a.ct0 = h.ct0, a.alpha = h.alpha, a.e2 = h.e2; break;
    case acuity_model::linear_mar:
      a.mar_slope = h.mar_slope, a.mar_fovea_deg = h.mar_fovea_deg, a.mar_dead_zone_deg = h.mar_dead_zone_deg;
      break;
    case acuity_model::piecewise_mar: std::copy(std::begin(h.pivot_cpd), std::end(h.pivot_cpd), a.pivot_cpd); break;
  }
  return a;
}

// "" when the header's acuity fields fit its version and model: versions before 4 know only
// the CSF and have no version-4 fields; every model leaves the others' fields 0.
std::string acuity_fields_problem(const header& h) {
  const bool csf_fields = h.ct0 != 0 || h.alpha != 0 || h.e2 != 0;
  const bool linear_fields = h.mar_slope != 0 || h.mar_fovea_deg != 0 || h.mar_dead_zone_deg != 0;
  const bool piecewise_fields = std::any_of(std::begin(h.pivot_cpd), std::end(h.pivot_cpd), [](double v) { return v != 0; });
  if (h.version < 4 && (linear_fields || piecewise_fields))
    return fmt::format("version {} file with fields of version 4 set (file corrupted)", h.version);
  if (h.version < 4 && h.acuity_model != uint32_t(acuity_model::wang_csf))
    return fmt::format("version {} file naming acuity model {} (only version 4 has models other than csf)", h.version,
                       h.acuity_model);
  const auto model = acuity_model(h.acuity_model);
  if (std::string(acuity_model_name(model)) == "unknown") return fmt::format("unknown acuity model {}", h.acuity_model);
  if ((model != acuity_model::wang_csf && csf_fields) || (model != acuity_model::linear_mar && linear_fields) ||
      (model != acuity_model::piecewise_mar && piecewise_fields))
    return fmt::format("acuity model {} with another model's parameters set (file corrupted)", acuity_model_name(model));
  return {};
}

uint64_t align_up(uint64_t v) { return (v + section_alignment - 1) / section_alignment * section_alignment; }

uint64_t zigzag(int64_t v) { return (uint64_t(v) << 1) ^ uint64_t(v >> 63); }
int64_t unzigzag(uint64_t v) { return int64_t(v >> 1) ^ -int64_t(v & 1); }

// --- ref_left coding of one chunk of rows (see docs/pointset-format.md) -------------

constexpr uint8_t literal_marker = 255;

void encode_chunk(const uint32_t* rows, uint32_t width, uint32_t row_count, uint32_t k,
                  std::vector<uint8_t>& symbols) {
  symbols.clear();
  const std::vector<uint32_t> none(k, 0);
  for (uint32_t y = 0; y < row_count; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      const uint32_t* cur = rows + (size_t(y) * width + x) * k;
      const uint32_t* ref = x > 0 ? cur - k : (y > 0 ? cur - size_t(width) * k : none.data());
      for (uint32_t j = 0; j < k; ++j) {
        uint32_t pos = 0;
        while (pos < k && ref[pos] != cur[j]) ++pos;
        if (pos < k) {
          symbols.push_back(uint8_t(zigzag(int64_t(pos) - int64_t(j))));
        } else {
          symbols.push_back(literal_marker);
          uint64_t v = zigzag(int64_t(cur[j]) - int64_t(ref[0]));
          while (v >= 128) {
            symbols.push_back(uint8_t(v | 128));
            v >>= 7;
          }
          symbols.push_back(uint8_t(v));
        }
      }
    }
}

// Returns an empty string on success, else what is wrong.
std::string decode_chunk(const uint8_t* symbols, size_t size, uint32_t width, uint32_t row_count, uint32_t k,
                         uint64_t point_count, uint32_t* rows) {
  const std::vector<uint32_t> none(k, 0);
  size_t at = 0;
  for (uint32_t y = 0; y < row_count; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      uint32_t* cur = rows + (size_t(y) * width + x) * k;
      const uint32_t* ref = x > 0 ? cur - k : (y > 0 ? cur - size_t(width) * k : none.data());
      for (uint32_t j = 0; j < k; ++j) {
        if (at >= size) return "table stream ends early";
        const uint8_t s = symbols[at++];
        if (s != literal_marker) {
          const int64_t pos = int64_t(j) + unzigzag(s);
          if (pos < 0 || pos >= int64_t(k)) return "table stream refers outside the previous list";
          cur[j] = ref[pos];
          continue;
        }
        uint64_t v = 0;
        for (int shift = 0;; shift += 7) {
          if (at >= size || shift > 63) return "table stream has a broken literal";
          const uint8_t b = symbols[at++];
          v |= uint64_t(b & 127) << shift;
          if (!(b & 128)) break;
        }
        const int64_t value = int64_t(ref[0]) + unzigzag(v);
        if (value < 0 || uint64_t(value) >= point_count)
          return fmt::format("table index {} is out of range (set has {} points)", value, point_count);
        cur[j] = uint32_t(value);
      }
    }
  if (at != size) return "table stream has trailing bytes";
  return {};
}

// Directory of a ref_left_zstd table section: chunk count, then per chunk its
// byte offset (from the section start), compressed size, symbol-stream size and CRC.
// The header's table checksum covers the directory; each chunk carries its own.
struct chunk_entry {
  uint64_t offset, bytes, symbols;
  uint32_t crc, reserved;  // CRC-32C of the chunk's compressed bytes
};
static_assert(sizeof(chunk_entry) == 32);

header make_header(const pointset& set, uint32_t k, uint32_t group, const save_params& params) {
  header h{};
  std::memcpy(h.magic, magic, 8);
  // A set of the thesis's CSF is written as before acuity models (version 3 when nested,
  // else 2, byte for byte), any other model as version 4.
  const acuity_params& a = set.model.acuity;
  h.version = a.model != acuity_model::wang_csf || set.darts.sampler != point_sampler::poisson ? 4 : set.nested() ? 3 : 2;
  h.sampler = uint32_t(set.darts.sampler);
  h.header_bytes = pointset_header_bytes;
  h.width = uint32_t(set.model.display.width);
  h.height = uint32_t(set.model.display.height);
  h.viewing_distance = set.model.display.viewing_distance;
  h.scale = set.model.scale;
  h.acuity_model = uint32_t(set.model.acuity.model);
  h.fovea = uint32_t(set.darts.fovea);
  h.grid_spacing = set.darts.fovea == fovea_layout::grid ? set.darts.grid_spacing : 0.0;
  h.grid_points = set.stats.grid_points;
  switch (a.model) {
    case acuity_model::wang_csf: h.ct0 = a.ct0, h.alpha = a.alpha, h.e2 = a.e2; break;
    case acuity_model::linear_mar:
      h.mar_slope = a.mar_slope, h.mar_fovea_deg = a.mar_fovea_deg, h.mar_dead_zone_deg = a.mar_dead_zone_deg;
      break;
    case acuity_model::piecewise_mar: std::copy(std::begin(a.pivot_cpd), std::end(a.pivot_cpd), h.pivot_cpd); break;
  }
  h.seed = set.darts.seed;
  h.saturation_rejections = set.darts.saturation_rejections;
  h.free_area_probes = set.darts.free_area_probes;
  h.central_fraction = set.darts.central_fraction;
  h.phase1_points = set.stats.phase1_points;
  h.phase2_points = set.stats.phase2_points;
  h.darts_thrown = set.stats.darts_thrown;
  h.free_probes_accepted = set.stats.free_probes_accepted;
  h.free_fraction = set.stats.free_fraction;
  h.point_count = set.points.size();
  h.canvas_width = set.canvas_width();
  h.canvas_height = set.canvas_height();
  h.k = k;
  h.group = std::clamp<uint32_t>(group, 1, k);
  h.encoding = uint32_t(params.encoding);
  h.chunk_rows = params.chunk_rows;
  if (set.nested()) {
    if (set.level_scales.size() > max_levels || set.level.size() != set.points.size())
      throw std::invalid_argument("a nested set's levels do not match its points");
    h.level_count = uint32_t(set.level_scales.size());
    for (size_t l = 0; l < set.level_scales.size(); ++l) h.level_scales[l] = set.level_scales[l];
  }
  return h;
}

}  // namespace

const char* table_encoding_name(table_encoding e) {
  switch (e) {
    case table_encoding::raw: return "raw";
    case table_encoding::ref_left_zstd: return "ref-left-zstd";
    case table_encoding::cells: return "cells";
  }
  return "unknown";
}

bool parse_table_encoding(const std::string& name, table_encoding& out) {
  if (name == "raw") { out = table_encoding::raw; return true; }
  if (name == "ref-left-zstd") { out = table_encoding::ref_left_zstd; return true; }
  if (name == "cells") { out = table_encoding::cells; return true; }
  return false;
}

void save_pointset(const std::string& path, const pointset& set, uint32_t k, uint32_t group,
                   const table_row_source& rows, const save_params& params) {
  if (params.chunk_rows == 0) throw std::invalid_argument("chunk_rows must be positive");
  header h = make_header(set, k, group, params);
  temp_output out(path);

  h.points_offset = align_up(pointset_header_bytes);
  h.points_bytes = uint64_t(set.points.size()) * sizeof(point);
  h.points_crc = crc32c(set.points.data(), h.points_bytes);
  out.write_at(h.points_offset, set.points.data(), h.points_bytes);
  h.table_offset = align_up(h.points_offset + h.points_bytes);

  const uint32_t width = h.canvas_width, height = h.canvas_height;
  const uint32_t chunk_rows = params.chunk_rows;
  const uint32_t chunks = (height + chunk_rows - 1) / chunk_rows;
  std::vector<uint32_t> band;  // a table's rows, band by band (a cells file writes none)
  auto for_each_band = [&](auto&& use) {
    band.resize(size_t(chunk_rows) * width * k);
    for (uint32_t c = 0; c < chunks; ++c) {
      const uint32_t y0 = c * chunk_rows, y1 = std::min(height, y0 + chunk_rows);
      rows(y0, y1, band.data());
      use(c, y0, y1);
    }
  };

  if (params.encoding == table_encoding::cells) {
    h.table_offset = h.points_offset + h.points_bytes;  // the file ends with the points
    h.table_bytes = 0;  // nothing: the loader builds the cells from the points
  } else if (params.encoding == table_encoding::raw) {
    // The in-memory grouped-plane layout, byte for byte.
    knn_table t;
    t.width = width; t.height = height; t.k = k; t.group = h.group;
    t.entries.resize(t.pixel_count() * k);
    for_each_band([&](uint32_t, uint32_t y0, uint32_t y1) {
      const uint64_t first = uint64_t(y0) * width;
      for (uint64_t p = 0; p < uint64_t(y1 - y0) * width; ++p)
        for (uint32_t j = 0; j < k; ++j) t.entries[t.offset(first + p, j)] = band[p * k + j];
    });
    h.table_bytes = t.entries.size() * 4;
    h.table_crc = crc32c(t.entries.data(), h.table_bytes);
    out.write_at(h.table_offset, t.entries.data(), h.table_bytes);
  } else {
    // Directory first (its size is known), then each chunk as soon as it is coded.
    std::vector<chunk_entry> directory(chunks);
    const uint64_t directory_bytes = 8 + uint64_t(chunks) * sizeof(chunk_entry);
    uint64_t at = align_up(directory_bytes);
    std::vector<uint8_t> symbols, z;
    for_each_band([&](uint32_t c, uint32_t y0, uint32_t y1) {
      encode_chunk(band.data(), width, y1 - y0, k, symbols);
      z.resize(ZSTD_compressBound(symbols.size()));
      const size_t n = ZSTD_compress(z.data(), z.size(), symbols.data(), symbols.size(), params.zstd_level);
      if (ZSTD_isError(n)) throw file_error(fmt::format("{}: compression failed: {}", path, ZSTD_getErrorName(n)));
      directory[c] = {at, n, symbols.size(), crc32c(z.data(), n), 0};
      out.write_at(h.table_offset + at, z.data(), n);
      at += n;
    });
    h.table_bytes = at;
    std::vector<uint8_t> dir(directory_bytes);
    const uint64_t count = chunks;
    std::memcpy(dir.data(), &count, 8);
    std::memcpy(dir.data() + 8, directory.data(), chunks * sizeof(chunk_entry));
    h.table_crc = crc32c(dir.data(), dir.size());
    out.write_at(h.table_offset, dir.data(), dir.size());
  }
  if (set.nested()) {
    h.levels_offset = align_up(h.table_offset + h.table_bytes);
    h.levels_bytes = set.level.size();
    h.levels_crc = crc32c(set.level.data(), h.levels_bytes);
    out.write_at(h.levels_offset, set.level.data(), h.levels_bytes);
  }
  const std::vector<uint8_t> head = encode_header(h);
  out.write_at(0, head.data(), head.size());
  out.commit();
}

void save_pointset(const std::string& path, const pointset& set, const save_params& params) {
  const knn_table& t = set.table;
  if (params.encoding == table_encoding::cells || (t.k == 0 && set.cells.k != 0)) {
    save_params cells = params;
    cells.encoding = table_encoding::cells;
    const uint32_t k = t.k != 0 ? t.k : set.cells.k;
    return save_pointset(path, set, k, 1, [](uint32_t, uint32_t, uint32_t*) {}, cells);
  }
  save_pointset(path, set, t.k, t.group,
                [&](uint32_t y0, uint32_t y1, uint32_t* out) {
                  for (uint64_t p = uint64_t(y0) * t.width; p < uint64_t(y1) * t.width; ++p)
                    for (uint32_t j = 0; j < t.k; ++j) *out++ = t.entries[t.offset(p, j)];
                },
                params);
}

namespace {

pointset load_checked(const std::string& path, const load_params& params) {
  auto fail = [&](const std::string& why) { return file_error(fmt::format("{}: {}", path, why)); };
  if (const std::string why = input_file_problem(path); !why.empty()) throw fail(why);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw fail(fmt::format("cannot open: {}", std::strerror(errno)));
  in.seekg(0, std::ios::end);
  const uint64_t file_size = uint64_t(in.tellg());
  in.seekg(0);
  auto read_at = [&](uint64_t offset, void* dst, uint64_t bytes) {
    in.seekg(std::streamoff(offset));
    in.read(static_cast<char*>(dst), std::streamsize(bytes));
    if (!in) throw fail("read failed");
  };
  if (file_size < 8) throw fail(fmt::format("truncated: {} bytes, not a point-set file", file_size));
  uint8_t head[pointset_header_bytes] = {};
  read_at(0, head, std::min<uint64_t>(file_size, pointset_header_bytes));
  if (std::memcmp(head, magic, 8) != 0) throw fail("not a point-set file (wrong magic)");
  if (file_size < pointset_header_bytes)
    throw fail(fmt::format("truncated: {} bytes, the header alone needs {}", file_size, pointset_header_bytes));
  const header h = decode_header(head);
  if (h.version < 1 || h.version > pointset_format_version)
    throw fail(fmt::format("unknown format version {} (this build reads 1..{})", h.version, pointset_format_version));
  if (h.header_bytes != pointset_header_bytes) throw fail("unexpected header size");
  if (!checksum_matches(crc32c(head, header_crc_offset), h.header_crc)) throw fail("header checksum mismatch (file corrupted)");

  pointset set;
  set.model.display = {int(h.width), int(h.height), h.viewing_distance};
  set.model.scale = h.scale;
  if (const std::string why = acuity_fields_problem(h); !why.empty()) throw fail(why);
  if (h.version < 4 && (h.sampler != 0 || h.reserved4 != 0))
    throw fail(fmt::format("version {} file with fields of version 4 set (file corrupted)", h.version));
  if (h.sampler > uint32_t(point_sampler::log_polar) || h.reserved4 != 0)
    throw fail(fmt::format("unknown sampler {}", h.sampler));
  set.model.acuity = acuity_from_header(h);
  if (h.width > 65536 || h.height > 65536) throw fail("screen size out of range");
  if (const std::string why = validate(set.model); !why.empty()) throw fail("invalid model: " + why);
  if (h.canvas_width != 2 * h.width || h.canvas_height != 2 * h.height) throw fail("canvas is not twice the screen");
  if (h.k < 1 || h.k > max_knn) throw fail(fmt::format("k = {} outside 1..{}", h.k, max_knn));
  if (h.group < 1 || h.group > h.k) throw fail("k-NN group size out of range");
  if (h.encoding > uint32_t(table_encoding::cells)) throw fail(fmt::format("unknown table encoding {}", h.encoding));
  const bool cells = h.encoding == uint32_t(table_encoding::cells);
  if (cells && (h.table_bytes != 0 || h.group != 1)) throw fail("a cells set with a table section");
  if (h.chunk_rows == 0) throw fail("chunk_rows is zero");
  if (h.point_count < h.k || h.point_count >= (uint64_t(1) << 32)) throw fail("point count out of range");
  set.darts = {};
  set.darts.seed = h.seed, set.darts.saturation_rejections = h.saturation_rejections;
  set.darts.central_fraction = h.central_fraction, set.darts.free_area_probes = h.free_area_probes;
  set.darts.sampler = point_sampler(h.sampler);
  set.stats = {};
  set.stats.phase1_points = h.phase1_points, set.stats.phase2_points = h.phase2_points;
  set.stats.darts_thrown = h.darts_thrown, set.stats.free_fraction = h.free_fraction;
  set.stats.free_probes_accepted = h.free_probes_accepted;
  if (h.version == 1 && (h.fovea != 0 || h.grid_spacing != 0 || h.grid_points != 0))
    throw fail("version 1 file with fields of version 2 set (file corrupted)");
  if (h.sampler != uint32_t(point_sampler::poisson) && h.fovea != uint32_t(fovea_layout::darts))
    throw fail("a lattice sampler's set with a grid fovea (a grid fovea is for darts)");
  if (h.fovea == uint32_t(fovea_layout::grid)) {
    if (!valid_grid_spacing(h.grid_spacing))
      throw fail(fmt::format("grid spacing outside {}..{} pixels", min_grid_spacing, max_grid_spacing));
    set.darts.fovea = fovea_layout::grid;
    set.darts.grid_spacing = h.grid_spacing;
    set.stats.grid_points = h.grid_points;
  } else if (h.fovea != uint32_t(fovea_layout::darts) || h.grid_spacing != 0 || h.grid_points != 0) {
    throw fail(fmt::format("unknown fovea layout {}", h.fovea));
  }
  bool nested_fields = h.level_count != 0 || h.reserved != 0 || h.levels_offset != 0 || h.levels_bytes != 0 ||
                       h.levels_crc != 0;
  for (double v : h.level_scales) nested_fields = nested_fields || v != 0;
  if (h.version < 3 && nested_fields) throw fail(fmt::format("version {} file with fields of version 3 set (file corrupted)", h.version));
  // Version 3 is a nested set; version 4 may be (its level count says).
  if (h.version == 3 || (h.version >= 4 && nested_fields)) {
    if (h.level_count < 2 || h.level_count > max_levels || h.reserved != 0)
      throw fail(fmt::format("a nested set with {} levels (2..{})", h.level_count, max_levels));
    if (h.fovea != uint32_t(fovea_layout::darts)) throw fail("a nested set with a grid fovea");
    if (h.sampler != uint32_t(point_sampler::poisson)) throw fail("a nested set of a lattice sampler (nested sets are darts)");
    for (uint32_t l = 0; l < max_levels; ++l) {
      const double v = h.level_scales[l];
      if (l >= h.level_count) {
        if (v != 0) throw fail("level scales past the level count");
        continue;
      }
      if (!(v > 0 && std::isfinite(v)) || (l > 0 && !(v < h.level_scales[l - 1])))
        throw fail("level scales must be positive and decrease from the coarsest level");
      spacing_model m = set.model;
      m.scale = v;
      if (const std::string why = validate(m); !why.empty()) throw fail(fmt::format("level {}: invalid model: {}", l, why));
      set.level_scales.push_back(v);
    }
    if (h.level_scales[h.level_count - 1] != h.scale) throw fail("the set's scale is not its finest level's");
  }

  const uint64_t pixels = uint64_t(h.canvas_width) * h.canvas_height;
  if (h.points_bytes != h.point_count * sizeof(point)) throw fail("points section has the wrong size");
  if (set.nested() && (h.levels_bytes != h.point_count || h.levels_offset < h.table_offset + h.table_bytes ||
                       h.levels_offset > file_size || h.levels_bytes > file_size - h.levels_offset))
    throw fail(fmt::format("truncated or inconsistent: {} bytes, the levels section lies at {} (+{}) for {} points",
                           file_size, h.levels_offset, h.levels_bytes, h.point_count));
  // Sections inside the file, compared without sums that could wrap past 2^64: nothing
  // is allocated for a section before its size is known to fit in the file.
  if (h.points_offset < pointset_header_bytes || h.points_offset > file_size ||
      h.points_bytes > file_size - h.points_offset || h.table_offset < h.points_offset + h.points_bytes ||
      h.table_offset > file_size || h.table_bytes > file_size - h.table_offset)
    throw fail(fmt::format("truncated or inconsistent: {} bytes, the header places its sections at {} (+{}) and {} (+{})",
                           file_size, h.points_offset, h.points_bytes, h.table_offset, h.table_bytes));
  // The canvas the header declares, bounded by what the file holds: a compressed table
  // section expands at most max_table_expansion times (above a small floor).
  const uint64_t table_entry_bytes = pixels * h.k * 4;
  if (h.encoding == uint32_t(table_encoding::ref_left_zstd) &&
      table_entry_bytes > std::max(min_table_expansion_bound, h.table_bytes * max_table_expansion))
    throw fail(fmt::format("declares a {} x {} canvas with k = {}: {:.2f} GB of k-NN table from a {:.2f} MB table section, more "
                           "than {} times its size (refused)",
                           h.canvas_width, h.canvas_height, h.k, double(table_entry_bytes) / 1e9, double(h.table_bytes) / 1e6,
                           max_table_expansion));

  set.points.resize(h.point_count);
  read_at(h.points_offset, set.points.data(), h.points_bytes);
  if (!checksum_matches(crc32c(set.points.data(), h.points_bytes), h.points_crc)) throw fail("points checksum mismatch (file corrupted)");
  uint64_t grid_points = 0, hidden_darts = 0;
  const grid_test on_grid(set);
  uint64_t previous_code = 0;
  for (const point& p : set.points) {
    if (!(p.x >= 0 && p.x < float(h.canvas_width) && p.y >= 0 && p.y < float(h.canvas_height) && p.spacing > 0 &&
          std::isfinite(p.spacing)))
      throw fail("a point lies outside the canvas or has no finite spacing");
    const uint64_t code = morton_code(p.x, p.y);
    if (code < previous_code) throw fail(fmt::format("point {} is out of Morton order", &p - set.points.data()));
    previous_code = code;
    const bool grid = on_grid(p);
    grid_points += grid;
    if (!grid) hidden_darts += on_grid.in_grid_pixel(p.x, p.y);
  }
  if (hidden_darts > 0)
    throw fail(fmt::format("{} darts lie inside grid pixels, where they would be traced and never weigh (a grid set made "
                           "before fovgen stopped placing them): generate it again",
                           hidden_darts));
  if (grid_points != set.stats.grid_points)
    throw fail(fmt::format("{} points on grid pixels, the header says {}", grid_points, set.stats.grid_points));
  if (set.nested()) {
    set.level.resize(h.point_count);
    read_at(h.levels_offset, set.level.data(), h.levels_bytes);
    if (!checksum_matches(crc32c(set.level.data(), h.levels_bytes), h.levels_crc))
      throw fail("levels checksum mismatch (file corrupted)");
    std::vector<uint64_t> per_level(h.level_count, 0);
    for (uint8_t l : set.level) {
      if (l >= h.level_count) throw fail(fmt::format("a point of level {} in a set of {} levels", l, h.level_count));
      ++per_level[l];
    }
    // Every level's set must hold the k neighbours a reader asks for.
    if (per_level[0] < h.k) throw fail(fmt::format("the coarsest level holds {} points, fewer than k = {}", per_level[0], h.k));
  }
  if (cells) {  // the cells' shape is known even when they are not built
    set.cells.width = h.canvas_width;
    set.cells.height = h.canvas_height;
    set.cells.k = h.k;
    if (!params.table) return set;
    // The work and memory of the cells grow with their count, which the points' spacings
    // and the canvas fix: bounded by the points the file holds, as a table by its section.
    const uint64_t cells = count_knn_cells(set.points, h.canvas_width, h.canvas_height);
    if (cells > std::max(min_cells_bound, max_cells_per_point * h.point_count))
      throw fail(fmt::format("declares a {} x {} canvas whose k-NN cells ({}) exceed {} per point of its {} (refused)",
                             h.canvas_width, h.canvas_height, cells, max_cells_per_point, h.point_count));
    const auto start = std::chrono::steady_clock::now();
    try {
      knn_cells_params cp;
      cp.k = h.k;
      cp.max_candidates = std::max(min_cells_bound, max_candidates_per_point * h.k * h.point_count);
      set.cells = build_knn_cells(set.points, h.canvas_width, h.canvas_height, cp);
    } catch (const std::invalid_argument& e) {
      throw fail(e.what());
    }
    set.knn_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return set;
  }
  knn_table& t = set.table;  // its shape is known even when the entries are not loaded
  t.width = h.canvas_width;
  t.height = h.canvas_height;
  t.k = h.k;
  t.group = h.group;
  if (!params.table) return set;

  if (const std::string why = memory_problem(table_entry_bytes, fmt::format("the k-NN table ({} x {} pixels, k = {})",
                                                                            h.canvas_width, h.canvas_height, h.k));
      !why.empty())
    throw fail(why);
  if (h.encoding == uint32_t(table_encoding::raw)) {
    if (h.table_bytes != table_entry_bytes) throw fail("table section has the wrong size");
    t.entries.resize(pixels * h.k);
    read_at(h.table_offset, t.entries.data(), h.table_bytes);
    if (!checksum_matches(crc32c(t.entries.data(), h.table_bytes), h.table_crc)) throw fail("table checksum mismatch (file corrupted)");
    for (uint32_t v : t.entries)
      if (v >= h.point_count) throw fail(fmt::format("table index {} out of range (set has {} points)", v, h.point_count));
  } else {
    std::vector<uint8_t> section(h.table_bytes);
    read_at(h.table_offset, section.data(), h.table_bytes);
    const uint32_t chunks = (h.canvas_height + h.chunk_rows - 1) / h.chunk_rows;
    const uint64_t directory_bytes = 8 + uint64_t(chunks) * sizeof(chunk_entry);
    if (section.size() < directory_bytes) throw fail("table directory truncated");
    if (!checksum_matches(crc32c(section.data(), directory_bytes), h.table_crc))
      throw fail("table directory checksum mismatch (file corrupted)");
    uint64_t count = 0;
    std::memcpy(&count, section.data(), 8);
    if (count != chunks) throw fail("table directory is inconsistent");
    std::vector<chunk_entry> directory(chunks);
    std::memcpy(directory.data(), section.data() + 8, chunks * sizeof(chunk_entry));
    // Every chunk inside the section, intact, and declaring (in its own zstd frame) the size
    // the directory gives, before the table is allocated.
    for (uint32_t c = 0; c < chunks; ++c) {
      const chunk_entry& e = directory[c];
      const uint32_t y0 = c * h.chunk_rows, y1 = std::min(h.canvas_height, y0 + h.chunk_rows);
      const uint64_t max_symbols = uint64_t(y1 - y0) * h.canvas_width * h.k * 6;
      if (e.offset < directory_bytes || e.offset > section.size() || e.bytes > section.size() - e.offset ||
          e.symbols > max_symbols)
        throw fail(fmt::format("table chunk {} lies outside its section", c));
      if (!checksum_matches(crc32c(section.data() + e.offset, e.bytes), e.crc))
        throw fail(fmt::format("table chunk {} checksum mismatch (file corrupted)", c));
      if (ZSTD_getFrameContentSize(section.data() + e.offset, e.bytes) != e.symbols)
        throw fail(fmt::format("table chunk {} does not decompress to the size its directory gives", c));
    }
    t.group = params.group ? std::min(params.group, t.k) : std::min<uint32_t>(h.group, t.k);
    t.entries.resize(pixels * h.k);
    std::vector<std::string> errors(chunks);
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, chunks, 1), [&](const tbb::blocked_range<uint32_t>& r) {
      std::vector<uint8_t> symbols;
      std::vector<uint32_t> band;
      for (uint32_t c = r.begin(); c < r.end(); ++c) {
        const chunk_entry& e = directory[c];
        const uint32_t y0 = c * h.chunk_rows, y1 = std::min(h.canvas_height, y0 + h.chunk_rows);
        symbols.resize(e.symbols);
        const size_t n = ZSTD_decompress(symbols.data(), symbols.size(), section.data() + e.offset, e.bytes);
        if (ZSTD_isError(n) || n != e.symbols) {
          errors[c] = "table chunk does not decompress";
          continue;
        }
        band.resize(size_t(y1 - y0) * h.canvas_width * h.k);
        errors[c] = decode_chunk(symbols.data(), n, h.canvas_width, y1 - y0, h.k, h.point_count, band.data());
        if (!errors[c].empty()) continue;
        const uint64_t first = uint64_t(y0) * h.canvas_width;
        for (uint64_t p = 0; p < uint64_t(y1 - y0) * h.canvas_width; ++p)
          for (uint32_t j = 0; j < h.k; ++j) t.entries[t.offset(first + p, j)] = band[p * h.k + j];
      }
    });
    for (const std::string& e : errors)
      if (!e.empty()) throw fail(e);
  }
  if (params.group && params.group != t.group) t = regroup(t, params.group);
  set_knn_radii(t, set.points);
  return set;
}

}  // namespace

pointset load_pointset(const std::string& path, const load_params& params) {
  try {
    return load_checked(path, params);
  } catch (const std::bad_alloc&) {  // what the memory check did not foresee (a process limit): the file named
    throw file_error(fmt::format("{}: out of memory while loading it (a smaller set, or more memory)", path));
  }
}

}  // namespace fov
