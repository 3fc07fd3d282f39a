#include "session.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "fov/files.h"
#include "fov/random.h"
#include "observer.h"

namespace fov {

uint64_t subject_number(const std::string& subject) {
  std::string digits;
  for (char c : subject)
    if (std::isdigit(static_cast<unsigned char>(c))) digits += c;
  if (!digits.empty() && digits.size() < 18) return std::stoull(digits);
  return text_seed(subject);
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
  // One series made, then copied: QUEST+'s likelihood table is shared, not rebuilt per condition.
  const stair_series first(p);
  stairs_.assign(p.conditions.size(), first);
  seed_ = stream_seed(p.seed, subject_number(subject), 0x5e55);
}

trial_plan stair_session::next() const {
  trial_plan t;
  t.index = trials_;
  t.condition = order_[current_];
  const stair_series& s = stairs_[t.condition];
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

nlohmann::json trial_record(const stair_protocol& p, const trial_plan& t, bool detected, const staircase::step& step) {
  nlohmann::json j = {{"type", "trial"},
                      {"index", t.index},
                      {"condition", p.conditions[t.condition].name},
                      {"series_trial", t.series_trial},
                      {"scale", t.scale},
                      {"catch", t.is_catch},
                      {"fixation", {t.fixation_x, t.fixation_y}},
                      {"detected", detected},
                      {"reversal", step.reversal},
                      {"recorded", step.recorded},
                      {"threshold", step.recorded ? nlohmann::json(step.threshold) : nlohmann::json(nullptr)}};
  if (p.procedure != stair_procedure::up_down && !t.is_catch)  // the posterior after this answer
    j["estimate"] = {{"threshold", step.posterior.estimate}, {"interval", {step.posterior.lo, step.posterior.hi}}};
  if (p.mode == stair_mode::two_afc) j["foveated_interval"] = t.foveated_interval + 1;
  return j;
}

namespace {

using json = nlohmann::json;

// Checks one record's fields against what trial_record and run_session write.
class record_check {
 public:
  record_check(const json& j, const std::string& path, int line) : j_(j), path_(path), line_(line) {}
  [[noreturn]] void fail(const std::string& why) const { throw std::runtime_error(fmt::format("{}:{}: {}", path_, line_, why)); }
  const json& field(const char* key) const {
    const auto it = j_.find(key);
    if (it == j_.end()) fail(fmt::format("no \"{}\"", key));
    return *it;
  }
  std::string text(const char* key) const {
    const json& v = field(key);
    if (!v.is_string()) fail(fmt::format("\"{}\" must be a string", key));
    return v.get<std::string>();
  }
  bool flag(const char* key) const {
    const json& v = field(key);
    if (!v.is_boolean()) fail(fmt::format("\"{}\" must be true or false", key));
    return v.get<bool>();
  }
  uint64_t count(const char* key) const {
    const json& v = field(key);
    if (!v.is_number_unsigned()) fail(fmt::format("\"{}\" must be a non-negative integer", key));
    return v.get<uint64_t>();
  }
  double number(const char* key) const {
    const json& v = field(key);
    if (!v.is_number() || !std::isfinite(v.get<double>())) fail(fmt::format("\"{}\" must be a number", key));
    return v.get<double>();
  }

 private:
  const json& j_;
  const std::string& path_;
  int line_;
};

}  // namespace

session_data read_session(const std::string& path) {
  std::istringstream in(read_input_file(path, max_session_bytes, "session file"));
  session_data out;
  std::string line;
  int number = 0;
  std::optional<stair_protocol> protocol;
  std::optional<stair_session> state;
  int end_line = 0;
  while (std::getline(in, line)) {
    ++number;
    if (in.eof()) {  // no newline: a torn last line, never a complete record
      if (number == 1) throw std::runtime_error(fmt::format("{}:1: the header line is incomplete (a torn write); not a session", path));
      break;
    }
    json j;
    try {
      j = json::parse(line);
    } catch (const json::exception&) {
      throw std::runtime_error(fmt::format("{}:{}: not a JSON record", path, number));
    }
    const record_check r(j, path, number);
    if (!j.is_object()) r.fail("not a JSON object (a record is {\"type\": ...})");
    const auto type_it = j.find("type");
    if (type_it == j.end() || !type_it->is_string()) {
      if (number == 1) r.fail("not a fovstair session (no header)");
      r.fail("a record needs \"type\": a string");
    }
    const std::string type = type_it->get<std::string>();
    if (number == 1) {
      if (type != "session") r.fail("not a fovstair session (no header)");
      const std::string subject = r.text("subject");
      r.text("session");
      if (j.contains("observer") && !j["observer"].is_null()) {
        try {
          parse_observer(r.text("observer"));
        } catch (const std::invalid_argument& e) {
          r.fail(fmt::format("observer {}", e.what()));
        }
      }
      protocol.emplace(parse_protocol(r.text("protocol_text"), path + " (stored protocol)"));
      state.emplace(*protocol, subject);
      out.header = std::move(j);
      continue;
    }
    if (end_line) r.fail(fmt::format("a record after the end record (line {})", end_line));
    if (type == "end") {
      if (!state->finished())
        r.fail(fmt::format("the end record comes after {} trials; the protocol's plan has more", state->trials()));
      end_line = number, out.ended = true;
      continue;
    }
    if (type == "practice") {  // before the first trial only; no procedure sees it
      if (state->trials() > 0 || !out.repeats.empty()) r.fail("a practice trial after the session's first trial");
      if (r.count("index") != out.practice.size())
        r.fail(fmt::format("practice trial index {}, expected {}", r.count("index"), out.practice.size()));
      const double scale = r.number("scale");
      if (!(scale >= protocol->scale_min && scale <= protocol->scale_max)) r.fail("a practice scale outside the protocol's range");
      r.flag("detected");
      out.practice.push_back(std::move(j));
      continue;
    }
    if (type == "repeat") {  // a trial shown again after broken fixation: it must be the one planned next
      if (state->finished()) r.fail("a repeated trial after the protocol's last");
      const trial_plan plan = state->next();
      if (r.count("index") != plan.index || r.text("condition") != protocol->conditions[plan.condition].name ||
          std::fabs(r.number("scale") - plan.scale) > 1e-9)
        r.fail(fmt::format("a repeated trial that is not the plan's next (trial {})", plan.index));
      r.flag("detected");
      out.repeats.push_back(std::move(j));
      continue;
    }
    if (type != "trial") r.fail(fmt::format("unknown record type '{}'", printable(type)));
    // The trial must be the one the stored protocol plans next, and record what the rule
    // did with its answer: a duplicated, missing or spliced trial is refused here.
    if (state->finished()) r.fail("a trial after the protocol's last");
    const trial_plan plan = state->next();
    const stair_protocol& p = *protocol;
    if (r.count("index") != plan.index) r.fail(fmt::format("trial index {}, the plan's next is {}", r.count("index"), plan.index));
    if (r.text("condition") != p.conditions[plan.condition].name)
      r.fail(fmt::format("condition '{}', the plan's next is '{}'", printable(r.text("condition")),
                         printable(p.conditions[plan.condition].name)));
    if (std::fabs(r.number("scale") - plan.scale) > 1e-9 || r.flag("catch") != plan.is_catch ||
        r.count("series_trial") != plan.series_trial)
      r.fail(fmt::format("trial {} does not match the protocol's plan (scale {}, catch {})", plan.index, plan.scale,
                         plan.is_catch));
    const bool two_afc = p.mode == stair_mode::two_afc;
    if (two_afc != j.contains("foveated_interval") ||
        (two_afc && (!j["foveated_interval"].is_number_unsigned() ||
                     j["foveated_interval"].get<uint64_t>() != plan.foveated_interval + 1)))
      r.fail(fmt::format("foveated_interval does not match a {} protocol's plan", two_afc ? "2afc" : "yes-no"));
    const staircase::step step = state->record(plan, r.flag("detected"));
    const json& threshold = r.field("threshold");
    if (r.flag("reversal") != step.reversal || r.flag("recorded") != step.recorded ||
        (step.recorded ? !threshold.is_number() || std::fabs(threshold.get<double>() - step.threshold) > 1e-9
                       : !threshold.is_null()))
      r.fail(fmt::format("trial {}: reversal, recorded and threshold are not what the rule gives", plan.index));
    if (step.bayesian) {  // the stored posterior must be the one the answers give (to 1e-6: libm may differ)
      const json& e = r.field("estimate");
      auto near = [](const json& v, double want) { return v.is_number() && std::fabs(v.get<double>() - want) <= 1e-6 * std::fabs(want); };
      if (!e.is_object() || !near(e.value("threshold", json()), step.posterior.estimate) || !e.contains("interval") ||
          !e["interval"].is_array() || e["interval"].size() != 2 || !near(e["interval"][0], step.posterior.lo) ||
          !near(e["interval"][1], step.posterior.hi))
        r.fail(fmt::format("trial {}: the estimate is not the posterior the answers give", plan.index));
    } else if (j.contains("estimate")) {
      r.fail(fmt::format("trial {}: an estimate where the procedure gives none (an up-down series or a catch trial)", plan.index));
    }
    out.trials.push_back(std::move(j));
  }
  if (number == 0) throw std::runtime_error(fmt::format("{}: empty session file", path));
  return out;
}

session_file session_file::resume(const std::string& path, const std::string& subject, nlohmann::json& header,
                                  std::vector<nlohmann::json>& trials) {
  session_data d = read_session(path);
  // Refused before the file is touched: the torn last line stays for its own subject.
  if (d.header.at("subject") != subject)
    throw std::runtime_error(fmt::format("{}: belongs to subject {}", path, printable(d.header.at("subject").get<std::string>())));
  if (d.ended) throw std::runtime_error(fmt::format("{}: the session is finished; nothing to resume", path));
  session_file f(line_log(path, line_log::mode::open_existing));  // cuts a torn last line
  header = d.header;
  trials = std::move(d.trials);
  return f;
}

void session_file::append(const nlohmann::json& record) { log_.append_line(record.dump()); }

}  // namespace fov
