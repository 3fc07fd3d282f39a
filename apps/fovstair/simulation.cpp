#include "simulation.h"

#include <cmath>

#include <fmt/format.h>

#include "fov/random.h"
#include "session.h"

namespace fov {

double down_run_probability(double p, uint32_t up, uint32_t down) {
  // P(a run of `down` detections before a run of `up` misses), trials independent with
  // P(detect) = p: p^(n-1) (1 - q^m) / (p^(n-1) + q^(m-1) - p^(n-1) q^(m-1)), q = 1 - p.
  const double q = 1 - p, pn = std::pow(p, double(down) - 1), qm = std::pow(q, double(up) - 1);
  return pn * (1 - qm * q) / (pn + qm - pn * qm);
}

double levitt_target_probability(uint32_t up, uint32_t down) {
  // The staircase is at equilibrium where a step down is as likely as a step up: the run
  // of detections that moves it down has probability 1/2 (Levitt 1971; for 1-up/n-down,
  // p^n = 1/2). It rises with p, so bisection finds it.
  double lo = 0, hi = 1;
  for (int i = 0; i < 100; ++i) {
    const double mid = (lo + hi) / 2;
    (down_run_probability(mid, up, down) < 0.5 ? lo : hi) = mid;
  }
  return (lo + hi) / 2;
}

double scale_at_probability(const observer_model& m, double probability, bool two_afc) {
  double lo = 0.01, hi = 100;
  for (int i = 0; i < 200; ++i) {
    const double mid = (lo + hi) / 2;
    (detect_probability(m, mid, two_afc) < probability ? lo : hi) = mid;
  }
  return (lo + hi) / 2;
}

double procedure_target_probability(const stair_protocol& p) {
  const bool two_afc = p.mode == stair_mode::two_afc;
  auto mean = [](const std::vector<double>& v, double otherwise) {
    double m = 0;
    for (double x : v) m += x / double(v.size());
    return v.empty() ? otherwise : m;
  };
  switch (p.procedure) {
    case stair_procedure::up_down: return levitt_target_probability(p.rule.up, p.rule.down);
    case stair_procedure::quest: return p.quest.p_threshold;
    case stair_procedure::quest_plus: {
      const double g = mean(p.quest_plus.lower_asymptotes, default_guess_rate(two_afc)), l = mean(p.quest_plus.lapse_rates, 0);
      return g + (1 - g - l) * (1 - std::exp(-1.0));
    }
  }
  return 0.5;
}

simulation_result simulate_rule(const stair_protocol& base, const observer_model& m, uint32_t runs) {
  const bool two_afc = base.mode == stair_mode::two_afc;
  simulation_result out;
  for (uint32_t r = 0; r < runs; ++r) {
    stair_protocol p = base;
    p.seed = base.seed + r;
    const std::string subject = fmt::format("sim{}", r + 1);
    stair_session s(p, subject);
    const uint64_t seed = stream_seed(p.seed, subject_number(subject));
    while (!s.finished()) {
      const trial_plan t = s.next();
      s.record(t, observer_answer(m, seed, t.index, t.scale, t.is_catch, two_afc));
    }
    out.trials += s.trials();
    for (uint32_t c = 0; c < p.conditions.size(); ++c) {
      const stair_series& st = s.series(c);
      ++out.series;
      if (!st.complete()) {
        ++out.incomplete;
        continue;
      }
      double mean = 0;
      for (double v : st.thresholds()) mean += v / double(st.thresholds().size());
      out.estimates.push_back(mean);
    }
  }
  double ss = 0;
  for (double e : out.estimates) out.mean += e / double(out.estimates.size());
  for (double e : out.estimates) ss += (e - out.mean) * (e - out.mean);
  out.sd = out.estimates.size() > 1 ? std::sqrt(ss / double(out.estimates.size() - 1)) : 0;
  out.target_probability = procedure_target_probability(base);
  out.target_scale = scale_at_probability(m, out.target_probability, two_afc);
  return out;
}

}  // namespace fov
