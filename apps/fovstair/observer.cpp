#include "observer.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "fov/files.h"

#include "fov/random.h"

namespace fov {

observer_model parse_observer(const std::string& text) {
  const std::string prefix = "logistic:";
  if (text.rfind(prefix, 0) != 0)
    throw std::invalid_argument(fmt::format("'{}': expected logistic:threshold=T,slope=S[,lapse=L][,false_alarm=F]", printable(text)));
  observer_model m;
  bool has_threshold = false;
  std::stringstream in(text.substr(prefix.size()));
  std::string part;
  while (std::getline(in, part, ',')) {
    const size_t eq = part.find('=');
    if (eq == std::string::npos) throw std::invalid_argument(fmt::format("'{}': expected name=value", printable(part)));
    const std::string name = part.substr(0, eq), value = part.substr(eq + 1);
    double v = 0;
    try {
      size_t used = 0;
      v = std::stod(value, &used);
      if (used != value.size() || !std::isfinite(v)) throw std::invalid_argument("");
    } catch (const std::exception&) {
      throw std::invalid_argument(fmt::format("'{}': '{}' is not a number", printable(part), printable(value)));
    }
    if (name == "threshold" && v > 0) m.threshold = v, has_threshold = true;
    else if (name == "slope" && v > 0) m.slope = v;
    else if (name == "lapse" && v >= 0 && v < 1) m.lapse = v;
    else if (name == "false_alarm" && v >= 0 && v <= 1) m.false_alarm = v;
    else throw std::invalid_argument(fmt::format("'{}': unknown name or value out of range", printable(part)));
  }
  if (!has_threshold) throw std::invalid_argument(fmt::format("'{}': needs threshold=T", printable(text)));
  return m;
}

std::string observer_text(const observer_model& m) {
  return fmt::format("logistic:threshold={},slope={},lapse={},false_alarm={}", m.threshold, m.slope, m.lapse, m.false_alarm);
}

double detect_probability(const observer_model& m, double scale, bool two_afc) {
  const double f = 1 / (1 + std::exp(-m.slope * (scale - m.threshold)));
  const double p = m.lapse / 2 + (1 - m.lapse) * f;
  return two_afc ? 0.5 + 0.5 * p : p;
}

bool observer_answer(const observer_model& m, uint64_t seed, uint64_t trial, double scale, bool is_catch, bool two_afc) {
  rng r(stream_seed(seed, 0x0b5e7e7, trial));
  const double u = r.uniform();
  if (is_catch) return two_afc ? u < 0.5 : u < m.false_alarm;  // nothing to find: a guess
  return u < detect_probability(m, scale, two_afc);
}

}  // namespace fov
