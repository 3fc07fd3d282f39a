// fovbench's data handling: the Pareto front, results.csv round trips, torn lines, the
// reference cache, and what its options accept.
#include <algorithm>
#include <cmath>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <tuple>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "bench.h"
#include "fov/knn_table.h"
#include "fov/flicker.h"
#include "fov/dart_throwing.h"
#include "cli.h"
#include "plot.h"
#include "report.h"
#include "summary.h"
#include "yardstick.h"
#include "sweep.h"

namespace fov {
namespace {


// A row as fovbench writes it (every cell within its column's range).
result_row sample_row(const std::string& method, const std::string& spp) {
  result_row r;
  for (const std::string& c : result_columns()) {
    const bool share = c.rfind("flip", 0) == 0 || c.rfind("foveated_flip", 0) == 0 || c.rfind("noise_floor_flip", 0) == 0 ||
                       c.rfind("geometry_", 0) == 0 || c == "pixel_fraction";
    r.cells[c] = c.rfind("ssim", 0) == 0 ? "0.5" : share ? "0.25" : "1.5";
  }
  r.cells["kind"] = "foveated";
  r.cells["scene"] = "env:/tmp/a, \"quoted\" name.exr";  // commas and quotes survive
  r.cells["method"] = method;
  r.cells["spp"] = spp;
  r.cells["psnr"] = "inf";
  r.cells["flicker"] = "";
  r.cells["error_profile"] = "0.1;0.2;0.05";
  r.cells["taa_frames"] = r.cells["taa_pattern"] = "";  // a single frame
  r.cells["density"] = "fixed";
  r.cells["acuity"] = "csf";
  r.cells["sampler"] = "poisson";
  r.cells["adaptive_threshold"] = r.cells["levels"] = r.cells["level_rays"] = "";
  r.cells["integrator"] = "direct", r.cells["bounces"] = "";
  r.cells["rays_cast"] = "3";  // at least the camera rays (1.5 here)
  for (const std::string& c : reuse_result_columns()) r.cells[c] = "";  // not a reuse row
  return r;
}

// The reuse columns (issue 28).
const std::set<std::string>& reuse_columns = reuse_result_columns();

// A reuse row as fovbench writes it.
result_row reuse_row() {
  result_row r = sample_row("shepard", "4");
  r.cells["ray_floor"] = "";
  r.cells["reuse"] = "temporal", r.cells["reuse_settings"] = "fovea=0 threshold=0.2 max_age=16 budget=0 view=0 edges=strict distance=world";
  r.cells["reuse_kept"] = "0.6", r.cells["reuse_rays_ratio"] = "0.7", r.cells["reuse_rays_cast_ratio"] = "0.5";
  r.cells["reuse_trace_ratio"] = "0.9", r.cells["reuse_trace_ratio_lo"] = "0.8", r.cells["reuse_trace_ratio_hi"] = "1.2";
  r.cells["reuse_video_jod_traced"] = "8.5", r.cells["reuse_flicker_traced"] = "0.04";
  return r;
}

TEST(ResultsCsv, RoundTripsEveryCellAndKey) {
  const std::string path = ::testing::TempDir() + "/results-roundtrip.csv";
  std::filesystem::remove(path);
  {
    results_writer w(path);
    w.append(sample_row("nn", "1"));
    w.append(sample_row("rbf", "32"));
  }
  const std::vector<result_row> rows = read_results(path);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].cells, sample_row("nn", "1").cells);
  EXPECT_EQ(rows[1].key(), sample_row("rbf", "32").key());
  EXPECT_NE(rows[0].key(), rows[1].key());
  EXPECT_TRUE(std::isinf(rows[0].number("psnr")));
  EXPECT_TRUE(std::isnan(rows[0].number("flicker")));
  EXPECT_DOUBLE_EQ(rows[0].number("frame_ms"), 1.5);
}

TEST(ResultsCsv, ATornLastLineIsIgnoredAndCutOnTheNextWrite) {
  const std::string path = ::testing::TempDir() + "/results-torn.csv";
  std::filesystem::remove(path);
  {
    results_writer w(path);
    w.append(sample_row("nn", "1"));
  }
  std::ofstream(path, std::ios::app) << "builtin,centre,48,40,1.00,shep";  // interrupted mid-row
  EXPECT_EQ(read_results(path).size(), 1u);
  {
    results_writer w(path);  // resuming: the torn bytes go, the new row follows the last whole one
    w.append(sample_row("shepard", "4"));
  }
  const std::vector<result_row> rows = read_results(path);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1].text("method"), "shepard");
}

TEST(ResultsCsv, AForeignFileIsRefusedWithItsLine) {
  const std::string path = ::testing::TempDir() + "/results-foreign.csv";
  std::ofstream(path) << "a,b,c\n1,2,3\n";
  try {
    read_results(path);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), path + ":1: not a results.csv of this fovbench (columns differ); use another -o");
  }
}

// What --resume must not take in: a duplicated configuration, a nan fovbench never writes
// (an empty cell stands for none), a number beyond a double; a CRLF copy reads as the file.
TEST(ResultsCsv, CorruptRowsAreRefusedAndCrlfIsRead) {
  const std::string path = ::testing::TempDir() + "/results-corrupt.csv";
  std::filesystem::remove(path);
  {
    results_writer w(path);
    w.append(sample_row("nn", "1"));
    w.append(sample_row("rbf", "32"));
  }
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  ASSERT_EQ(lines.size(), 3u);
  auto write = [&](const std::vector<std::string>& ls, const std::string& end) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    for (const std::string& l : ls) out << l << end;
  };
  auto refused = [&](const std::string& what) {
    try {
      read_results(path);
      ADD_FAILURE() << what << ": accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()).rfind(path + ":", 0), 0u) << e.what();
      return std::string(e.what());
    }
    return std::string();
  };
  write({lines[0], lines[1], lines[2], lines[1]}, "\n");
  EXPECT_NE(refused("duplicate").find(":4: the same configuration as line 2"), std::string::npos);
  // A row as text, written past the writer (which refuses rows it would not read back).
  auto line_of = [](const result_row& r) {
    std::string line;
    for (const std::string& c : result_columns()) line += (line.empty() ? "" : ",") + csv_cell(r.text(c));
    return line;
  };
  for (const char* bad : {"nan", "1e999", "12abc"}) {
    result_row r = sample_row("nn", "1");
    r.cells["frame_ms"] = bad;
    EXPECT_THROW(results_writer(path).append(r), std::logic_error) << bad;
    write({lines[0], line_of(r)}, "\n");
    EXPECT_NE(refused(bad).find(":2: frame_ms '" + std::string(bad) + "' is not a number fovbench writes"), std::string::npos);
  }
  // Numbers fovbench never writes, and text cells it never writes: refused by the rule new
  // rows pass, with the cell named (issue 30: -inf PSNR, a zero frame time, kind bogus,
  // scale 1e308, an error profile that is not numbers).
  for (const auto& [column, bad, why] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"psnr", "-inf", "psnr -inf lies outside [0, inf]"},
           {"frame_ms", "0", "frame_ms 0 lies outside (0"},
           {"frame_ms", "-3", "frame_ms -3 lies outside (0"},
           {"kind", "bogus", "kind 'bogus' is not foveated, uniform, full or falloff"},
           {"acuity", "wang_csf", "acuity 'wang_csf' is not csf, linear-mar or piecewise-mar"},
           {"sampler", "grid", "sampler 'grid' is not poisson, polar or log-polar"},
           {"integrator", "whitted", "integrator 'whitted' is not direct or path"},
           {"bounces", "2", "a path row names its bounces; no other row does"},
           {"rays_cast", "1", "rays_cast '1' is not a whole number of at least the row's rays"},
           {"rays_cast", "4.5", "rays_cast '4.5' is not a whole number of at least the row's rays"},
           {"scale", "1e308", "scale 1e308 lies outside (0, 10]"},
           {"ssim", "1.5", "ssim 1.5 lies outside [-1, 1]"},
           {"method", "full", "method 'full' is not one a foveated row has"},
           {"kind", "falloff", "method 'nn' is not one a falloff row has"},
           {"error_profile", "abc;def", "error_profile 'abc;def' is not numbers >= 0 joined by ';'"}}) {
    result_row r = sample_row("nn", "1");
    r.cells[column] = bad;
    EXPECT_NE(result_row_problem(r), "") << column << " " << bad;
    write({lines[0], line_of(r)}, "\n");
    const std::string e = refused(column + " " + bad);
    EXPECT_NE(e.find(":2: " + why), std::string::npos) << e;
  }
  EXPECT_EQ(result_row_problem(sample_row("nn", "1")), "");
  // A steady-state row names a whole number of frames 2..max_taa_frames and a pattern; a
  // single frame neither.
  result_row steady = sample_row("nn", "1");
  steady.cells["taa_frames"] = "16", steady.cells["taa_pattern"] = "mirror";
  EXPECT_EQ(result_row_problem(steady), "");
  EXPECT_NE(steady.key(), sample_row("nn", "1").key());
  for (const auto& [frames, pattern, why] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"1", "mirror", "taa_frames '1' is not a whole number in 2..256"},
           {"2.5", "mirror", "taa_frames '2.5' is not a whole number in 2..256"},
           {"257", "reseed", "taa_frames '257' is not a whole number in 2..256"},
           {"x", "reseed", "taa_frames 'x' is not a whole number in 2..256"},
           {"4", "swirl", "taa_pattern 'swirl' is not reseed, mirror or fixed"},
           {"4", "", "taa_pattern '' is not reseed, mirror or fixed"},
           {"", "mirror", "taa_pattern 'mirror' without taa_frames"}}) {
    result_row r = sample_row("nn", "1");
    r.cells["taa_frames"] = frames, r.cells["taa_pattern"] = pattern;
    EXPECT_EQ(result_row_problem(r), why) << frames << " " << pattern;
  }
  // The integrator (issue 29): a path row names its bounces, a whole number 0..max_bounces.
  result_row traced = sample_row("nn", "1");
  traced.cells["integrator"] = "path", traced.cells["bounces"] = "3";
  EXPECT_EQ(result_row_problem(traced), "");
  EXPECT_EQ(integrator_text(traced), "path, 3 bounces");
  EXPECT_EQ(integrator_text(sample_row("nn", "1")), "direct");
  for (const std::string bounces : {"", "65", "1.5", "-1", "x"}) {
    traced.cells["bounces"] = bounces;
    EXPECT_NE(result_row_problem(traced), "") << bounces;
  }
  // Density (issue 26): a foveated row's fixed or adaptive; an adaptive row names its
  // threshold and levels (increasing scales) and no scale, its rays per level counts.
  result_row adaptive = sample_row("nn", "1");
  adaptive.cells["density"] = "adaptive", adaptive.cells["adaptive_threshold"] = "0.5";
  adaptive.cells["levels"] = "1.00;2.00", adaptive.cells["level_rays"] = "4607;0", adaptive.cells["scale"] = "";
  EXPECT_EQ(result_row_problem(adaptive), "");
  result_row other = adaptive;
  other.cells["adaptive_threshold"] = "1";
  EXPECT_NE(other.key(), adaptive.key());
  EXPECT_NE(adaptive.key(), sample_row("nn", "1").key());
  const std::string pairing = "an adaptive row names its threshold and levels and no scale; no other row does";
  for (const auto& [column, bad, why] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"density", "sparse", "density 'sparse' is not fixed or adaptive"},
           {"kind", "uniform", "density 'adaptive' on a uniform row (only foveated rows have one)"},
           {"scale", "1.00", pairing},
           {"adaptive_threshold", "", pairing},
           {"levels", "", pairing},
           {"adaptive_threshold", "2000", "adaptive_threshold 2000 lies outside [0, 1000]"},
           {"levels", "2.00;1.00", "levels '2.00;1.00' is not 2..8 increasing positive scales"},
           {"levels", "1.00", "levels '1.00' is not 2..8 increasing positive scales"},
           {"levels", "1.00;x", "levels '1.00;x' is not scales joined by ';'"},
           {"level_rays", "5;-1", "level_rays '5;-1' is not numbers >= 0 joined by ';'"}}) {
    result_row r = adaptive;
    r.cells[column] = bad;
    if (column == "kind") r.cells["method"] = "nn";
    EXPECT_EQ(result_row_problem(r), why) << column << " " << bad;
  }
  result_row fixed_with_threshold = sample_row("nn", "1");
  fixed_with_threshold.cells["adaptive_threshold"] = "0.5";
  EXPECT_EQ(result_row_problem(fixed_with_threshold), pairing);
  // Reuse (issue 28): a fixed set's single frame without a ray floor, its settings part of its
  // key, and what it measured on it alone.
  const result_row reused = reuse_row();
  ASSERT_EQ(reuse_columns.size(), 10u);  // reuse, its settings and what it measured
  EXPECT_EQ(result_row_problem(reused), "");
  result_row fixed_twin = reused;
  for (const std::string& c : reuse_columns) fixed_twin.cells[c] = "";
  EXPECT_EQ(result_row_problem(fixed_twin), "");
  EXPECT_NE(fixed_twin.key(), reused.key());
  result_row other_settings = reused;
  other_settings.cells["reuse_settings"] = "fovea=5 threshold=0.2 max_age=16 budget=0 view=0 edges=strict distance=world";
  EXPECT_NE(other_settings.key(), reused.key());
  const std::string single = "a reuse row is a fixed set's single frame without a ray floor";
  for (const auto& [column, bad, why] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"reuse", "eyes", "reuse 'eyes' is not temporal"},
           {"density", "adaptive", single},
           {"taa_frames", "16", single},
           {"ray_floor", "1", single},
           {"reuse_settings", "", "reuse_settings is given on a reuse row and on no other"},
           {"reuse_trace_ratio_hi", "", "reuse_trace_ratio_hi is given on a reuse row and on no other"},
           {"reuse_kept", "1.5", "reuse_kept 1.5 lies outside [0, 1]"},
           {"reuse_rays_ratio", "0", "reuse_rays_ratio 0 lies outside (0, inf)"},
           {"reuse_trace_ratio", "1.3", "reuse_trace_ratio does not lie within its _lo and _hi"},
           {"reuse_video_jod_traced", "11", "reuse_video_jod_traced 11 lies outside [-1.79769e+308, 10]"}}) {
    result_row r = reused;
    r.cells[column] = bad;
    if (column == "density") r.cells["adaptive_threshold"] = "0.5", r.cells["levels"] = "1.00;2.00", r.cells["scale"] = "";
    if (column == "taa_frames") r.cells["taa_pattern"] = "mirror";
    EXPECT_EQ(result_row_problem(r), why) << column << " " << bad;
  }
  for (const std::string& c : reuse_columns) {  // none of it on a row without reuse
    if (c == "reuse") continue;
    result_row r = sample_row("nn", "1");
    r.cells[c] = c == "reuse_settings" ? "fovea=0" : "0.5";
    EXPECT_NE(result_row_problem(r), "") << c;
  }
  write(lines, "\r\n");
  EXPECT_EQ(read_results(path).size(), 2u);
}

// A reference's sidecar is read through the one checked read: a FIFO does not block, a
// directory or a value of the wrong type is refused in one line naming the file and key
// (issue 30: they hung, or printed a raw json or filebuf message).
TEST(ReferenceMeta, SpecialFilesAndWrongTypesAreRefusedNamingTheFile) {
  const std::string dir = ::testing::TempDir() + "/refmeta";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir + "/as-dir.json");
  ASSERT_EQ(mkfifo((dir + "/fifo.json").c_str(), 0600), 0);
  std::ofstream(dir + "/type.json") << R"({"scene": "builtin", "spp": 4, "seed": 1, "ms": 2.5, "rays": 9, "sampler": "sobol", "render_settings": 3})";
  std::ofstream(dir + "/good.json") << R"({"scene": "builtin", "spp": 4, "seed": 1, "ms": 2.5, "rays": 9, "sampler": "sobol", "render_settings": "x"})";
  std::ofstream(dir + "/neg.json") << R"({"scene": "builtin", "spp": 4, "seed": 1, "ms": -1, "rays": 9, "sampler": "sobol", "render_settings": "x"})";
  for (const auto& [name, why] : std::vector<std::pair<std::string, std::string>>{
           {"as-dir.json", "is a directory"}, {"fifo.json", "not a regular file"},
           {"type.json", "\"render_settings\" must be a string"}, {"neg.json", "\"ms\" must be finite and >= 0"}}) {
    try {
      read_reference_meta(dir + "/" + name);
      ADD_FAILURE() << name << ": accepted";
    } catch (const std::runtime_error& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind(dir + "/" + name + ": ", 0), 0u) << m;
      EXPECT_NE(m.find(why), std::string::npos) << m;
    }
  }
  const reference_meta m = read_reference_meta(dir + "/good.json");
  EXPECT_EQ(m.spp, 4u);
  EXPECT_DOUBLE_EQ(m.ms, 2.5);
}

// --resume appends to results.csv: through a symbolic link it is refused, as a write is,
// and the link's target is left as it was.
TEST(ResultsCsv, AppendsRefuseSymbolicLinks) {
  const std::string dir = ::testing::TempDir() + "/results-link";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/elsewhere.csv") << "precious\n";
  std::filesystem::create_symlink(dir + "/elsewhere.csv", dir + "/results.csv");
  try {
    results_writer w(dir + "/results.csv");
    ADD_FAILURE() << "appended through a link";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("a symbolic link"), std::string::npos) << e.what();
  }
  std::ifstream in(dir + "/elsewhere.csv");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "precious\n");
  // A FIFO is refused at once (no reader: never waited on), as every input is.
  ASSERT_EQ(mkfifo((dir + "/fifo.csv").c_str(), 0600), 0);
  try {
    results_writer w(dir + "/fifo.csv");
    ADD_FAILURE() << "appended to a FIFO";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), dir + "/fifo.csv: not a regular file (a FIFO, device or socket): refused");
  }
}

// A reference is traced once per scene, size and spp, and read back from its files after
// that: a new cache over the same folder returns the same image and timing, tracing nothing.
TEST(ReferenceCache, TracesOnceAndReadsTheFilesAfter) {
  namespace fs = std::filesystem;
  const std::string dir = ::testing::TempDir() + "/fovbench-refs";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::shared_ptr<const scene> scn = load_scene("builtin");
  render_params p;
  p.device = reconstruct_device::cpp;
  renderer r(scn, p);
  const display_geometry d{40, 30, 1.0};
  reference_cache first(dir, "builtin", d);
  const reference_frame& a = first.get(r, p, 2, 7);
  EXPECT_FALSE(a.from_disk);
  EXPECT_EQ(a.rays, 40u * 30u * 2u);
  EXPECT_GT(a.ms, 0.0);
  EXPECT_TRUE(fs::exists(first.file_base(2, 7) + ".exr"));
  EXPECT_EQ(&first.get(r, p, 2, 7), &a);  // kept in memory too
  const auto written = fs::last_write_time(first.file_base(2, 7) + ".exr");
  reference_cache second(dir, "builtin", d);
  const reference_frame& b = second.get(r, p, 2, 7);
  EXPECT_TRUE(b.from_disk);
  EXPECT_EQ(b.ms, a.ms);
  EXPECT_EQ(b.rays, a.rays);
  EXPECT_EQ(b.image.rgb, a.image.rgb);  // EXR keeps linear float RGB
  EXPECT_EQ(b.image.depth, a.image.depth);  // and the depth (geometry coverage needs it)
  EXPECT_EQ(fs::last_write_time(first.file_base(2, 7) + ".exr"), written);
  const reference_frame& other_seed = second.get(r, p, 2, 8);  // another seed: traced, and different
  EXPECT_FALSE(other_seed.from_disk);
  EXPECT_NE(other_seed.image.rgb, a.image.rgb);
  EXPECT_FALSE(second.get(r, p, 1, 7).from_disk);  // another spp: traced
  // A cache made with other settings is refused, not silently reused.
  render_params renka = p;
  renka.reconstruct.renka = true;
  reference_cache third(dir, "builtin", d);
  EXPECT_THROW(third.get(r, renka, 2, 7), std::runtime_error);
}



// A converged temporal path is traced once and read back by every later cache over the same
// folder, frame for frame; a frame whose sidecar names another path is refused.
TEST(ReferenceCache, CachesTheConvergedPath) {
  namespace fs = std::filesystem;
  const std::string dir = ::testing::TempDir() + "/fovbench-path-refs";
  fs::remove_all(dir);
  fs::create_directories(dir);
  render_params p;
  p.device = reconstruct_device::cpp;
  renderer r(load_scene("builtin"), p);
  auto set = std::make_shared<pointset>();
  set->model.display = {40, 30, 1.0};
  set->points = throw_darts(set->model, {});
  knn_params kp;
  kp.k = 8;
  set->table = build_knn_table(set->points, set->canvas_width(), set->canvas_height(), kp);
  r.use_pointset(set);
  flicker_params f;
  f.frames = 3;
  f.yaw_deg_per_frame = 2;
  reference_cache first(dir, "builtin", set->model.display);
  bool from_disk = true;
  const std::vector<frame> traced = first.path(r, p, 2, 7, f, {}, &from_disk);
  EXPECT_FALSE(from_disk);
  ASSERT_EQ(traced.size(), 3u);
  EXPECT_NE(traced[0].rgb, traced[2].rgb);  // the camera turned
  const std::vector<frame> direct = converged_path(r, p, 2, 7, f);
  for (size_t n = 0; n < 3; ++n) EXPECT_EQ(traced[n].rgb, direct[n].rgb) << n;
  reference_cache second(dir, "builtin", set->model.display);
  const std::vector<frame> read = second.path(r, p, 2, 7, f, {}, &from_disk);
  EXPECT_TRUE(from_disk);
  ASSERT_EQ(read.size(), 3u);
  for (size_t n = 0; n < 3; ++n) EXPECT_EQ(read[n].rgb, traced[n].rgb) << n;  // EXR keeps float RGB
  second.path(r, p, 2, 8, f, {}, &from_disk);  // another seed: traced
  EXPECT_FALSE(from_disk);
  // Another path with the same files' names is refused: the sidecars name frames and yaw.
  fs::copy_file(second.path_file_base(2, 7, f, 1) + ".json", second.path_file_base(2, 7, f, 0) + ".json",
                fs::copy_options::overwrite_existing);
  try {
    second.path(r, p, 2, 7, f);
    ADD_FAILURE() << "a sidecar of frame 1 accepted as frame 0";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(second.path_file_base(2, 7, f, 0) + ".json: not frame 0 of this path"), std::string::npos)
        << e.what();
  }
}

TEST(BenchOptions, AreCheckedBeforeAnythingRuns) {
  bench_options o;
  o.scenes = {"builtin"};
  o.methods = {method::shepard};
  EXPECT_NO_THROW(check_bench_options(o));
  bench_options bad = o;
  bad.render.reconstruct.shape = -1;
  EXPECT_THROW(check_bench_options(bad), usage_error);
  bad = o;
  bad.render.view.hfov_deg = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(check_bench_options(bad), usage_error);
  bad = o;
  bad.spps = {0};
  EXPECT_THROW(check_bench_options(bad), usage_error);
  bad = o;
  bad.reference_spp = 4;  // not better than the --spp 4 it would measure
  EXPECT_THROW(check_bench_options(bad), usage_error);
  bad = o;
  bad.uniform_fractions = {0.3};
  EXPECT_THROW(check_bench_options(bad), usage_error);
  bad = o;
  bad.spread_limit = 0;
  EXPECT_THROW(check_bench_options(bad), usage_error);
  bad = o;
  bad.scenes = {"/nonexistent.gltf"};
  EXPECT_THROW(check_bench_options(bad), std::runtime_error);
  // Adaptive rows (issue 26): thresholds and levels come together, levels increasing within
  // 0.5..10, thresholds within 0..max_adaptive_threshold, a darts fovea.
  bad = o;
  bad.adaptive_thresholds = {0.5};
  EXPECT_THROW(check_bench_options(bad), usage_error);
  bad.levels = {1.0, 2.0};
  EXPECT_NO_THROW(check_bench_options(bad));
  bad.adaptive_thresholds.clear();
  EXPECT_THROW(check_bench_options(bad), usage_error);
  for (const std::vector<double>& levels : std::vector<std::vector<double>>{{2.0, 1.0}, {1.0}, {0.4, 1.0}, {1.0, 11.0}}) {
    bad = o;
    bad.adaptive_thresholds = {0.5}, bad.levels = levels;
    EXPECT_THROW(check_bench_options(bad), usage_error) << levels[0];
  }
  for (double t : {-1.0, 1001.0, std::numeric_limits<double>::quiet_NaN()}) {
    bad = o;
    bad.levels = {1.0, 2.0}, bad.adaptive_thresholds = {t};
    EXPECT_THROW(check_bench_options(bad), usage_error) << t;
  }
  bad = o;
  bad.levels = {1.0, 2.0}, bad.adaptive_thresholds = {1}, bad.fovea = fovea_layout::grid;
  EXPECT_THROW(check_bench_options(bad), usage_error);
  // Reuse rows (issue 28): temporal only, along a temporal path, on sparse sets, within range.
  bad = o;
  bad.reuse.mode = reuse_mode::temporal;
  EXPECT_THROW(check_bench_options(bad), usage_error);  // no temporal path
  bad.temporal_frames = 4;
  EXPECT_NO_THROW(check_bench_options(bad));
  bad.reuse.threshold = 2;
  EXPECT_THROW(check_bench_options(bad), usage_error);
  bad.reuse.threshold = 0.2, bad.no_sparse = true, bad.ray_floors = {1}, bad.spps = {4};
  EXPECT_THROW(check_bench_options(bad), usage_error);
  bad = o;
  bad.reuse.mode = reuse_mode::eyes, bad.temporal_frames = 4;
  EXPECT_THROW(check_bench_options(bad), usage_error);
  render_params renka = o.render;
  renka.reconstruct.renka = true;
  EXPECT_NE(render_settings_label(o.render), render_settings_label(renka));  // --resume tells them apart
}

// A figure's data as plot.py reads it: points with a non-finite coordinate (or not positive
// on a log axis) left out, every per-point list kept aligned with them.
TEST(Plot, FigureJsonKeepsOnlyDrawablePoints) {
  plot_panel p;
  p.log_x = true;
  plot_series s;
  s.name = "foveated nn", s.scheme = "nn";
  s.x = {1, NAN, 3, 0}, s.y = {0.5, 0.6, INFINITY, 0.8};
  s.x_lo = {0.9, 1, 2, 0}, s.x_hi = {1.1, 1, NAN, 0};
  s.labels = {"a", "b", "c", "d"};
  s.ringed = {true, false, false, false};
  p.series = {s};
  const nlohmann::json j = figure_json({p}, {"f.png", "f.svg"});
  const nlohmann::json& out = j["panels"][0]["series"][0];
  EXPECT_EQ(out["x"], nlohmann::json::array({1.0}));
  EXPECT_EQ(out["x_lo"], nlohmann::json::array({0.9}));
  EXPECT_EQ(out["labels"], nlohmann::json::array({"a"}));
  EXPECT_EQ(out["scheme"], "nn");
  EXPECT_EQ(j["outputs"][1], "f.svg");
}

// plot.py through Debian's python3 and matplotlib (scripts/install-deps.sh installs both):
// a PNG and an SVG, and a line naming what failed otherwise.
TEST(Plot, WritesPngAndSvg) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("fovbench-plot-test-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  plot_panel p;
  p.title = "test", p.x_label = "ms", p.y_label = "JOD";
  p.log_x = true;
  plot_series s;
  s.name = "full resolution", s.scheme = "full";
  s.x = {10, 20, 40}, s.y = {8.1, 8.9, 9.3}, s.labels = {"full 1spp", "full 2spp", "full 4spp"};
  p.series = {s};
  const std::string stem = (dir / "figure").string();
  EXPECT_EQ(write_plot({p}, stem), "");
  EXPECT_GT(std::filesystem::file_size(stem + ".png"), 1000u);
  EXPECT_GT(std::filesystem::file_size(stem + ".svg"), 1000u);
  const std::string why = write_plot({p}, (dir / "missing" / "figure").string());  // no such folder
  EXPECT_NE(why.find("not drawn"), std::string::npos) << why;
  std::filesystem::remove_all(dir);
}

// Where a JOD curve over scales falls to a level: interpolated inside, NaN outside.
TEST(Yardstick, ScaleAtJodInterpolatesTheCrossing) {
  EXPECT_DOUBLE_EQ(scale_at_jod({1, 2, 3}, {9.5, 9.1, 8.7}, 9.0), 2.25);
  EXPECT_DOUBLE_EQ(scale_at_jod({1, 2}, {9.4, 9.0}, 9.0), 2.0);
  EXPECT_TRUE(std::isnan(scale_at_jod({1, 2, 3}, {9.5, 9.3, 9.1}, 9.0)));  // never reaches it
  EXPECT_TRUE(std::isnan(scale_at_jod({1, 2, 3}, {8.9, 8.5, 8.0}, 9.0)));  // below it from the start
  EXPECT_DOUBLE_EQ(thesis_threshold("shepard"), 1.779);
  EXPECT_TRUE(std::isnan(thesis_threshold("bilinear")));
}

// A row of one study: kind, scale (or pixel fraction), spp, JOD, the per-repetition
// full / frame ratios (foveated kinds) or the ladder (full rows).
result_row study_row(const std::string& kind, const std::string& scale, const std::string& spp, double jod,
                     const std::string& samples, const std::string& fovea = "darts") {
  result_row r = sample_row("shepard", spp);
  r.cells["scene"] = "builtin", r.cells["gaze"] = "centre", r.cells["display"] = "fove", r.cells["ppd"] = "22.3";
  r.cells["kind"] = kind, r.cells["fovea"] = fovea, r.cells["k"] = "5", r.cells["ray_floor"] = "";
  r.cells["scale"] = kind == "foveated" || kind == "falloff" ? scale : "";
  r.cells["pixel_fraction"] = kind == "uniform" ? scale : "";
  r.cells["density"] = kind == "foveated" ? "fixed" : "";
  if (kind == "full") r.cells["method"] = "full", r.cells["k"] = "";
  if (kind == "falloff") r.cells["method"] = "falloff", r.cells["k"] = "", r.cells["ray_floor"] = "1";
  r.cells["jod"] = fmt::format("{}", jod), r.cells["noise_floor_jod"] = "9.99";
  r.cells["full_rays"] = fmt::format("{}", 1000 * std::stoi(spp)), r.cells["rays"] = r.cells["full_rays"];
  r.cells["rays_cast"] = fmt::format("{}", 2000 * std::stoi(spp));  // and a shadow ray each
  r.cells["speedup_samples"] = kind == "full" ? "1;1;1" : samples;
  r.cells["ladder_samples"] = kind == "full" ? samples : "";
  return r;
}

// Full frames at 1, 2 and 4 spp scoring 9.0, 9.6 and 9.8 JOD, 1x, 2x and 4x the 1-spp time.
std::vector<result_row> full_rows() {
  return {study_row("full", "", "1", 9.0, "1;1;1"), study_row("full", "", "2", 9.6, "2;2;2"),
          study_row("full", "", "4", 9.8, "4;4;4")};
}

const scheme_answer* answer_of(const std::vector<scheme_answer>& answers, scheme which) {
  for (const scheme_answer& a : answers)
    if (a.scheme == which) return &a;
  return nullptr;
}

// The goal's yardstick is the cheapest full frame reaching the target; each scheme is priced
// against it on its own: the fastest configuration reaching its JOD (chained speedup), or its
// best JOD short of it.
TEST(SchemeAnswers, PriceEachSchemeAtTheCheapestFullFrameReachingTheTarget) {
  std::vector<result_row> rows = full_rows();
  rows.push_back(study_row("foveated", "1.00", "1", 9.7, "2;2;2"));  // 2x the 1-spp frame: 4x the 2-spp one
  rows.push_back(study_row("foveated", "0.50", "4", 9.75, "1.5;1.5;1.5"));  // 1.5x the 4-spp frame: 0.75x the 2-spp one
  rows.push_back(study_row("falloff", "1.00", "4", 9.3, "3;3;3"));   // fast, short of 9.6
  rows.push_back(study_row("falloff", "0.50", "4", 9.4, "2;2;2"));   // the falloff's best JOD
  result_row falling = study_row("foveated", "1.00", "4", 9.65, "1.2;1.2;1.2");  // rays falling 4 -> 1: 0.6x
  falling.cells["ray_floor"] = "1";
  rows.push_back(falling);
  const std::vector<scheme_answer> goal = at_goal(scheme_answers_by_level(rows), 9.5);
  ASSERT_EQ(goal.size(), 2u);
  const scheme_answer* sparse = answer_of(goal, scheme::sparse);
  ASSERT_TRUE(sparse);
  EXPECT_EQ(sparse->yardstick_spp, 2.0);
  EXPECT_DOUBLE_EQ(sparse->yardstick_jod, 9.6);
  EXPECT_TRUE(sparse->reached);
  EXPECT_EQ(sparse->best, "s1.00 shepard 1spp k5");
  EXPECT_NEAR(sparse->speedup.estimate, 4.0, 1e-12);
  EXPECT_NEAR(sparse->speedup.lo, 4.0, 1e-12);
  EXPECT_DOUBLE_EQ(sparse->target_jod, 9.5);
  EXPECT_DOUBLE_EQ(sparse->noise_floor_jod, 9.99);
  EXPECT_DOUBLE_EQ(sparse->ppd, 22.3);
  const scheme_answer* falloff = answer_of(goal, scheme::falloff);
  ASSERT_TRUE(falloff);
  EXPECT_FALSE(falloff->reached);
  EXPECT_DOUBLE_EQ(falloff->best_jod, 9.4);
  EXPECT_TRUE(std::isnan(falloff->speedup.estimate));
  // A target no full frame reaches: the best full frame is the yardstick, and only the
  // 0.5 set (9.75) is short of its 9.8.
  const std::vector<scheme_answer> high = at_goal(scheme_answers_by_level(rows), 9.9);
  ASSERT_TRUE(answer_of(high, scheme::sparse));
  // Its rows with falling rays are named by their floor where they are the answer.
  const std::vector<scheme_answer> at_four = scheme_answers_by_level({rows[2], falling});
  ASSERT_EQ(at_four.size(), 1u);
  EXPECT_EQ(at_four[0].best, "s1.00 shepard 4-1spp k5");
  EXPECT_EQ(answer_of(high, scheme::sparse)->yardstick_spp, 4.0);
  EXPECT_FALSE(answer_of(high, scheme::sparse)->reached);
  EXPECT_DOUBLE_EQ(answer_of(high, scheme::sparse)->best_jod, 9.75);
  // The markdown names the yardstick and each cell.
  const std::string md = scheme_answers_markdown(goal);
  EXPECT_NE(md.find("full 2 spp (9.60"), std::string::npos) << md;
  EXPECT_NE(md.find("**4.00x** (4.00-4.00, faster)"), std::string::npos) << md;
  EXPECT_NE(md.find("not reached (-0.20 JOD): fall s0.50 4-1spp"), std::string::npos) << md;
  EXPECT_NE(md.find("| 1.5x |"), std::string::npos) << md;  // FOVE's goal
}

// fovbench summary: runs of one study (a darts run and a grid-fovea run) give one row of
// answers, each scheme's best; inputs that disagree or hold nothing are refused.
TEST(Summary, JoinsRunsAndRefusesOnesThatDisagree) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(::testing::TempDir()) / ("fovbench-summary-" + std::to_string(getpid()));
  fs::remove_all(dir);
  auto write_run = [&](const std::string& name, std::vector<result_row> rows) {
    fs::create_directories(dir / name);
    results_writer w((dir / name / "results.csv").string());
    for (const result_row& r : rows) w.append(r);
  };
  std::vector<result_row> darts = full_rows(), grid = full_rows();
  darts.push_back(study_row("foveated", "1.00", "1", 9.7, "2;2;2"));
  darts.push_back(study_row("uniform", "0.2500", "1", 9.2, "3;3;3"));
  grid.push_back(study_row("foveated", "0.50", "2", 9.65, "0.5;0.5;0.5"));
  for (result_row& row : grid) row.cells["fovea"] = "grid-4.00";  // one fovea per run, as fovbench writes
  write_run("runs/darts", darts);
  write_run("runs/grid", grid);
  char arg0[] = "fovbench";
  char* argv[] = {arg0};
  summary_options o;
  o.inputs = {(dir / "runs").string()};
  o.out = (dir / "summary").string();
  const summary_result r = write_summary(o, 1, argv);
  EXPECT_EQ(r.files.size(), 2u);
  ASSERT_EQ(r.answers.size(), 3u);  // sparse, lower resolution, hybrid
  const scheme_answer* hybrid = answer_of(r.answers, scheme::hybrid);
  ASSERT_TRUE(hybrid);
  EXPECT_TRUE(hybrid->reached);
  EXPECT_NEAR(hybrid->speedup.estimate, 0.5, 1e-12);
  EXPECT_EQ(hybrid->best, "s0.50 shepard 2spp k5 grid-4.00");
  EXPECT_NE(hybrid->source.find("grid"), std::string::npos);
  EXPECT_FALSE(answer_of(r.answers, scheme::lower_resolution)->reached);
  for (const char* file : {"summary.md", "summary.csv"}) EXPECT_GT(fs::file_size(dir / "summary" / file), 100u) << file;
  EXPECT_THROW(write_summary(o, 1, argv), usage_error);  // never over an earlier summary
  // A run whose 2-spp full frame scores otherwise is another study.
  std::vector<result_row> other = full_rows();
  other[1].cells["jod"] = "9.55";
  other.push_back(study_row("foveated", "1.00", "1", 9.7, "2;2;2"));
  write_run("other", other);
  o.inputs = {(dir / "runs").string(), (dir / "other").string()};
  o.out = (dir / "summary-2").string();
  EXPECT_THROW(write_summary(o, 1, argv), std::runtime_error);
  EXPECT_FALSE(fs::exists(dir / "summary-2" / "summary.md"));
  o.inputs = {(dir / "summary").string()};  // no results.csv there
  EXPECT_THROW(write_summary(o, 1, argv), usage_error);
  o.inputs = {(dir / "nothing-here").string()};
  EXPECT_THROW(write_summary(o, 1, argv), usage_error);
  fs::remove_all(dir);
}

// The cost of a sample as a study axis (issue 29): runs of one scene and display traced by
// other integrators are other questions, each answered against its own yardstick, not one
// study that disagrees with itself.
TEST(Summary, AnswersEachIntegratorOnItsOwn) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(::testing::TempDir()) / ("fovbench-summary-integrators-" + std::to_string(getpid()));
  fs::remove_all(dir);
  auto write_run = [&](const std::string& name, std::vector<result_row> rows) {
    fs::create_directories(dir / name);
    results_writer w((dir / name / "results.csv").string());
    for (const result_row& r : rows) w.append(r);
  };
  std::vector<result_row> direct = full_rows(), path = full_rows();
  direct.push_back(study_row("foveated", "1.00", "1", 9.7, "2;2;2"));  // 4x the 2-spp frame
  path[1].cells["jod"] = "9.2";                                        // noisier: 4 spp is the yardstick
  path.push_back(study_row("foveated", "1.00", "2", 9.85, "3;3;3"));   // 3x the 2-spp frame: 6x the 4-spp one
  for (result_row& row : path) row.cells["integrator"] = "path", row.cells["bounces"] = "3";
  write_run("direct", direct);
  write_run("path", path);
  char arg0[] = "fovbench";
  char* argv[] = {arg0};
  summary_options o;
  o.inputs = {dir.string()};
  o.out = (dir / "summary").string();
  const summary_result r = write_summary(o, 1, argv);
  ASSERT_EQ(r.answers.size(), 2u);
  for (const scheme_answer& a : r.answers) {
    ASSERT_TRUE(a.reached) << a.integrator;
    const bool direct_run = a.integrator == "direct";
    if (!direct_run) {
      EXPECT_EQ(a.integrator, "path, 3 bounces");
    }
    EXPECT_EQ(a.yardstick_spp, direct_run ? 2.0 : 4.0) << a.integrator;
    EXPECT_NEAR(a.speedup.estimate, direct_run ? 4.0 : 6.0, 1e-12) << a.integrator;
  }
  std::ifstream md(dir / "summary" / "summary.md");
  const std::string text((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("**builtin (path, 3 bounces)**"), std::string::npos) << text;
  EXPECT_NE(text.find("**builtin**"), std::string::npos) << text;
  fs::remove_all(dir);
}

// A results.csv from before the steady-state columns reads for a summary (single frames),
// never for --resume.
// Files of older fovbenches: before the reuse columns, before rays_cast too, before the integrator columns too, before the acuity column too,
// before the density columns too, and before the steady-state ones too (their rows read as
// csf and direct); a header missing only later columns never existed and is refused.
TEST(ResultsCsv, TheColumnsBeforeSteadyStateReadOnlyWhenAsked) {
  const std::string path = ::testing::TempDir() + "/results-before-steady-state.csv";
  const std::set<std::string> density = {"density", "adaptive_threshold", "levels", "level_rays"};
  const std::set<std::string> steady = {"taa_frames", "taa_pattern"}, acuity = {"acuity", "sampler"};
  auto joined = [](std::set<std::string> a, const std::set<std::string>& b) {
    a.insert(b.begin(), b.end());
    return a;
  };
  const std::set<std::string> cast = joined(reuse_columns, {"rays_cast"});
  const std::set<std::string> traced = joined(cast, {"integrator", "bounces"});
  for (const auto& [dropped, readable] : std::vector<std::pair<std::set<std::string>, bool>>{
           {reuse_columns, true}, {cast, true}, {traced, true}, {joined(traced, acuity), true},
           {joined(joined(traced, acuity), density), true}, {joined(joined(joined(traced, acuity), density), steady), true},
           {acuity, false}, {density, false}, {steady, false}, {{"integrator", "bounces"}, false}, {{"rays_cast"}, false},
           {{"reuse_kept"}, false}}) {
    std::vector<std::string> columns = result_columns();
    columns.erase(std::remove_if(columns.begin(), columns.end(), [&](const std::string& c) { return dropped.count(c) > 0; }),
                  columns.end());
    result_row row = sample_row("nn", "1");
    for (const std::string& c : dropped) row.cells[c] = "";  // what the reader gives a column the file lacks
    row.cells["density"] = "fixed";                           // (an older foveated row's set is fixed)
    row.cells["acuity"] = "csf";                              // (and of the thesis's acuity model)
    row.cells["sampler"] = "poisson";                         // (and darts)
    row.cells["integrator"] = "direct";                       // (and the direct integrator)
    {
      std::ofstream out(path);
      for (size_t i = 0; i < columns.size(); ++i) out << (i ? "," : "") << columns[i];
      out << "\n";
      for (size_t i = 0; i < columns.size(); ++i) out << (i ? "," : "") << csv_cell(row.text(columns[i]));
      out << "\n";
    }
    EXPECT_THROW(read_results(path), std::runtime_error);
    if (!readable) {
      EXPECT_THROW(read_results(path, true), std::runtime_error);
      continue;
    }
    const std::vector<result_row> rows = read_results(path, true);
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_EQ(rows[0].cells, row.cells);
    EXPECT_EQ(integrator_text(rows[0]), "direct");
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace fov
