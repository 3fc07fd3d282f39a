#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>

#include <cstring>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "fov/checksum.h"
#include "fov/knn_table.h"
#include "fov/pointset_io.h"
#include "test_sets.h"

namespace fov {
namespace {

namespace fs = std::filesystem;

class PointsetFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("fovray-io-" + std::to_string(getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    knn_params kp;
    kp.k = 12;
    set_ = generate_pointset(testing::small_model(60, 50), testing::quick_darts(), kp);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  static std::vector<char> read(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  static void write(const std::string& p, const std::vector<char>& bytes) {
    std::ofstream(p, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
  }
  // Loads and returns the error message, or "" when the file loads.
  static std::string load_error(const std::string& p) {
    try {
      load_pointset(p);
      return "";
    } catch (const file_error& e) {
      return e.what();
    }
  }

  // Makes the header checksum valid again after a test edits header fields.
  static void seal_header(std::vector<char>& bytes) {
    const uint32_t crc = crc32c(bytes.data(), 508);
    std::memcpy(&bytes[508], &crc, 4);
  }

  fs::path dir_;
  pointset set_;
};

void expect_same(const pointset& a, const pointset& b) {
  EXPECT_EQ(a.model.display.width, b.model.display.width);
  EXPECT_EQ(a.model.display.height, b.model.display.height);
  EXPECT_EQ(a.model.display.viewing_distance, b.model.display.viewing_distance);
  EXPECT_EQ(a.model.scale, b.model.scale);
  EXPECT_EQ(a.model.acuity.alpha, b.model.acuity.alpha);
  EXPECT_EQ(a.darts.seed, b.darts.seed);
  EXPECT_EQ(a.stats.phase1_points, b.stats.phase1_points);
  EXPECT_EQ(a.stats.free_fraction, b.stats.free_fraction);
  ASSERT_EQ(a.points.size(), b.points.size());
  EXPECT_EQ(0, std::memcmp(a.points.data(), b.points.data(), a.points.size() * sizeof(point)));
  ASSERT_EQ(a.table.k, b.table.k);
  for (uint32_t y = 0; y < a.table.height; ++y)
    for (uint32_t x = 0; x < a.table.width; ++x)
      for (uint32_t j = 0; j < a.table.k; ++j) ASSERT_EQ(a.table.at(x, y, j), b.table.at(x, y, j));
}

TEST_F(PointsetFile, RoundTripsInBothEncodings) {
  for (table_encoding e : {table_encoding::raw, table_encoding::ref_left_zstd}) {
    save_params sp;
    sp.encoding = e;
    sp.chunk_rows = 7;  // several chunks, the last one partial
    save_pointset(path("a.fovset"), set_, sp);
    expect_same(set_, load_pointset(path("a.fovset")));
    load_params lp;
    lp.group = 1;
    const pointset planes = load_pointset(path("a.fovset"), lp);
    EXPECT_EQ(planes.table.group, 1u);
    expect_same(set_, planes);
  }
}

// Issue 24: a cells file holds the header and points only; loading builds the cells, which
// give every pixel the table's neighbours. A set holding cells saves as one, byte for byte
// the file a table set saved with encoding cells gives; a header-only load keeps k.
TEST_F(PointsetFile, CellsFilesHoldThePointsAndLoadTheTablesNeighbours) {
  save_params sp;
  sp.encoding = table_encoding::cells;
  save_pointset(path("c.fovset"), set_, sp);
  EXPECT_EQ(fs::file_size(path("c.fovset")), 512 + set_.points.size() * sizeof(point));
  const pointset loaded = load_pointset(path("c.fovset"));
  EXPECT_EQ(loaded.table.k, 0u);
  ASSERT_TRUE(loaded.cells.loaded());
  EXPECT_EQ(stored_k(loaded), 12u);
  EXPECT_EQ(0, std::memcmp(loaded.points.data(), set_.points.data(), set_.points.size() * sizeof(point)));
  uint32_t got[max_knn];
  for (uint32_t y = 0; y < set_.table.height; ++y)
    for (uint32_t x = 0; x < set_.table.width; ++x) {
      pixel_neighbours(loaded, x, y, 12, got);
      for (uint32_t j = 0; j < 12; ++j) ASSERT_EQ(got[j], set_.table.at(x, y, j)) << x << "," << y << " rank " << j;
    }
  save_pointset(path("again.fovset"), loaded);  // a set holding cells saves as cells
  EXPECT_EQ(read(path("c.fovset")), read(path("again.fovset")));
  load_params lp;
  lp.table = false;
  const pointset header_only = load_pointset(path("c.fovset"), lp);
  EXPECT_EQ(stored_k(header_only), 12u);
  EXPECT_FALSE(header_only.cells.loaded());
  EXPECT_THROW(require_neighbours(header_only), std::invalid_argument);
  // Header fields patched at their offsets (docs/pointset-format.md), the header checksum made
  // valid again so that the checks behind it are reached.
  const std::vector<char> good = read(path("c.fovset"));
  auto patched = [&](std::initializer_list<std::pair<size_t, uint32_t>> fields, const std::string& name) {
    std::vector<char> bytes = good;
    for (auto [at, value] : fields) std::memcpy(&bytes[at], &value, 4);
    const uint32_t crc = crc32c(bytes.data(), 508);
    std::memcpy(&bytes[508], &crc, 4);
    write(path(name), bytes);
    return load_error(path(name));
  };
  // A cells file that claims another group is refused by name.
  const std::string group = patched({{156, 2}}, "bad.fovset");
  EXPECT_NE(group.find("a cells set with a table section"), std::string::npos) << group;
  EXPECT_NE(group.find("bad.fovset"), std::string::npos) << group;
  // The points of a 120 x 100 canvas on a declared 8000 x 8000 one: every empty cell would keep
  // them all (d_k of its centre spans the canvas), refused once the candidates pass their bound.
  const std::string huge = patched({{16, 4000}, {20, 4000}, {144, 8000}, {148, 8000}}, "huge.fovset");
  EXPECT_NE(huge.find("candidates (refused)"), std::string::npos) << huge;
  // On a declared 120000 x 120000 canvas the empty tiles alone are 14 M cells: refused by count.
  const std::string vast = patched({{16, 60000}, {20, 60000}, {144, 120000}, {148, 120000}}, "vast.fovset");
  EXPECT_NE(vast.find("per point"), std::string::npos) << vast;
}

TEST_F(PointsetFile, SameSetGivesByteIdenticalFiles) {
  knn_params kp;
  kp.k = 12;
  const pointset again = generate_pointset(testing::small_model(60, 50), testing::quick_darts(), kp);
  save_pointset(path("a.fovset"), set_);
  save_pointset(path("b.fovset"), again);
  EXPECT_EQ(read(path("a.fovset")), read(path("b.fovset")));
}

TEST_F(PointsetFile, HeaderOnlyLoadKeepsTheTableShape) {
  save_pointset(path("a.fovset"), set_);
  load_params lp;
  lp.table = false;
  const pointset s = load_pointset(path("a.fovset"), lp);
  EXPECT_EQ(s.points.size(), set_.points.size());
  EXPECT_EQ(s.table.k, 12u);
  EXPECT_TRUE(s.table.entries.empty());
}

TEST_F(PointsetFile, RejectsWrongMagicVersionAndTruncation) {
  save_pointset(path("a.fovset"), set_);
  const std::vector<char> good = read(path("a.fovset"));
  std::vector<char> bad = good;
  bad[0] = 'X';
  write(path("magic.fovset"), bad);
  EXPECT_NE(load_error(path("magic.fovset")).find("wrong magic"), std::string::npos);
  bad = good;
  bad[8] = 9;  // version
  write(path("version.fovset"), bad);
  EXPECT_NE(load_error(path("version.fovset")).find("unknown format version 9"), std::string::npos);
  for (size_t cut : {size_t(0), size_t(5), size_t(300), size_t(600), good.size() / 2, good.size() - 1}) {
    write(path("cut.fovset"), std::vector<char>(good.begin(), good.begin() + long(cut)));
    const std::string e = load_error(path("cut.fovset"));
    EXPECT_NE(e.find("truncated"), std::string::npos) << "cut at " << cut << ": " << e;
    EXPECT_NE(e.find("cut.fovset"), std::string::npos) << "the message names the file";
  }
  EXPECT_NE(load_error(path("missing.fovset")).find("cannot open"), std::string::npos);
}

TEST_F(PointsetFile, RejectsFlippedBytesInEverySection) {
  for (table_encoding e : {table_encoding::raw, table_encoding::ref_left_zstd}) {
    save_params sp;
    sp.encoding = e;
    save_pointset(path("a.fovset"), set_, sp);
    const std::vector<char> good = read(path("a.fovset"));
    const size_t points_at = 512, table_at = 512 + ((set_.points.size() * 12 + 63) / 64) * 64;
    for (auto [where, what] : {std::pair{size_t(40), "header checksum"}, {points_at + 100, "points checksum"},
                               {table_at + 3, e == table_encoding::raw ? "table checksum" : "directory checksum"},
                               {good.size() - 10, "checksum"}}) {
      std::vector<char> bad = good;
      bad[where] ^= 0x10;
      write(path("flip.fovset"), bad);
      EXPECT_NE(load_error(path("flip.fovset")).find(what), std::string::npos)
          << table_encoding_name(e) << " byte " << where << ": " << load_error(path("flip.fovset"));
    }
  }
}

TEST_F(PointsetFile, RejectsOutOfRangeIndicesEvenWithValidChecksums) {
  save_params sp;
  sp.encoding = table_encoding::raw;
  save_pointset(path("a.fovset"), set_, sp);
  std::vector<char> bytes = read(path("a.fovset"));
  // Put an index past the point count into the raw table and re-seal its checksum,
  // so only the range check can catch it.
  uint64_t table_offset = 0, table_bytes = 0;
  // Header offsets of table_offset / table_bytes / table_crc (docs/pointset-format.md).
  std::memcpy(&table_offset, &bytes[184], 8);
  std::memcpy(&table_bytes, &bytes[192], 8);
  const uint32_t huge = uint32_t(set_.points.size()) + 5;
  std::memcpy(&bytes[table_offset + 40], &huge, 4);
  const uint32_t crc = crc32c(&bytes[table_offset], table_bytes);
  std::memcpy(&bytes[204], &crc, 4);
  const uint32_t header_crc = crc32c(bytes.data(), 508);
  std::memcpy(&bytes[508], &header_crc, 4);
  write(path("range.fovset"), bytes);
  EXPECT_NE(load_error(path("range.fovset")).find("out of range"), std::string::npos) << load_error(path("range.fovset"));
}

TEST_F(PointsetFile, GridSetsRoundTripAndVersionOneFilesStillLoad) {
  knn_params kp;
  kp.k = 6;
  const pointset grid = generate_pointset(testing::partial_grid_model(), testing::grid_darts(), kp);
  ASSERT_GT(grid.stats.grid_points, 1000u);
  save_pointset(path("g.fovset"), grid);
  const pointset back = load_pointset(path("g.fovset"));
  EXPECT_EQ(back.darts.fovea, fovea_layout::grid);
  EXPECT_EQ(back.darts.grid_spacing, grid.darts.grid_spacing);
  EXPECT_EQ(back.stats.grid_points, grid.stats.grid_points);
  uint64_t marked = 0;
  for (const point& p : back.points) marked += is_grid_point(back, p);
  EXPECT_EQ(marked, grid.stats.grid_points);

  // A grid point moved off its pixel centre, checksums re-sealed: the count check catches it.
  std::vector<char> bytes = read(path("g.fovset"));
  size_t moved = 0;
  for (size_t i = 0; i < back.points.size(); ++i)
    if (is_grid_point(back, back.points[i])) moved = i;
  float x = back.points[moved].x + 0.25f;
  std::memcpy(&bytes[512 + moved * 12], &x, 4);
  auto reseal = [&](std::vector<char>& b, size_t points) {
    const uint32_t crc = crc32c(&b[512], points * 12);
    std::memcpy(&b[200], &crc, 4);
    const uint32_t header_crc = crc32c(b.data(), 508);
    std::memcpy(&b[508], &header_crc, 4);
  };
  reseal(bytes, back.points.size());
  write(path("moved.fovset"), bytes);
  EXPECT_NE(load_error(path("moved.fovset")).find("grid pixels"), std::string::npos) << load_error(path("moved.fovset"));

  // The same moved point with the header's grid count lowered to match: now a dart inside a
  // grid pixel, which the loader refuses by name (grid sets from before issue 24 held ~1 a pixel).
  const uint64_t fewer = back.stats.grid_points - 1;
  std::memcpy(&bytes[216], &fewer, 8);
  reseal(bytes, back.points.size());
  write(path("hidden.fovset"), bytes);
  EXPECT_NE(load_error(path("hidden.fovset")).find("1 darts lie inside grid pixels"), std::string::npos)
      << load_error(path("hidden.fovset"));

  // Version 1 (before the fovea layout) had zeros where version 2 keeps it: it loads as darts.
  save_pointset(path("d.fovset"), set_);
  bytes = read(path("d.fovset"));
  const uint32_t v1 = 1;
  std::memcpy(&bytes[8], &v1, 4);
  reseal(bytes, set_.points.size());
  write(path("v1.fovset"), bytes);
  ASSERT_EQ(load_error(path("v1.fovset")), "");
  EXPECT_EQ(load_pointset(path("v1.fovset")).darts.fovea, fovea_layout::darts);
  // ... but a version-1 file with the layout field set is refused.
  const uint32_t grid_layout = 1;
  std::memcpy(&bytes[44], &grid_layout, 4);
  reseal(bytes, set_.points.size());
  write(path("v1grid.fovset"), bytes);
  EXPECT_NE(load_error(path("v1grid.fovset")).find("version 1"), std::string::npos) << load_error(path("v1grid.fovset"));
}

// Issue 27: a set of another acuity model is a version-4 file holding that model's own
// parameters (and nothing at the others' fields); the loader gives the model back, and refuses
// a model older versions cannot name, another model's fields set, parameters out of range.
TEST_F(PointsetFile, AcuityModelsRoundTripAsVersionFour) {
  for (const auto& [label, model] : acuity_model_labels) {
    spacing_model m = testing::small_model(60, 50);
    m.acuity.model = model;
    m.acuity.mar_slope = 0.03;        // read by linear-mar only
    m.acuity.pivot_cpd[2] = 7;        // read by piecewise-mar only
    knn_params kp;
    kp.k = 6;
    const pointset set = generate_pointset(m, testing::quick_darts(), kp);
    EXPECT_EQ(count_spacing_violations(set.points, set.canvas_width(), set.canvas_height()), 0u) << label;
    const std::string file = path(std::string(label) + ".fovset");
    save_pointset(file, set);
    const std::vector<char> bytes = read(file);
    uint32_t version = 0;
    std::memcpy(&version, &bytes[8], 4);
    EXPECT_EQ(version, model == acuity_model::wang_csf ? 2u : 4u) << label;
    const pointset back = load_pointset(file);
    EXPECT_EQ(back.model.acuity.model, model);
    EXPECT_TRUE(same_acuity(back.model.acuity, set.model.acuity)) << label;
    expect_same(set, back);
    if (model == acuity_model::wang_csf) continue;
    // Another model's fields set (the CSF's ct0 at offset 48), header re-sealed: refused.
    std::vector<char> b = bytes;
    const double ct0 = 1.0 / 64;
    std::memcpy(&b[48], &ct0, 8);
    seal_header(b);
    write(path("mixed.fovset"), b);
    EXPECT_NE(load_error(path("mixed.fovset")).find("another model's parameters"), std::string::npos)
        << load_error(path("mixed.fovset"));
    // The same file called version 2, which knows only the CSF: refused by name.
    b = bytes;
    const uint32_t v2 = 2;
    std::memcpy(&b[8], &v2, 4);
    seal_header(b);
    write(path("v2.fovset"), b);
    EXPECT_NE(load_error(path("v2.fovset")).find("version 2"), std::string::npos) << load_error(path("v2.fovset"));
    // A parameter out of its range (linear-mar's slope at 316, piecewise's first acuity at 340).
    b = bytes;
    const double bad = -1;
    std::memcpy(&b[model == acuity_model::linear_mar ? 316 : 340], &bad, 8);
    seal_header(b);
    write(path("range.fovset"), b);
    EXPECT_NE(load_error(path("range.fovset")).find("invalid model"), std::string::npos) << load_error(path("range.fovset"));
  }
  // An unknown model number in a version-4 file.
  spacing_model m = testing::small_model(60, 50);
  m.acuity.model = acuity_model::linear_mar;
  knn_params kp;
  kp.k = 6;
  save_pointset(path("l.fovset"), generate_pointset(m, testing::quick_darts(), kp));
  std::vector<char> b = read(path("l.fovset"));
  const uint32_t unknown = 9;
  std::memcpy(&b[40], &unknown, 4);
  seal_header(b);
  write(path("unknown.fovset"), b);
  EXPECT_NE(load_error(path("unknown.fovset")).find("unknown acuity model 9"), std::string::npos)
      << load_error(path("unknown.fovset"));
}

// A lattice sampler's set: version 4 with the sampler at offset 380; an unknown sampler, the
// field set in an older version, a lattice with a grid fovea are refused by name.
TEST_F(PointsetFile, SamplersAreKeptAndCheckedInTheHeader) {
  dart_params d = testing::quick_darts();
  d.sampler = point_sampler::log_polar;
  knn_params kp;
  kp.k = 6;
  save_pointset(path("lp.fovset"), generate_pointset(testing::small_model(60, 50), d, kp));
  const std::vector<char> bytes = read(path("lp.fovset"));
  uint32_t version = 0, sampler = 0;
  std::memcpy(&version, &bytes[8], 4);
  std::memcpy(&sampler, &bytes[380], 4);
  EXPECT_EQ(version, 4u);
  EXPECT_EQ(sampler, uint32_t(point_sampler::log_polar));
  auto patched = [&](size_t at, uint32_t value, const std::string& name) {
    std::vector<char> b = bytes;
    std::memcpy(&b[at], &value, 4);
    seal_header(b);
    write(path(name), b);
    return load_error(path(name));
  };
  EXPECT_NE(patched(380, 7, "s7.fovset").find("unknown sampler 7"), std::string::npos);
  EXPECT_NE(patched(384, 1, "r.fovset").find("unknown sampler"), std::string::npos);
  EXPECT_NE(patched(8, 2, "v2.fovset").find("version 2 file with fields of version 4"), std::string::npos);
  EXPECT_NE(patched(44, 1, "grid.fovset").find("grid fovea"), std::string::npos);
  // The darts' sets keep writing version 2 with the field 0.
  save_pointset(path("d.fovset"), set_);
  const std::vector<char> darts = read(path("d.fovset"));
  std::memcpy(&version, &darts[8], 4);
  std::memcpy(&sampler, &darts[380], 4);
  EXPECT_EQ(version, 2u);
  EXPECT_EQ(sampler, 0u);
}

// Hostile headers: sizes are checked against the file (without sums that wrap) and the
// machine's memory before anything is allocated; points out of Morton order are refused.
TEST_F(PointsetFile, HeaderSizesAreBoundedByTheFileBeforeAnyAllocation) {
  save_pointset(path("a.fovset"), set_);
  const std::vector<char> good = read(path("a.fovset"));
  auto reseal_header = [](std::vector<char>& b) {
    const uint32_t header_crc = crc32c(b.data(), 508);
    std::memcpy(&b[508], &header_crc, 4);
  };
  auto patched = [&](const std::string& name, auto&& patch) {
    std::vector<char> b = good;
    patch(b);
    reseal_header(b);
    write(path(name), b);
    return load_error(path(name));
  };
  // A points section whose end wraps past 2^64 back inside the file.
  std::string e = patched("wrap.fovset", [](std::vector<char>& b) {
    const uint64_t offset = ~uint64_t(0) - 100;
    std::memcpy(&b[168], &offset, 8);
  });
  EXPECT_NE(e.find("inconsistent"), std::string::npos) << e;
  e = patched("wrap-table.fovset", [](std::vector<char>& b) {
    uint64_t offset = 0;
    std::memcpy(&offset, &b[184], 8);
    const uint64_t bytes = ~uint64_t(0) - offset + 10;
    std::memcpy(&b[192], &bytes, 8);
  });
  EXPECT_NE(e.find("inconsistent"), std::string::npos) << e;
  // 2^31 points claimed by a small file: refused by size, not by a failed allocation.
  e = patched("many.fovset", [](std::vector<char>& b) {
    const uint64_t n = uint64_t(1) << 31, bytes = n * 12;
    std::memcpy(&b[136], &n, 8);
    std::memcpy(&b[176], &bytes, 8);
  });
  EXPECT_NE(e.find("inconsistent"), std::string::npos) << e;
  // A screen the file's table section cannot hold (the 4096 x 4096 in a small file):
  // refused from the header, before the table is allocated or decoded.
  auto declare_screen = [](std::vector<char>& b, uint32_t w) {
    const uint32_t cw = 2 * w;
    std::memcpy(&b[16], &w, 4);
    std::memcpy(&b[20], &w, 4);
    std::memcpy(&b[144], &cw, 4);
    std::memcpy(&b[148], &cw, 4);
  };
  e = patched("4k.fovset", [&](std::vector<char>& b) { declare_screen(b, 4096); });
  EXPECT_NE(e.find("more than 1024 times its size (refused)"), std::string::npos) << e;
  EXPECT_NE(e.find("4k.fovset"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << "one line";
  // A 65536 x 65536 screen (its canvas's table 2.2 TB at k = 12) whose section could hold
  // it (a sparse 2.2 GB file): refused naming the machine's memory.
  e = patched("huge.fovset", [&](std::vector<char>& b) {
    declare_screen(b, 65536);
    uint64_t table_offset = 0;
    std::memcpy(&table_offset, &b[184], 8);
    const uint64_t section = (uint64_t(131072) * 131072 * 12 * 4) / 1024 + 1;
    std::memcpy(&b[192], &section, 8);
  });
  EXPECT_NE(e.find("inconsistent"), std::string::npos) << "the file is shorter than the section: " << e;
  {
    std::vector<char> b = good;
    declare_screen(b, 65536);
    uint64_t table_offset = 0;
    std::memcpy(&table_offset, &b[184], 8);
    const uint64_t section = (uint64_t(131072) * 131072 * 12 * 4) / 1024 + 1;
    std::memcpy(&b[192], &section, 8);
    reseal_header(b);
    write(path("huge-sparse.fovset"), b);
    fs::resize_file(path("huge-sparse.fovset"), table_offset + section);  // sparse: no disk used
    e = load_error(path("huge-sparse.fovset"));
    EXPECT_NE(e.find("GB, more than this machine's"), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << "one line";
    fs::remove(path("huge-sparse.fovset"));
  }
  // Two points swapped (checksum re-sealed): out of Morton order.
  e = patched("order.fovset", [&](std::vector<char>& b) {
    std::vector<char> first(&b[512], &b[524]);
    std::memmove(&b[512], &b[524], 12);
    std::memcpy(&b[524], first.data(), 12);
    const uint32_t crc = crc32c(&b[512], set_.points.size() * 12);
    std::memcpy(&b[200], &crc, 4);
  });
  EXPECT_NE(e.find("Morton order"), std::string::npos) << e;
}

// Special files are refused before they are opened: a FIFO would block the open forever.
TEST_F(PointsetFile, FifosAndDirectoriesAreRefusedWithoutBlocking) {
  ASSERT_EQ(mkfifo(path("pipe.fovset").c_str(), 0600), 0);
  std::string e = load_error(path("pipe.fovset"));
  EXPECT_NE(e.find("not a regular file"), std::string::npos) << e;
  EXPECT_NE(e.find("pipe.fovset"), std::string::npos) << e;
  fs::create_directories(path("dir.fovset"));
  e = load_error(path("dir.fovset"));
  EXPECT_NE(e.find("is a directory"), std::string::npos) << e;
  EXPECT_NE(load_error(path("absent.fovset")).find("No such file"), std::string::npos);
}

TEST_F(PointsetFile, FailedWritesLeaveNothingBehind) {
  EXPECT_THROW(save_pointset(path("no/such/dir/a.fovset"), set_), file_error);
  EXPECT_THROW(check_writable(path("no/such/dir/a.fovset")), file_error);
  // A table source that fails half-way leaves neither the target nor a temporary file.
  EXPECT_THROW(save_pointset(path("half.fovset"), set_, set_.table.k, 4,
                             [](uint32_t y0, uint32_t, uint32_t*) {
                               if (y0 > 0) throw std::runtime_error("disk full");
                             }),
               std::runtime_error);
  EXPECT_FALSE(fs::exists(path("half.fovset")));
  EXPECT_TRUE(fs::is_empty(dir_));
}

// Outputs that are links, devices, directories or inputs are refused before anything is
// written; nothing is replaced.
TEST_F(PointsetFile, OutputsThatAreNotPlainNewFilesAreRefused) {
  save_pointset(path("a.fovset"), set_);
  const auto before = fs::file_size(path("a.fovset"));
  fs::create_symlink(path("a.fovset"), path("link.fovset"));
  EXPECT_NE(output_file_problem(path("link.fovset")).find("symbolic link"), std::string::npos);
  EXPECT_THROW(save_pointset(path("link.fovset"), set_), file_error);
  EXPECT_TRUE(fs::is_symlink(path("link.fovset")));
  EXPECT_NE(output_file_problem("/dev/null").find("not a regular file"), std::string::npos);
  EXPECT_THROW(write_file_atomic("/dev/null", "x", 1), file_error);
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  EXPECT_NE(output_file_problem(dir_.string()).find("directory"), std::string::npos);
  ASSERT_EQ(mkfifo(path("fifo").c_str(), 0600), 0);
  EXPECT_THROW(check_writable(path("fifo")), file_error);
  EXPECT_NE(output_file_problem(path("a.fovset"), {path("x"), path("a.fovset")}).find("is also an input"), std::string::npos);
  fs::create_hard_link(path("a.fovset"), path("hard.fovset"));
  EXPECT_THROW(check_writable(path("hard.fovset"), {path("a.fovset")}), file_error);  // the same file by another name
  EXPECT_EQ(output_file_problem(path("new.fovset"), {path("a.fovset")}), "");
  EXPECT_EQ(fs::file_size(path("a.fovset")), before);
}

// Quoted input fits its bound however it is escaped: 40 control bytes become at most 60
// characters (a CI fuzz run found a gaze datagram whose two quoted fields, bounded by input
// length, escaped to 256 characters).
TEST(Printable, BoundsTheEscapedLength) {
  EXPECT_EQ(printable("a\tb\n", 60), "a\\tb\\n");
  EXPECT_EQ(printable("abcdef", 3), "abc...");
  const std::string controls(40, '\x01');
  const std::string p = printable(controls, 60);
  EXPECT_LE(p.size(), 63u);
  EXPECT_EQ(p.substr(0, 8), "\\x01\\x01");
  EXPECT_EQ(p.substr(p.size() - 3), "...");
  EXPECT_EQ(printable(std::string(5, '\xff'), 60), "\\xff\\xff\\xff\\xff\\xff");
}

// A temporary file is removed when the process is stopped by SIGTERM or SIGINT, and one a
// killed process left behind (kill -9) is removed by the next writer of that file.
TEST_F(PointsetFile, TemporaryFilesDoNotOutliveTheirProcess) {
  for (int sig : {SIGTERM, SIGINT}) {
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      temp_output out(path("stopped.png"), ".png");
      out.write_at(0, "half", 4);
      ::raise(sig);
      _exit(0);  // not reached
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << "signal " << sig;
    EXPECT_TRUE(fs::is_empty(dir_)) << "signal " << sig << " left " << fs::directory_iterator(dir_)->path();
  }
  const pid_t dead = fork();  // a process that has ended: its temporary file is stale
  ASSERT_GE(dead, 0);
  if (dead == 0) _exit(0);
  ASSERT_EQ(waitpid(dead, nullptr, 0), dead);
  const std::string stale = path("out.fovset") + ".tmp-" + std::to_string(dead) + "-Ab12Cd";
  const std::string alive = path("out.fovset") + ".tmp-" + std::to_string(getppid()) + "-Ab12Cd";  // a live process's
  std::ofstream(stale) << "left by kill -9";
  std::ofstream(alive) << "still being written";
  save_pointset(path("out.fovset"), set_);
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(alive));
  EXPECT_NO_THROW(load_pointset(path("out.fovset")));
}

TEST(Checksum, Crc32cKnownAnswer) {
  // The standard check value of CRC-32C for "123456789" is 0xE3069283.
  EXPECT_EQ(crc32c("123456789", 9), 0xE3069283u);
  EXPECT_EQ(crc32c("56789", 5, crc32c("1234", 4)), 0xE3069283u);  // chaining
}

}  // namespace
}  // namespace fov
