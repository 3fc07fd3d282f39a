// Thresholds from sessions or published tables, and the statistics the thesis reported.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "psychometric.h"
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

// One subject's answers in one condition, binned by scale, for a psychometric fit: the
// non-catch trials of all the subject's sessions in that condition. `guess` is the fit's
// fixed lower asymptote: 0.5 in 2AFC, in yes-no the subject's false-alarm rate on catch
// trials (all conditions; 0 without catch trials, at most 0.5).
struct psychometric_data {
  std::string subject, condition;
  bool two_afc = false;
  double guess = 0;
  uint32_t catch_trials = 0;
  std::vector<psychometric_level> levels;  // ascending scale
};
std::vector<psychometric_data> psychometric_data_from_sessions(const std::vector<session_data>& sessions);

// Sessions answered by a simulated observer (`observer` in the header) beside sessions of
// people: one line naming how many of each, or "" when they are not mixed.
std::string simulated_mix_warning(const std::vector<session_data>& sessions, const std::vector<std::string>& paths);

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
  bool anova = false;                       // the ANOVA and the pairs apply (else `anova_note` says why)
  std::string anova_note;
  double F = 0, df1 = 0, df2 = 0, p = 0;    // one-way ANOVA on log subject means
  std::vector<pair_comparison> pairs;
};

// Per-condition statistics always; the ANOVA and pairwise tests only with two conditions or
// more and more subject means than conditions (a pilot's single subject gets its thresholds
// and means, and a note). Throws std::runtime_error when `values` is empty.
threshold_analysis analyze_thresholds(const std::vector<threshold_value>& values);

}  // namespace fov
