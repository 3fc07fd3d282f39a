// fovbench's data: one configuration per row of results.csv, read back for --resume and
// for the plots and the report.
#pragma once

#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "../common/line_log.h"
#include "fov/labels.h"
#include "fov/pareto.h"

namespace fov {

// A row of results.csv: every knob and every figure, by column name. Numbers are kept as
// text exactly as written, so a round trip changes nothing.
// What a results.csv row measures: a foveated set, the full pixel grid at a foveated
// sampling rate (rays falling from spp at the gaze to a floor, fov::ray_falloff), or a
// baseline (a uniform set of a fraction of the pixels, or full resolution). Its label is the
// `kind` column.
enum class row_kind { foveated, uniform, full, falloff };
inline constexpr std::pair<const char*, row_kind> row_kind_labels[] = {
    {"foveated", row_kind::foveated}, {"uniform", row_kind::uniform}, {"full", row_kind::full}, {"falloff", row_kind::falloff}};
inline const char* row_kind_name(row_kind k) { return label_of(row_kind_labels, k); }

struct result_row {
  std::map<std::string, std::string> cells;
  std::string key() const;  // scene|gaze|kind|scale|pixel_fraction|method|k|ray_floor|spp|taa_frames|taa_pattern|density|adaptive_threshold|levels|reuse|reuse_settings: what --resume skips on
  double number(const std::string& column) const;  // NaN when empty or not a number
  // The kind column; std::logic_error for a row that result_row_problem would refuse.
  row_kind kind() const;
  const std::string& text(const std::string& column) const;
};

// The most frames of TAA a steady-state row (--taa-frames) may blend.
constexpr uint32_t max_taa_frames = 256;

// The columns, in file order (docs/speed-accuracy.md explains each).
const std::vector<std::string>& result_columns();

// The reuse rows' columns (every column named reuse...): none of them in a results.csv from
// before reuse rows.
const std::set<std::string>& reuse_result_columns();

// Why a row is not one fovbench writes, or "" when it is: the rule every row passes, read
// back (--resume) or about to be written. Text cells: kind foveated, uniform, full or falloff, a
// method its kind has, error_profile numbers >= 0 joined by ';'. Numbers (empty where a
// column does not apply): PSNR >= 0 or inf; SSIM in [-1, 1]; FLIP, geometry shares and
// pixel_fraction in [0, 1]; times, counts, errors and flicker finite and >= 0; frame and
// full-frame times, speedups, scale (<= 10), k (<= 32), spp and frames > 0.
std::string result_row_problem(const result_row& row);

// A row's integrator as titles say it: "direct" (also for rows from before the integrator
// columns, which were all direct) or "path, N bounces".
std::string integrator_text(const result_row& row);

// The largest results.csv read back (about 300,000 rows).
constexpr uintmax_t max_results_bytes = uintmax_t(256) << 20;

// Reads results.csv; throws std::runtime_error "FILE:LINE: reason" when the file is not a
// regular file of at most max_results_bytes, the header is not result_columns(), a row has
// the wrong number of cells, a numeric cell is not a number fovbench writes (finite, inf,
// or empty; never nan), a row fails result_row_problem, or a row repeats an earlier row's
// configuration (key()). A torn last line (no newline: an interrupted write) is ignored;
// CRLF line ends read as LF. With older_ok (for reading only: fovbench summary), a results.csv
// from before the reuse columns (no reuse rows), before rays_cast, before the integrator columns (integrator, bounces: its rows direct), before that
// without the acuity model's (acuity, sampler), before the density columns (density, adaptive_threshold, levels, level_rays), or also
// before the steady-state ones (taa_frames, taa_pattern), reads too, its rows single frames of
// fixed density; --resume refuses one, since its new rows would have more columns.
std::vector<result_row> read_results(const std::string& path, bool older_ok = false);

// Appends rows to results.csv, creating it with the header when missing. Each row is
// flushed and fsync'ed before the call returns, so an interrupted sweep loses at most
// the configuration it was measuring.
class results_writer {
 public:
  explicit results_writer(const std::string& path);
  void append(const result_row& row);

 private:
  line_log log_;
};

// CSV cell quoting (RFC 4180) for text that may hold commas or quotes.
std::string csv_cell(const std::string& text);

}  // namespace fov
