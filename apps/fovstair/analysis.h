// Thresholds from sessions or published tables, and the statistics the thesis reported.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "session.h"

namespace fov {

struct threshold_value {
  std::string subject, condition;
  double threshold = 0;
};

// The largest thresholds CSV read (about 40,000 rows), and the most conditions it may
// name: a protocol's (the analysis compares every pair of them).
constexpr uintmax_t max_thresholds_bytes = uintmax_t(1) << 20;
constexpr size_t max_threshold_conditions = 64;

// A CSV with the header subject,condition,threshold (one row per threshold value): a
// regular file of at most max_thresholds_bytes naming at most max_threshold_conditions
// conditions. Throws std::runtime_error "FILE:LINE: reason".
std::vector<threshold_value> read_thresholds_csv(const std::string& path);
void write_thresholds_csv(const std::vector<threshold_value>& values, const std::string& path);  // temp + rename

// Every recorded threshold of every series in the sessions.
std::vector<threshold_value> thresholds_from_sessions(const std::vector<session_data>& sessions);

// Regularised incomplete beta I_x(a, b) (continued fraction), and the tails built on it.
double incomplete_beta(double a, double b, double x);
double f_upper_tail(double f, double df1, double df2);  // P(F > f)
double t_two_sided(double t, double df);                // P(|T| > |t|)

struct condition_stats {
  std::string name;
  size_t n = 0;             // subjects
  double mean = 0, sd = 0;  // of the subject means (sd: sample, n - 1)
  size_t values = 0;        // threshold values behind them
};
struct pair_comparison {
  std::string a, b;
  double t = 0, df = 0, p = 0;  // Fisher's LSD on the log subject means (pooled ANOVA error)
  double p_bonferroni = 0;
  size_t paired_n = 0;          // subjects with both conditions
  double paired_t = 0, paired_p = 0;  // paired t-test on the log means of those subjects
};
struct threshold_analysis {
  std::vector<condition_stats> conditions;  // in order of first appearance
  std::map<std::string, std::map<std::string, std::vector<double>>> values;  // subject -> condition -> thresholds
  double F = 0, df1 = 0, df2 = 0, p = 0;    // one-way ANOVA on log subject means
  std::vector<pair_comparison> pairs;
};

// Throws std::runtime_error when there are fewer than two conditions or too few subjects
// for the ANOVA.
threshold_analysis analyze_thresholds(const std::vector<threshold_value>& values);

}  // namespace fov
