// Simulated sessions: a rule's bias and spread against an observer whose threshold is known.
#pragma once

#include <cstdint>
#include <vector>

#include "observer.h"
#include "protocol.h"

namespace fov {

// The probability that, from a fresh start, `down` consecutive detections come before `up`
// consecutive misses when each trial detects with probability p.
double down_run_probability(double p, uint32_t up, uint32_t down);

// The detection probability a transformed up-down rule converges on (Levitt 1971): where
// that run has probability 1/2 (0.5 for 1-up/1-down, 0.707 for 1-up/2-down, 0.794 for
// 1-up/3-down), by bisection.
double levitt_target_probability(uint32_t up, uint32_t down);

// The scale at which the observer detects with `probability` (bisection over 0.01..100).
double scale_at_probability(const observer_model& m, double probability, bool two_afc);

// The detection probability the protocol's procedure aims at: Levitt's for up-down,
// p_threshold for QUEST, and for QUEST+ where its Weibull's threshold lies (63 % of the way
// from the lower asymptote to 1 - lapse; their means over the lists).
double procedure_target_probability(const stair_protocol& p);

struct simulation_result {
  std::vector<double> estimates;  // each complete series' estimate: its thresholds' mean
  double mean = 0, sd = 0;        // of the estimates (sd with n - 1; 0 for fewer than 2)
  uint64_t series = 0, incomplete = 0, trials = 0;
  double target_probability = 0, target_scale = 0;  // where the procedure aims, for this observer
};

// The most sessions one simulate call runs (each plans at most max_protocol_trials).
constexpr uint32_t max_simulation_runs = 10000;

// `runs` sessions of the protocol answered by the observer, seeded seed + run.
simulation_result simulate_rule(const stair_protocol& base, const observer_model& m, uint32_t runs);

}  // namespace fov
