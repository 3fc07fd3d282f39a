// The .fovset file: one point set with its k-NN table (docs/pointset-format.md).
#pragma once

#include <functional>
#include <stdexcept>
#include <string>

#include "fov/files.h"
#include "fov/pointset.h"

namespace fov {

// 2 adds the fovea layout (a pixel grid in the fovea), 3 nested sets (levels), 4 acuity
// models other than the thesis's CSF; every earlier version still loads. Sets of the CSF are
// written as version 2 (one level) or 3 (nested), byte for byte as before.
inline constexpr uint32_t pointset_format_version = 4;
inline constexpr uint32_t pointset_header_bytes = 512;

// How the k-NN table is stored on disk.
enum class table_encoding : uint32_t {
  raw = 0,            // fixed-width little-endian uint32 in the grouped-plane layout: mmap and use
  ref_left_zstd = 1,  // ranks coded against the left pixel's list, zstd-compressed in row chunks
  cells = 2,          // no table on disk: the loader builds k-NN cells (knn_cells.h) from the points,
                      // so file and memory grow with the points, not with the canvas's pixels
};
const char* table_encoding_name(table_encoding encoding);
bool parse_table_encoding(const std::string& name, table_encoding& out);

struct save_params {
  table_encoding encoding = table_encoding::ref_left_zstd;
  int zstd_level = 3;
  uint32_t chunk_rows = 64;  // rows per independently decodable chunk
};

struct load_params {
  bool table = true;   // false: header and points only (no table read, no cells built)
  uint32_t group = 0;  // layout wanted in memory; 0 = as stored (ref_left_zstd: 4)
};

// Fills rows [y0, y1) of the table pixel-major, k ranks per pixel (see knn_builder::rows).
using table_row_source = std::function<void(uint32_t y0, uint32_t y1, uint32_t* out)>;

// Files hold only what the parameters and seed determine (no timings, no host
// names), so the same flags and seed give a byte-identical file.

// Writes `set` (its points, model and dart statistics) with a table taken row band by row
// band from `rows`, so the whole table never needs to be in memory. Writes to a
// temporary file beside `path` and renames it into place; on any error nothing
// is left at `path`.
void save_pointset(const std::string& path, const pointset& set, uint32_t k, uint32_t group,
                   const table_row_source& rows, const save_params& params = {});

// Writes a set whose table is in memory, or (with encoding cells, or a set holding cells and
// no table) the set's points for its cells' k.
void save_pointset(const std::string& path, const pointset& set, const save_params& params = {});

// A compressed table section may expand to at most this many times its size (real sets:
// 8-15x, docs/pointset-format.md; zstd itself allows about 32,000x), except that tables of
// up to min_table_expansion_bound bytes are always allowed: a 2 MB file declaring an 8 GB
// table is refused from its header, before anything is allocated.
constexpr uint64_t max_table_expansion = 1024;
constexpr uint64_t min_table_expansion_bound = uint64_t(64) << 20;

// A cells file's k-NN cells (their count fixed by the canvas and the points' spacings) may
// number at most this many per point, except that up to min_cells_bound are always
// allowed: a file of a few points cannot make its loader build a canvas's worth of cells.
// (Generated sets keep a few cells per point; a sparse uniform set up to 64.)
constexpr uint64_t max_cells_per_point = 256;
constexpr uint64_t min_cells_bound = uint64_t(1) << 20;
// And they may keep at most this many candidates per point and neighbour (generated sets
// keep 2-5; docs/benchmarks.md), above the same floor: points gathered far from most of a
// declared canvas would otherwise make every empty cell keep them all.
constexpr uint64_t max_candidates_per_point = 16;

// Reads and verifies a file (with table = false, table.entries stays empty but its shape is set): magic, version, checksums, sizes, parameter ranges,
// the canvas against the table section (max_table_expansion), point coordinates and every
// table index. Throws file_error naming the file, for running out of memory too.
pointset load_pointset(const std::string& path, const load_params& params = {});


}  // namespace fov
