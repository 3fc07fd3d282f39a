#include "session.h"


#include <algorithm>
#include <fstream>
#include <numeric>
#include <stdexcept>

#include <fmt/format.h>

#include "fov/random.h"

namespace fov {

uint64_t subject_number(const std::string& subject) {
  std::string digits;
  for (char c : subject)
    if (std::isdigit(static_cast<unsigned char>(c))) digits += c;
  if (!digits.empty() && digits.size() < 18) return std::stoull(digits);
  uint64_t h = 1469598103934665603ull;  // FNV-1a
  for (char c : subject) h = (h ^ uint8_t(c)) * 1099511628211ull;
  return h;
}

std::vector<uint32_t> condition_order(const stair_protocol& p, const std::string& subject) {
  const uint32_t n = uint32_t(p.conditions.size());
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  if (p.order == "fixed") return order;
  if (p.order == "random") {
    rng r(stream_seed(p.seed, subject_number(subject), 0x0de7));
    for (uint32_t i = n; i > 1; --i) std::swap(order[i - 1], order[r.next() % i]);
    return order;
  }
  // Williams: first row 0, 1, n-1, 2, n-2, ...; row r adds r (mod n); for odd n the
  // rows n..2n-1 are the first n reversed, so each condition follows each other equally.
  std::vector<uint32_t> first(n);
  for (uint32_t j = 0, lo = 1, hi = n - 1; j < n; ++j)
    first[j] = j == 0 ? 0 : (j % 2 == 1 ? lo++ : hi--);
  const uint64_t rows = n % 2 == 0 ? n : 2 * n;
  const uint64_t row = (subject_number(subject) + rows - 1) % rows;  // subject 1 gets row 0
  for (uint32_t j = 0; j < n; ++j) order[j] = (first[j] + uint32_t(row % n)) % n;
  if (row >= n) std::reverse(order.begin(), order.end());
  return order;
}

stair_session::stair_session(const stair_protocol& p, const std::string& subject)
    : p_(p), subject_(subject), order_(condition_order(p, subject)) {
  for (size_t i = 0; i < p.conditions.size(); ++i) stairs_.emplace_back(p.rule, p.scale_min, p.scale_max, p.scale_start);
  seed_ = stream_seed(p.seed, subject_number(subject), 0x5e55);
}

trial_plan stair_session::next() const {
  trial_plan t;
  t.index = trials_;
  t.condition = order_[current_];
  const staircase& s = stairs_[t.condition];
  t.series_trial = s.trials();
  t.scale = s.scale();
  rng r(stream_seed(seed_, trials_, 0x7121));
  t.is_catch = r.uniform() < p_.catch_rate;
  t.foveated_interval = uint32_t(r.next() >> 63);
  const auto& f = p_.fixations[trials_ % p_.fixations.size()];
  t.fixation_x = f.first, t.fixation_y = f.second;
  const bool new_condition = trials_ > 0 && trials_ == series_began_at_;
  t.break_before = new_condition || (p_.break_every > 0 && trials_ > 0 && trials_ % p_.break_every == 0);
  return t;
}

staircase::step stair_session::record(const trial_plan& t, bool detected) {
  if (finished() || t.index != trials_) throw std::logic_error("stair_session: answer to a trial that is not next");
  ++trials_;
  staircase::step out;
  if (!t.is_catch) out = stairs_[t.condition].answer(detected);
  if (stairs_[t.condition].done()) {
    ++current_;
    series_began_at_ = trials_;
  }
  return out;
}

session_file session_file::create(const std::string& path, const nlohmann::json& header) {
  try {
    session_file f(line_log(path, line_log::mode::create_new));
    f.append(header);
    return f;
  } catch (const file_exists_error&) {
    throw std::runtime_error(fmt::format("{}: the session exists; continue it with --resume or choose another --session", path));
  }
}

session_data read_session(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open the session file", path));
  session_data out;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (in.eof()) break;  // no newline: a torn last line, never a complete record
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(line);
    } catch (const nlohmann::json::exception&) {
      throw std::runtime_error(fmt::format("{}:{}: not a JSON record", path, number));
    }
    const std::string type = j.value("type", "");
    if (number == 1 && type != "session") throw std::runtime_error(fmt::format("{}:1: not a fovstair session (no header)", path));
    if (type == "session" && number == 1) out.header = j;
    else if (type == "trial") out.trials.push_back(j);
    else if (type == "end") out.ended = true;
    else throw std::runtime_error(fmt::format("{}:{}: unknown record type '{}'", path, number, type));
  }
  if (number == 0) throw std::runtime_error(fmt::format("{}: empty session file", path));
  return out;
}

session_file session_file::resume(const std::string& path, nlohmann::json& header, std::vector<nlohmann::json>& trials) {
  session_data d = read_session(path);
  if (d.ended) throw std::runtime_error(fmt::format("{}: the session is finished; nothing to resume", path));
  session_file f(line_log(path, line_log::mode::open_existing));  // cuts a torn last line
  header = d.header;
  trials = std::move(d.trials);
  return f;
}

void session_file::append(const nlohmann::json& record) { log_.append_line(record.dump()); }

}  // namespace fov
