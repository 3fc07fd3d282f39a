#include "analysis.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <tuple>
#include <set>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "fov/files.h"

namespace fov {

std::vector<threshold_value> read_thresholds_csv(const std::string& path) {
  std::istringstream in(read_input_file(path, max_thresholds_bytes, "thresholds CSV"));
  std::set<std::string> conditions;
  std::string line;
  if (!std::getline(in, line)) throw std::runtime_error(fmt::format("{}: empty file", path));
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (line != "subject,condition,threshold")
    throw std::runtime_error(fmt::format("{}:1: the header must be subject,condition,threshold", path));
  std::vector<threshold_value> out;
  for (int number = 2; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    std::stringstream row(line);
    threshold_value v;
    std::string value;
    if (!std::getline(row, v.subject, ',') || !std::getline(row, v.condition, ',') || !std::getline(row, value) ||
        v.subject.empty() || v.condition.empty())
      throw std::runtime_error(fmt::format("{}:{}: expected subject,condition,threshold", path, number));
    try {
      size_t used = 0;
      v.threshold = std::stod(value, &used);
      if (used != value.size()) throw std::invalid_argument("");
    } catch (const std::exception&) {
      throw std::runtime_error(fmt::format("{}:{}: threshold '{}' is not a number", path, number, value));
    }
    if (!(v.threshold > 0) || !std::isfinite(v.threshold))
      throw std::runtime_error(fmt::format("{}:{}: threshold must be positive (the analysis takes logs)", path, number));
    if (conditions.insert(v.condition).second && conditions.size() > max_threshold_conditions)
      throw std::runtime_error(fmt::format("{}:{}: more than {} conditions (a protocol's most)", path, number,
                                           max_threshold_conditions));
    out.push_back(v);
  }
  if (out.empty()) throw std::runtime_error(fmt::format("{}: no threshold rows", path));
  return out;
}

void write_thresholds_csv(const std::vector<threshold_value>& values, const std::string& path) {
  std::string text = "subject,condition,threshold\n";
  for (const auto& v : values) text += fmt::format("{},{},{}\n", v.subject, v.condition, v.threshold);
  write_file_atomic(path, text.data(), text.size());
}

std::vector<threshold_value> thresholds_from_sessions(const std::vector<session_data>& sessions) {
  std::vector<threshold_value> out;
  for (const session_data& s : sessions)
    for (const auto& t : s.trials)
      if (t.value("recorded", false))
        out.push_back({s.header.value("subject", "?"), t.value("condition", "?"), t.value("threshold", 0.0)});
  return out;
}

std::vector<psychometric_data> psychometric_data_from_sessions(const std::vector<session_data>& sessions) {
  // subject -> (catch trials, false alarms) for yes-no guess rates.
  std::map<std::string, std::pair<uint32_t, uint32_t>> catches;
  std::map<std::tuple<std::string, std::string, bool>, std::map<long, psychometric_level>> cells;
  std::vector<std::tuple<std::string, std::string, bool>> order;
  for (const session_data& s : sessions) {
    const std::string subject = s.header.value("subject", "?");
    const stair_protocol p = parse_protocol(s.header.at("protocol_text").get<std::string>(), "stored protocol");  // checked
    const bool two_afc = p.mode == stair_mode::two_afc;
    for (const auto& t : s.trials) {
      const bool detected = t.value("detected", false);
      if (t.value("catch", false)) {
        if (!two_afc) ++catches[subject].first, catches[subject].second += detected;
        continue;
      }
      const auto key = std::make_tuple(subject, t.value("condition", "?"), two_afc);
      if (!cells.count(key)) order.push_back(key);
      const double scale = t.value("scale", 1.0);
      psychometric_level& l = cells[key][std::lround(scale * 100)];
      l.scale = std::round(scale * 100) / 100;
      ++l.n, l.k += detected;
    }
  }
  std::vector<psychometric_data> out;
  for (const auto& key : order) {
    psychometric_data d;
    std::tie(d.subject, d.condition, d.two_afc) = key;
    const auto c = catches[d.subject];
    d.catch_trials = d.two_afc ? 0 : c.first;
    d.guess = d.two_afc ? 0.5 : c.first ? std::min(0.5, double(c.second) / c.first) : 0.0;
    for (const auto& [hundredths, level] : cells[key]) d.levels.push_back(level);
    out.push_back(std::move(d));
  }
  return out;
}

std::string simulated_mix_warning(const std::vector<session_data>& sessions, const std::vector<std::string>& paths) {
  std::vector<std::string> simulated, people;
  for (size_t i = 0; i < sessions.size(); ++i) {
    const auto it = sessions[i].header.find("observer");
    (it != sessions[i].header.end() && !it->is_null() ? simulated : people).push_back(i < paths.size() ? paths[i] : "?");
  }
  if (simulated.empty() || people.empty()) return "";
  return fmt::format("{} session(s) answered by a simulated observer ({}{}) analysed together with {} of people",
                     simulated.size(), simulated.front(), simulated.size() > 1 ? ", ..." : "", people.size());
}

namespace {

// Continued fraction for I_x(a, b), modified Lentz's method.
double beta_fraction(double a, double b, double x) {
  constexpr double tiny = 1e-300;
  double c = 1, d = 1 - (a + b) * x / (a + 1);
  if (std::fabs(d) < tiny) d = tiny;
  d = 1 / d;
  double h = d;
  for (int m = 1; m < 500; ++m) {
    const double even = m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m));
    d = 1 + even * d;
    c = 1 + even / c;
    if (std::fabs(d) < tiny) d = tiny;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1 / d;
    h *= d * c;
    const double odd = -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1));
    d = 1 + odd * d;
    c = 1 + odd / c;
    if (std::fabs(d) < tiny) d = tiny;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1 / d;
    const double delta = d * c;
    h *= delta;
    if (std::fabs(delta - 1) < 1e-15) break;
  }
  return h;
}

}  // namespace

double incomplete_beta(double a, double b, double x) {
  if (x <= 0) return 0;
  if (x >= 1) return 1;
  const double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x));
  if (x < (a + 1) / (a + b + 2)) return front * beta_fraction(a, b, x) / a;
  return 1 - front * beta_fraction(b, a, 1 - x) / b;
}

double f_upper_tail(double f, double df1, double df2) {
  if (!(f > 0)) return 1;
  return incomplete_beta(df2 / 2, df1 / 2, df2 / (df2 + df1 * f));
}

double t_two_sided(double t, double df) { return incomplete_beta(df / 2, 0.5, df / (df + t * t)); }

threshold_analysis analyze_thresholds(const std::vector<threshold_value>& values) {
  threshold_analysis out;
  std::vector<std::string> names;
  for (const auto& v : values) {
    if (std::find(names.begin(), names.end(), v.condition) == names.end()) names.push_back(v.condition);
    out.values[v.subject][v.condition].push_back(v.threshold);
  }
  if (values.empty()) throw std::runtime_error("no thresholds to analyse");
  // Log subject means per condition.
  std::vector<std::vector<double>> logs(names.size());
  std::vector<std::map<std::string, double>> by_subject(names.size());
  for (size_t c = 0; c < names.size(); ++c) {
    condition_stats s;
    s.name = names[c];
    std::vector<double> means;
    for (const auto& [subject, conditions] : out.values) {
      const auto it = conditions.find(names[c]);
      if (it == conditions.end()) continue;
      double sum = 0;
      for (double t : it->second) sum += t;
      const double mean = sum / double(it->second.size());
      means.push_back(mean);
      logs[c].push_back(std::log(mean));
      by_subject[c][subject] = std::log(mean);
      s.values += it->second.size();
    }
    s.n = means.size();
    for (double m : means) s.mean += m / double(s.n);
    double ss = 0;
    for (double m : means) ss += (m - s.mean) * (m - s.mean);
    s.sd = s.n > 1 ? std::sqrt(ss / double(s.n - 1)) : std::numeric_limits<double>::quiet_NaN();
    out.conditions.push_back(s);
  }
  size_t total = 0;
  double grand = 0;
  for (const auto& g : logs) {
    total += g.size();
    for (double v : g) grand += v;
  }
  grand /= double(total);
  double between = 0, within = 0;
  std::vector<double> group_mean(logs.size());
  for (size_t c = 0; c < logs.size(); ++c) {
    for (double v : logs[c]) group_mean[c] += v / double(logs[c].size());
    between += double(logs[c].size()) * (group_mean[c] - grand) * (group_mean[c] - grand);
    for (double v : logs[c]) within += (v - group_mean[c]) * (v - group_mean[c]);
  }
  out.df1 = double(logs.size() - 1);
  out.df2 = double(total) - double(logs.size());
  if (names.size() < 2) {
    out.anova_note = "one condition: nothing to compare";
    return out;
  }
  if (out.df2 < 1) {
    out.anova_note = fmt::format("{} subject means for {} conditions: the ANOVA needs more subject means than conditions",
                                 total, names.size());
    return out;
  }
  out.anova = true;
  const double error = within / out.df2;
  // No spread within conditions (every subject mean equal in each): any difference between
  // conditions is certain (F = inf, p = 0), and none is none (F = 0, p = 1); 0/0 printed -nan.
  const bool no_within = !(error > 1e-24);
  const double ratio = [](double d, double e, bool none) {
    if (!none) return d / e;
    return d > 1e-24 ? std::numeric_limits<double>::infinity() : 0.0;
  }(between / out.df1, error, no_within);
  out.F = ratio;
  out.p = std::isinf(out.F) ? 0.0 : f_upper_tail(out.F, out.df1, out.df2);
  const double comparisons = double(names.size() * (names.size() - 1) / 2);
  for (size_t a = 0; a < names.size(); ++a)
    for (size_t b = a + 1; b < names.size(); ++b) {
      pair_comparison pc;
      pc.a = names[a], pc.b = names[b];
      pc.df = out.df2;
      const double difference = group_mean[a] - group_mean[b];
      if (!no_within) {
        pc.t = difference / std::sqrt(error * (1.0 / logs[a].size() + 1.0 / logs[b].size()));
        pc.p = t_two_sided(pc.t, pc.df);
      } else {  // as for F above
        pc.t = std::fabs(difference) > 1e-12 ? std::copysign(std::numeric_limits<double>::infinity(), difference) : 0.0;
        pc.p = std::isinf(pc.t) ? 0.0 : 1.0;
      }
      pc.p_bonferroni = std::min(1.0, pc.p * comparisons);
      std::vector<double> d;
      for (const auto& [subject, v] : by_subject[a])
        if (const auto it = by_subject[b].find(subject); it != by_subject[b].end()) d.push_back(v - it->second);
      pc.paired_n = d.size();
      if (d.size() >= 2) {
        double mean = 0, ss = 0;
        for (double x : d) mean += x / double(d.size());
        for (double x : d) ss += (x - mean) * (x - mean);
        const double se = std::sqrt(ss / double(d.size() - 1) / double(d.size()));
        if (se > 1e-12 * std::max(1.0, std::fabs(mean))) {
          pc.paired_t = mean / se;
          pc.paired_p = t_two_sided(pc.paired_t, double(d.size() - 1));
        } else {  // no spread: identical differences are certain (p = 0) unless all are zero
          pc.paired_t = mean == 0 ? 0 : std::copysign(std::numeric_limits<double>::infinity(), mean);
          pc.paired_p = mean == 0 ? 1 : 0;
        }
      }
      out.pairs.push_back(pc);
    }
  return out;
}

}  // namespace fov
