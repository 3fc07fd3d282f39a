#include "protocol.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "fov/files.h"
#include "fov/json_scan.h"
#include "fov/knn_table.h"
#include "simulation.h"

namespace fov {

namespace {

using json = nlohmann::json;

// The line each value starts on, by JSON pointer ("/conditions/1/k"), from a scan of
// the text (nlohmann's parser keeps no positions). Run only on text that parsed.
class line_map {
 public:
  explicit line_map(const std::string& text) : s_(text) {
    skip();
    value("");
  }
  int line(const std::string& pointer) const {
    for (std::string p = pointer;; p = p.substr(0, p.rfind('/'))) {
      const auto it = lines_.find(p);
      if (it != lines_.end()) return it->second;
      if (p.empty()) return 1;
    }
  }

 private:
  const std::string& s_;
  size_t at_ = 0;
  int line_ = 1;
  std::map<std::string, int> lines_;

  void advance() {
    if (s_[at_] == '\n') ++line_;
    ++at_;
  }
  void skip() {
    while (at_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[at_]))) advance();
  }
  std::string string() {  // at the opening quote
    advance();
    std::string out;
    while (at_ < s_.size() && s_[at_] != '"') {
      if (s_[at_] == '\\') advance();
      out += s_[at_];
      advance();
    }
    advance();
    return out;
  }
  void value(const std::string& pointer) {
    lines_[pointer] = line_;
    if (at_ >= s_.size()) return;
    if (s_[at_] == '{') {
      advance();
      skip();
      while (at_ < s_.size() && s_[at_] != '}') {
        const std::string key = string();
        skip();
        advance();  // ':'
        skip();
        value(pointer + "/" + key);
        skip();
        if (s_[at_] == ',') advance(), skip();
      }
      advance();
    } else if (s_[at_] == '[') {
      advance();
      skip();
      for (int i = 0; at_ < s_.size() && s_[at_] != ']'; ++i) {
        value(pointer + "/" + std::to_string(i));
        skip();
        if (s_[at_] == ',') advance(), skip();
      }
      advance();
    } else if (s_[at_] == '"') {
      string();
    } else {
      while (at_ < s_.size() && !std::strchr(",]} \t\r\n", s_[at_])) advance();
    }
  }
};

// Reads typed fields of one object, rejecting unknown keys and wrong types with the line.
class reader {
 public:
  reader(const json& j, std::string pointer, const line_map& lines, const std::string& file)
      : j_(j), pointer_(std::move(pointer)), lines_(lines), file_(file) {
    if (!j_.is_object()) fail(pointer_, "must be an object");
  }
  [[noreturn]] void fail(const std::string& pointer, const std::string& why) const {
    throw protocol_error(fmt::format("{}:{}: {}: {}", file_, lines_.line(pointer), printable(where(pointer), 80), why));
  }
  std::string at(const std::string& key) const { return pointer_ + "/" + key; }
  bool has(const std::string& key) { known_.insert(key); return j_.contains(key); }
  const json& raw(const std::string& key) { known_.insert(key); return j_.at(key); }

  template <class T>
  void get(const std::string& key, T& out) {
    if (!has(key)) return;
    const json& v = j_.at(key);
    if constexpr (std::is_same_v<T, bool>) {
      if (!v.is_boolean()) fail(at(key), "must be true or false");
      out = v.get<bool>();
    } else if constexpr (std::is_same_v<T, std::string>) {
      if (!v.is_string()) fail(at(key), "must be a string");
      out = v.get<std::string>();
    } else if constexpr (std::is_integral_v<T>) {
      // Read whole, not cast: 4294967301 must not become 5.
      if (!v.is_number_unsigned() || v.get<uint64_t>() > std::numeric_limits<T>::max())
        fail(at(key), fmt::format("must be an integer in 0..{}", std::numeric_limits<T>::max()));
      out = T(v.get<uint64_t>());
    } else {
      if (!v.is_number() || !std::isfinite(v.get<double>())) fail(at(key), "must be a number");
      out = v.get<double>();
    }
  }
  void no_unknown_keys() const {
    for (const auto& [key, value] : j_.items())
      if (!known_.count(key)) fail(at(key), "unknown key (see docs/fovstair.md)");
  }

 private:
  const json& j_;
  std::string pointer_;
  const line_map& lines_;
  const std::string& file_;
  std::set<std::string> known_;

  static std::string where(const std::string& pointer) {  // "/conditions/1/k" -> "conditions[1].k"
    std::string out;
    std::stringstream in(pointer);
    std::string part;
    std::getline(in, part, '/');
    while (std::getline(in, part, '/')) {
      if (!part.empty() && std::all_of(part.begin(), part.end(), ::isdigit)) out += "[" + part + "]";
      else out += (out.empty() ? "" : ".") + part;
    }
    return out.empty() ? "protocol" : out;
  }
};

// The line of the first number that overflows a double (1 if none does).
int overflow_line(const std::string& text) {
  int found = 1;
  size_t after = 0;  // the end of the number last read: each is read once, whole
  outside_json_strings(text, [&](size_t i, int line) {
    if (i < after || (text[i] != '-' && !std::isdigit(static_cast<unsigned char>(text[i])))) return true;
    size_t j = i;
    while (j < text.size() && std::strchr("+-.0123456789eE", text[j])) ++j;
    after = j;
    if (!std::isinf(std::strtod(text.substr(i, j - i).c_str(), nullptr))) return true;
    found = line;
    return false;
  });
  return found;
}

// A non-empty list of at most `most` numbers, each in [lo, hi].
std::vector<double> number_list(reader& r, const std::string& key, double lo, double hi, size_t most) {
  const json& v = r.raw(key);
  const std::string at = r.at(key);
  if (!v.is_array() || v.empty() || v.size() > most) r.fail(at, fmt::format("must be a list of 1 to {} numbers", most));
  std::vector<double> out;
  for (size_t i = 0; i < v.size(); ++i) {
    if (!v[i].is_number() || !(v[i].get<double>() >= lo && v[i].get<double>() <= hi))
      r.fail(at + "/" + std::to_string(i), fmt::format("must be a number in [{}, {}]", lo, hi));
    out.push_back(v[i].get<double>());
  }
  return out;
}

void parse_quest(reader r, stair_protocol& p, bool two_afc) {
  quest_params& q = p.quest;
  r.get("threshold_guess", q.threshold_guess);
  r.get("guess_sd", q.guess_sd);
  r.get("p_threshold", q.p_threshold);
  r.get("beta", q.beta);
  r.get("delta", q.delta);
  r.get("gamma", q.gamma);
  r.get("grain", q.grain);
  r.get("range", q.range);
  std::string method = label_of(quest_method_labels, q.method);
  r.get("method", method);
  r.get("max_trials", q.max_trials);
  r.get("stop_interval", q.stop_interval);
  r.no_unknown_keys();
  if (!(q.threshold_guess == 0 || (q.threshold_guess >= p.scale_min && q.threshold_guess <= p.scale_max)))
    r.fail("/quest/threshold_guess", "must lie in the scale range, or be 0 for its geometric middle");
  if (!(q.guess_sd >= 0 && q.guess_sd <= 10)) r.fail("/quest/guess_sd", "must lie in (0, 10] log10 units, or be 0 for the range's");
  if (!(q.beta > 0 && q.beta <= 100)) r.fail("/quest/beta", "must lie in (0, 100]");
  if (!(q.delta >= 0 && q.delta <= 0.5)) r.fail("/quest/delta", "must lie in [0, 0.5]");
  if (!(q.gamma == -1 || (q.gamma >= 0 && q.gamma < 1))) r.fail("/quest/gamma", "must lie in [0, 1)");
  const double gamma = q.gamma >= 0 ? q.gamma : default_guess_rate(two_afc);
  const double top = q.delta * gamma + (1 - q.delta);
  if (!(q.p_threshold > gamma && q.p_threshold < top))
    r.fail("/quest/p_threshold", fmt::format("must lie strictly between gamma ({}) and 1 - delta (1 - gamma) ({})", gamma, top));
  if (!(q.grain >= 0.001 && q.grain <= 0.1)) r.fail("/quest/grain", "must lie in [0.001, 0.1] log10 units");
  if (!(q.range > 0 && q.range <= 10)) r.fail("/quest/range", "must lie in (0, 10] log10 units");
  if (q.range / q.grain > max_quest_grid) r.fail("/quest/range", fmt::format("range / grain must be at most {}", max_quest_grid));
  if (!parse_label(quest_method_labels, method, q.method)) r.fail("/quest/method", "must be " + label_alternatives(quest_method_labels));
  if (q.max_trials < 1 || q.max_trials > max_protocol_series_trials)
    r.fail("/quest/max_trials", fmt::format("must lie in 1..{}", max_protocol_series_trials));
  if (!(q.stop_interval >= 0 && q.stop_interval <= 10)) r.fail("/quest/stop_interval", "must lie in [0, 10] log10 units (0: off)");
}

void parse_quest_plus(reader r, stair_protocol& p, bool two_afc) {
  quest_plus_params& q = p.quest_plus;
  if (r.has("thresholds")) q.thresholds = number_list(r, "thresholds", 0.01, 100, max_quest_grid);
  if (r.has("slopes")) q.slopes = number_list(r, "slopes", 0.01, 100, 1000);
  if (r.has("lower_asymptotes")) q.lower_asymptotes = number_list(r, "lower_asymptotes", 0, 0.99, 1000);
  if (r.has("lapse_rates")) q.lapse_rates = number_list(r, "lapse_rates", 0, 0.5, 1000);
  std::string estimate = label_of(quest_plus_estimate_labels, q.estimate);
  r.get("estimate", estimate);
  r.get("max_trials", q.max_trials);
  r.get("stop_interval", q.stop_interval);
  r.no_unknown_keys();
  if (!parse_label(quest_plus_estimate_labels, estimate, q.estimate))
    r.fail("/quest_plus/estimate", "must be " + label_alternatives(quest_plus_estimate_labels));
  if (q.max_trials < 1 || q.max_trials > max_protocol_series_trials)
    r.fail("/quest_plus/max_trials", fmt::format("must lie in 1..{}", max_protocol_series_trials));
  if (!(q.stop_interval >= 0 && q.stop_interval <= 10))
    r.fail("/quest_plus/stop_interval", "must lie in [0, 10] log10 units (0: off)");
  const double highest_gamma = q.lower_asymptotes.empty() ? default_guess_rate(two_afc)
                                                          : *std::max_element(q.lower_asymptotes.begin(), q.lower_asymptotes.end());
  if (highest_gamma + *std::max_element(q.lapse_rates.begin(), q.lapse_rates.end()) >= 1)
    r.fail("/quest_plus/lapse_rates", "every lower asymptote + lapse rate must stay below 1");
}

// The QUEST+ likelihood table's size, checked with or without a quest_plus block (its
// defaults over a fine scales.grid can exceed it too): "" or why it is refused.
std::string quest_plus_table_problem(const stair_protocol& p) {
  const quest_plus_params& q = p.quest_plus;
  const uint64_t stimuli = procedure_grid(p.scale_min, p.scale_max, p.scale_grid).size();
  const uint64_t params = uint64_t(q.thresholds.empty() ? stimuli : q.thresholds.size()) * q.slopes.size() *
                          std::max<size_t>(1, q.lower_asymptotes.size()) * q.lapse_rates.size();
  if (stimuli * params <= max_quest_plus_table) return "";
  return fmt::format("{} scales x {} parameter combinations = {} likelihoods; at most {} (so that no trial waits on the "
                     "entropy search): coarsen scales.grid or the parameter lists",
                     stimuli, params, stimuli * params, max_quest_plus_table);
}

}  // namespace

stair_protocol parse_protocol(const std::string& text, const std::string& file) {
  // Nesting is bounded before anything walks the text: the line map recurses per level.
  if (const int line = json_too_deep_line(text, max_protocol_depth))
    throw protocol_error(fmt::format("{}:{}: nested deeper than {} levels", file, line, max_protocol_depth));
  json j;
  try {
    j = json::parse(text);
  } catch (const json::parse_error& e) {
    int line = 1;
    for (size_t i = 0; i < std::min<size_t>(e.byte, text.size()); ++i) line += text[i] == '\n';
    std::string why = e.what();
    if (const size_t colon = why.rfind(": "); colon != std::string::npos) why = why.substr(colon + 2);
    throw protocol_error(fmt::format("{}:{}: not valid JSON: {}", file, line, why));
  } catch (const json::exception&) {  // a number beyond double's range (1e400): no position given
    throw protocol_error(fmt::format("{}:{}: a number beyond the range of a double", file, overflow_line(text)));
  }
  const line_map lines(text);
  reader top(j, "", lines, file);
  stair_protocol p;
  uint32_t version = 0;
  top.get("fovstair_protocol", version);
  if (version != 1) top.fail("/fovstair_protocol", "must be 1 (the schema version this fovstair reads)");
  top.get("name", p.name);
  top.get("description", p.description);
  top.get("scene", p.scene);
  top.get("points_dir", p.points_dir);
  top.get("display", p.display);
  if (display_geometry d; !parse_display(p.display, d).empty()) top.fail("/display", parse_display(p.display, d));
  top.get("spp", p.spp);
  if (p.spp < 1 || p.spp > 1024) top.fail("/spp", "must lie in 1..1024");
  top.get("taa", p.taa);
  top.get("hfov", p.hfov);
  if (p.hfov < 0 || p.hfov >= 180) top.fail("/hfov", "must lie in (0, 180) degrees, or 0 for the scene's");
  std::string integrator_label = label_of(integrator_labels, p.method);
  top.get("integrator", integrator_label);
  if (!parse_label(integrator_labels, integrator_label, p.method))
    top.fail("/integrator", "must be " + label_alternatives(integrator_labels));
  top.get("bounces", p.bounces);
  if (p.bounces > max_bounces) top.fail("/bounces", fmt::format("must lie in 0..{}", max_bounces));
  top.get("env_light", p.env_light);
  top.get("order", p.order);
  if (p.order != "latin-square" && p.order != "fixed" && p.order != "random")
    top.fail("/order", "must be latin-square, fixed or random");
  std::string mode = "yes-no";
  top.get("mode", mode);
  if (mode == "yes-no") p.mode = stair_mode::yes_no;
  else if (mode == "2afc") p.mode = stair_mode::two_afc;
  else top.fail("/mode", "must be yes-no or 2afc");
  top.get("catch_rate", p.catch_rate);
  if (!(p.catch_rate >= 0 && p.catch_rate <= max_protocol_catch_rate))
    top.fail("/catch_rate", fmt::format("must lie in [0, {}]", max_protocol_catch_rate));
  top.get("interval_ms", p.interval_ms);
  if (!(p.interval_ms > 0 && p.interval_ms <= max_protocol_interval_ms))
    top.fail("/interval_ms", fmt::format("must lie in (0, {}] milliseconds", max_protocol_interval_ms));
  top.get("break_every", p.break_every);
  top.get("seed", p.seed);

  if (!top.has("conditions")) top.fail("", "needs \"conditions\": a list of {name, method, k}");
  const json& conditions = top.raw("conditions");
  if (!conditions.is_array() || conditions.empty()) top.fail("/conditions", "must be a non-empty list");
  if (conditions.size() > max_protocol_conditions)
    top.fail("/conditions", fmt::format("{} conditions; a protocol may have at most {}", conditions.size(), max_protocol_conditions));
  std::set<std::string> names;
  for (size_t i = 0; i < conditions.size(); ++i) {
    const std::string at = "/conditions/" + std::to_string(i);
    reader r(conditions[i], at, lines, file);
    stair_condition c;
    r.get("name", c.name);
    if (c.name.empty()) r.fail(at, "needs a \"name\"");
    if (!names.insert(c.name).second) r.fail(at + "/name", "repeats an earlier condition's name");
    std::string method_text = method_name(c.reconstruct.how);
    r.get("method", method_text);
    if (!parse_label(method_labels, method_text, c.reconstruct.how))
      r.fail(at + "/method", "must be " + label_alternatives(method_labels));
    r.get("k", c.reconstruct.k);
    if (c.reconstruct.k < 1 || c.reconstruct.k > max_knn) r.fail(at + "/k", fmt::format("must lie in 1..{}", max_knn));
    r.get("renka", c.reconstruct.renka);
    std::string kernel = label_of(rbf_kernel_labels, c.reconstruct.kernel);
    r.get("rbf_kernel", kernel);
    if (!parse_label(rbf_kernel_labels, kernel, c.reconstruct.kernel))
      r.fail(at + "/rbf_kernel", "must be " + label_alternatives(rbf_kernel_labels));
    r.get("rbf_shape", c.reconstruct.shape);
    if (!(c.reconstruct.shape > 0)) r.fail(at + "/rbf_shape", "must be positive");
    r.get("spp", c.spp);
    if (c.spp > 1024) r.fail(at + "/spp", "must lie in 1..1024, or 0 for the protocol's");
    r.no_unknown_keys();
    p.conditions.push_back(c);
  }

  if (top.has("scales")) {
    reader r(top.raw("scales"), "/scales", lines, file);
    r.get("min", p.scale_min);
    r.get("max", p.scale_max);
    p.scale_start = p.scale_min;
    r.get("start", p.scale_start);
    r.get("grid", p.scale_grid);
    r.no_unknown_keys();
    if (!(p.scale_min >= 0.5 && p.scale_min < p.scale_max)) r.fail("/scales/min", "must be >= 0.5 and below max");
    if (!(p.scale_max <= max_protocol_scale)) r.fail("/scales/max", fmt::format("must be at most {}", max_protocol_scale));
    if (!(p.scale_start >= p.scale_min && p.scale_start <= p.scale_max)) r.fail("/scales/start", "must lie in [min, max]");
    if (!(p.scale_grid >= 0.01 && p.scale_grid <= p.scale_max - p.scale_min) ||
        std::fabs(p.scale_grid * 100 - std::round(p.scale_grid * 100)) > 1e-6)
      r.fail("/scales/grid", "must be a multiple of 0.01 between 0.01 and max - min");
  }
  std::string procedure = label_of(stair_procedure_labels, p.procedure);
  top.get("procedure", procedure);
  if (!parse_label(stair_procedure_labels, procedure, p.procedure))
    top.fail("/procedure", "must be " + label_alternatives(stair_procedure_labels));
  // Settings of a procedure the protocol does not use are refused, not ignored.
  for (const auto& [key, used] : {std::pair<const char*, stair_procedure>{"rule", stair_procedure::up_down},
                                  {"quest", stair_procedure::quest}, {"quest_plus", stair_procedure::quest_plus}})
    if (top.has(key) && p.procedure != used)
      top.fail(std::string("/") + key, fmt::format("settings for procedure {}, but the protocol's procedure is {}",
                                                   label_of(stair_procedure_labels, used), procedure));
  const bool two_afc = p.mode == stair_mode::two_afc;
  if (top.has("quest")) parse_quest(reader(top.raw("quest"), "/quest", lines, file), p, two_afc);
  if (top.has("quest_plus")) parse_quest_plus(reader(top.raw("quest_plus"), "/quest_plus", lines, file), p, two_afc);
  if (p.procedure == stair_procedure::quest_plus)
    if (const std::string why = quest_plus_table_problem(p); !why.empty())
      top.fail(top.has("quest_plus") ? "/quest_plus" : "/procedure", why);
  // In 2AFC the default rule is 1-up/3-down (79.4 % correct): 1-up/1-down would converge
  // on 50 % correct, which is chance.
  if (two_afc) p.rule.down = 3;
  if (top.has("rule")) {
    reader r(top.raw("rule"), "/rule", lines, file);
    stair_rule& s = p.rule;
    r.get("up", s.up);
    r.get("down", s.down);
    r.get("initial_step", s.initial_step);
    r.get("step", s.step);
    r.get("discard_reversals", s.discard_reversals);
    r.get("thresholds", s.thresholds);
    r.get("max_trials", s.max_trials);
    r.no_unknown_keys();
    if (s.up < 1 || s.up > 4) r.fail("/rule/up", "must lie in 1..4");
    if (s.down < 1 || s.down > 4) r.fail("/rule/down", "must lie in 1..4");
    if (!(s.step >= 0.01)) r.fail("/rule/step", "must be at least 0.01");
    if (!(s.initial_step >= s.step)) r.fail("/rule/initial_step", "must be at least step");
    if (!(s.initial_step <= max_protocol_scale))
      r.fail("/rule/initial_step", fmt::format("must be at most {}", max_protocol_scale));
    if (s.thresholds < 1 || s.thresholds > max_protocol_thresholds)
      r.fail("/rule/thresholds", fmt::format("must lie in 1..{}", max_protocol_thresholds));
    if (s.discard_reversals > max_protocol_thresholds)
      r.fail("/rule/discard_reversals", fmt::format("must lie in 0..{}", max_protocol_thresholds));
    if (s.max_trials < s.thresholds || s.max_trials > max_protocol_series_trials)
      r.fail("/rule/max_trials", fmt::format("must lie in thresholds..{}", max_protocol_series_trials));
    if (two_afc && levitt_target_probability(s.up, s.down) < 0.5 + 1e-6)
      r.fail("/rule", fmt::format("a {}-up/{}-down rule converges on {:.0f} % correct, at or below chance in 2AFC: use more "
                                  "down than up steps (1-up/3-down, 79.4 %, is usual)",
                                  s.up, s.down, 100 * levitt_target_probability(s.up, s.down)));
  }
  auto on_grid = [](double v, double unit) { return std::fabs(v / unit - std::round(v / unit)) < 1e-6; };
  if (!on_grid(p.rule.step, 0.01) || !on_grid(p.rule.initial_step, 0.01))
    top.fail("/rule", "steps must be multiples of 0.01 (point sets are named by scale to 2 decimals)");
  if (top.has("fixations")) {
    const json& f = top.raw("fixations");
    if (!f.is_array() || f.empty()) top.fail("/fixations", "must be a non-empty list of [x, y] in 0..1");
    p.fixations.clear();
    for (size_t i = 0; i < f.size(); ++i) {
      const std::string at = "/fixations/" + std::to_string(i);
      if (!f[i].is_array() || f[i].size() != 2 || !f[i][0].is_number() || !f[i][1].is_number())
        top.fail(at, "must be [x, y] (normalised screen coordinates)");
      const double x = f[i][0].get<double>(), y = f[i][1].get<double>();
      if (!(x >= 0 && x <= 1 && y >= 0 && y <= 1)) top.fail(at, "must lie in 0..1 (normalised screen coordinates)");
      p.fixations.emplace_back(x, y);
    }
  }
  if (top.has("instructions")) {
    const json& v = top.raw("instructions");
    if (!v.is_array() || v.empty() || v.size() > 20) top.fail("/instructions", "must be a list of 1 to 20 lines of text");
    for (size_t i = 0; i < v.size(); ++i) {
      if (!v[i].is_string() || v[i].get<std::string>().size() > 300)
        top.fail("/instructions/" + std::to_string(i), "must be a line of text of at most 300 characters");
      p.instructions.push_back(v[i].get<std::string>());
    }
  }
  top.get("question", p.question);
  if (p.question.size() > 300) top.fail("/question", "must be at most 300 characters");
  if (top.has("practice")) {
    reader r(top.raw("practice"), "/practice", lines, file);
    r.get("trials", p.practice.trials);
    if (r.has("scales")) p.practice.scales = number_list(r, "scales", p.scale_min, p.scale_max, 100);
    r.get("feedback", p.practice.feedback);
    r.no_unknown_keys();
    if (p.practice.trials > 100) r.fail("/practice/trials", "must lie in 0..100");
    const std::vector<double> reachable = reachable_scales(p);
    for (size_t i = 0; i < p.practice.scales.size(); ++i)
      if (std::none_of(reachable.begin(), reachable.end(), [&](double s) { return std::fabs(s - p.practice.scales[i]) < 1e-9; }))
        r.fail("/practice/scales/" + std::to_string(i), "must be a scale the protocol's sets cover (validate lists them)");
  }
  if (top.has("fixation_control")) {
    reader r(top.raw("fixation_control"), "/fixation_control", lines, file);
    r.get("radius_deg", p.fixation.radius_deg);
    std::string action = label_of(fixation_action_labels, p.fixation.action);
    r.get("action", action);
    r.get("max_repeats", p.fixation.max_repeats);
    r.no_unknown_keys();
    if (!(p.fixation.radius_deg >= 0 && p.fixation.radius_deg <= 90))
      r.fail("/fixation_control/radius_deg", "must lie in [0, 90] degrees (0: off)");
    if (!parse_label(fixation_action_labels, action, p.fixation.action))
      r.fail("/fixation_control/action", "must be " + label_alternatives(fixation_action_labels));
    if (p.fixation.max_repeats > 100) r.fail("/fixation_control/max_repeats", "must lie in 0..100");
  }
  top.no_unknown_keys();
  return p;
}

std::vector<std::string> instruction_lines(const stair_protocol& p) {
  if (!p.instructions.empty()) return p.instructions;
  if (p.mode == stair_mode::two_afc)
    return {"Look at the cross. Two images follow, one after the other; keep your eyes where the cross was.",
            "One of them is rendered with fewer samples away from where you look.",
            "After both, press 1 or 2 for the one that was. If unsure, guess.", "Esc pauses.", "Press Space to begin."};
  return {"Look at the cross. An image follows; keep your eyes where the cross was.",
          "Does anything in it look unnatural: blur, flicker, blocks, missing detail?",
          "Press Y for yes or N for no.", "Esc pauses.", "Press Space to begin."};
}

std::string question_text(const stair_protocol& p) {
  if (!p.question.empty()) return p.question;
  return p.mode == stair_mode::two_afc ? "Which interval was foveated? Press 1 or 2." : "Anything unnatural? Y or N.";
}

double practice_scale(const stair_protocol& p, uint32_t i) {
  return p.practice.scales.empty() ? p.scale_max : p.practice.scales[i % p.practice.scales.size()];
}

double sweep_step(const stair_protocol& p) { return p.procedure == stair_procedure::up_down ? p.rule.step : p.scale_grid; }

stair_protocol load_protocol(const std::string& path) {
  return parse_protocol(read_protocol_text(path), path);
}

std::string read_protocol_text(const std::string& path) {
  try {
    return read_input_file(path, max_protocol_bytes, "protocol file");
  } catch (const file_error& e) {
    throw protocol_error(e.what());
  }
}

std::vector<double> reachable_scales(const stair_protocol& p) {
  if (p.procedure != stair_procedure::up_down) return procedure_grid(p.scale_min, p.scale_max, p.scale_grid);
  std::set<long> hundredths;
  const long lo = std::lround(p.scale_min * 100), hi = std::lround(p.scale_max * 100);
  const long start = std::lround(p.scale_start * 100);
  const long big = std::lround(p.rule.initial_step * 100), small = std::lround(p.rule.step * 100);
  hundredths.insert(lo), hundredths.insert(hi);
  // Initial steps from the start in both directions, then fine steps from any of those.
  std::vector<long> seeds;
  for (long v = start; v >= lo; v -= big) seeds.push_back(v);
  for (long v = start; v <= hi; v += big) seeds.push_back(v);
  seeds.push_back(lo), seeds.push_back(hi);  // clamped moves land on the ends
  for (long s : seeds)
    for (long v = s % small; v <= hi; v += small)
      if (v >= lo) hundredths.insert(v);
  std::vector<double> out;
  for (long h : hundredths) out.push_back(h / 100.0);
  return out;
}

std::string pointset_path(const stair_protocol& p, double scale) {
  spacing_model model;
  if (const std::string why = parse_display(p.display, model.display); !why.empty()) throw std::runtime_error("display: " + why);
  model.scale = scale;
  return p.points_dir + "/" + pointset_file_name(model, dart_params{});
}

render_params stimulus_params(const stair_protocol& p, const stair_condition& c) {
  render_params r;
  r.reconstruct = c.reconstruct;
  r.spp = c.spp ? c.spp : p.spp;
  r.taa = p.taa;
  r.view.hfov_deg = float(p.hfov);
  r.method = p.method;
  r.bounces = p.bounces;
  r.env_light = p.env_light;
  return r;
}

}  // namespace fov
