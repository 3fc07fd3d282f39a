// Small CSV files of numbers with a fixed header (gaze traces, camera paths).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace fov {

struct numeric_csv {
  size_t header = 0;                      // which of the accepted headers the file has
  std::vector<std::vector<double>> rows;  // finite numbers, as many as the header names
  std::vector<int> lines;                 // each row's line number, for messages
};

// The largest such file (a gaze trace at 120 Hz for an hour is about 11 MB).
constexpr uintmax_t max_numeric_csv_bytes = uintmax_t(32) << 20;

// Reads `path` (a regular file of at most max_numeric_csv_bytes): its first line must be one of `headers` (else the error says `header_rule`),
// every other non-empty line as many finite numbers as the header has names. Throws
// std::runtime_error "FILE:LINE: reason"; `what` names the file in "cannot open" errors.
numeric_csv read_numeric_csv(const std::string& path, const std::vector<std::string>& headers,
                             const std::string& header_rule, const std::string& what);

}  // namespace fov
