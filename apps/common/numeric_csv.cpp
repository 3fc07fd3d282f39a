#include "numeric_csv.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "fov/files.h"

namespace fov {

numeric_csv read_numeric_csv(const std::string& path, const std::vector<std::string>& headers,
                             const std::string& header_rule, const std::string& what) {
  std::istringstream in(read_input_file(path, max_numeric_csv_bytes, what));
  auto chomp = [](std::string& s) {
    if (!s.empty() && s.back() == '\r') s.pop_back();
  };
  std::string line;
  std::getline(in, line);
  chomp(line);
  numeric_csv out;
  while (out.header < headers.size() && headers[out.header] != line) ++out.header;
  if (out.header == headers.size()) throw std::runtime_error(fmt::format("{}:1: the header must be {}", path, header_rule));
  const std::string& names = headers[out.header];
  const size_t columns = size_t(std::count(names.begin(), names.end(), ',')) + 1;
  for (int number = 2; std::getline(in, line); ++number) {
    chomp(line);
    if (line.empty()) continue;
    std::vector<double> v(columns);
    std::stringstream row(line);
    std::string cell;
    for (size_t i = 0; i < columns; ++i) {
      char* end = nullptr;
      if (!std::getline(row, cell, ',') || (v[i] = std::strtod(cell.c_str(), &end), end == cell.c_str() || *end) ||
          !std::isfinite(v[i]))
        throw std::runtime_error(fmt::format("{}:{}: expected {} numbers {}", path, number, columns, names));
    }
    if (std::getline(row, cell, ',')) throw std::runtime_error(fmt::format("{}:{}: more than {} cells", path, number, columns));
    out.rows.push_back(std::move(v));
    out.lines.push_back(number);
  }
  return out;
}

}  // namespace fov
