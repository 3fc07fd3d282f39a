// fovstair's logic without a window: staircase, protocol validation, counterbalancing,
// session files, statistics and the simulated observer.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include <gtest/gtest.h>

#include "analysis.h"
#include "fov/dart_throwing.h"
#include "fov/knn_table.h"
#include "observer.h"
#include "protocol.h"
#include "session.h"
#include "simulation.h"
#include "staircase.h"

namespace fov {
namespace {

std::vector<double> run_script(staircase& s, const std::string& answers, std::vector<double>* shown = nullptr) {
  for (char a : answers) {
    if (shown) shown->push_back(s.scale());
    s.answer(a == 'y');
  }
  return s.thresholds();
}

TEST(Staircase, ThesisRuleAscendsBySmallerStepsAfterTheFirstReversal) {
  staircase s(stair_rule{}, 1.0, 3.0, 1.0);
  std::vector<double> shown;
  // 1.0 no, 1.2 no, 1.4 no, 1.6 yes (reversal 1, not recorded; steps now 0.1), 1.5 yes,
  // 1.4 no (recorded), 1.5 yes (recorded), 1.4 yes, 1.3 no (recorded), 1.4 yes (recorded).
  const auto t = run_script(s, "nnnyynyyny", &shown);
  const std::vector<double> expected_shown{1.0, 1.2, 1.4, 1.6, 1.5, 1.4, 1.5, 1.4, 1.3, 1.4};
  ASSERT_EQ(shown.size(), expected_shown.size());
  for (size_t i = 0; i < shown.size(); ++i) EXPECT_NEAR(shown[i], expected_shown[i], 1e-12) << i;
  ASSERT_EQ(t.size(), 4u);
  EXPECT_DOUBLE_EQ(t[0], 1.4);
  EXPECT_DOUBLE_EQ(t[1], 1.5);
  EXPECT_DOUBLE_EQ(t[2], 1.3);
  EXPECT_DOUBLE_EQ(t[3], 1.4);
  EXPECT_EQ(s.reversals(), 5u);
  EXPECT_TRUE(s.done());
  EXPECT_TRUE(s.complete());
}

TEST(Staircase, OneUpTwoDownNeedsTwoDetectionsToDescend) {
  stair_rule r;
  r.down = 2;
  r.initial_step = r.step = 0.1;
  r.discard_reversals = 0;
  staircase s(r, 1.0, 3.0, 1.5);
  s.answer(true);
  EXPECT_DOUBLE_EQ(s.scale(), 1.5);  // one detection: stay
  s.answer(false);
  EXPECT_DOUBLE_EQ(s.scale(), 1.6);  // a miss resets the run and ascends
  s.answer(true);
  s.answer(true);  // two: descend, a reversal (was ascending)
  EXPECT_DOUBLE_EQ(s.scale(), 1.5);
  EXPECT_EQ(s.reversals(), 1u);
  ASSERT_EQ(s.thresholds().size(), 1u);
  EXPECT_DOUBLE_EQ(s.thresholds()[0], 1.6);
}

TEST(Staircase, ClampsAtTheEndsAndStopsAtMaxTrials) {
  stair_rule r;
  r.max_trials = 30;
  staircase s(r, 1.0, 3.0, 1.0);
  for (int i = 0; i < 30; ++i) s.answer(false);
  EXPECT_DOUBLE_EQ(s.scale(), 3.0);
  EXPECT_TRUE(s.done());
  EXPECT_FALSE(s.complete());
  EXPECT_TRUE(s.thresholds().empty());
}

std::string protocol_with(const std::string& conditions_line) {
  return "{\n"
         "  \"fovstair_protocol\": 1,\n"
         "  \"conditions\": [\n"
         "    {\"name\": \"A\", \"method\": \"nn\", \"k\": 5},\n" +
         conditions_line +
         "\n  ]\n"
         "}\n";
}

std::string error_of(const std::string& text) {
  try {
    parse_protocol(text, "p.json");
  } catch (const protocol_error& e) {
    return e.what();
  }
  return "";
}

TEST(Protocol, ErrorsNameTheFileLineAndField) {
  EXPECT_EQ(error_of(protocol_with("    {\"name\": \"B\", \"method\": \"shepard\", \"k\": 40}")),
            "p.json:5: conditions[1].k: must lie in 1..32");
  EXPECT_EQ(error_of(protocol_with("    {\"name\": \"B\", \"method\": \"cubic\"}")),
            "p.json:5: conditions[1].method: must be nn, shepard, rbf, barycentric or natural");
  EXPECT_EQ(error_of(protocol_with("    {\"name\": \"B\", \"rbf_kernel\": \"cubic\"}")),
            "p.json:5: conditions[1].rbf_kernel: must be multiquadric or gaussian");
  EXPECT_EQ(error_of(protocol_with("    {\"name\": \"A\", \"method\": \"rbf\"}")),
            "p.json:5: conditions[1].name: repeats an earlier condition's name");
  EXPECT_EQ(error_of(protocol_with("    {\"name\": \"B\", \"kay\": 5}")), "p.json:5: conditions[1].kay: unknown key (see docs/fovstair.md)");
  EXPECT_EQ(error_of("{\n  \"fovstair_protocol\": 1,\n  \"conditions\": [\n    {\"name\": \"A\",}\n  ]\n}\n").substr(0, 28),
            "p.json:4: not valid JSON: sy");
  EXPECT_EQ(error_of("{\"fovstair_protocol\": 2}"), "p.json:1: fovstair_protocol: must be 1 (the schema version this fovstair reads)");
  EXPECT_EQ(error_of("{\n\"fovstair_protocol\": 1,\n\"conditions\": [{\"name\": \"A\"}],\n\"rule\": {\"up\": 1,\n \"step\": 0.05,\n \"initial_step\": 0.01}\n}"),
            "p.json:6: rule.initial_step: must be at least step");
  EXPECT_EQ(error_of("{\n\"fovstair_protocol\": 1,\n\"conditions\": [{\"name\": \"A\"}],\n\"fixations\": [[0.5, 0.5],\n [1.5, 0]]\n}"),
            "p.json:5: fixations[1]: must lie in 0..1 (normalised screen coordinates)");
  EXPECT_EQ(error_of(protocol_with("    {\"name\": \"B\"}")), "");  // valid
}

// How stimuli are traced comes from the protocol: the integrator, bounces and an
// environment light reach the render settings; a wrong integrator or too many bounces
// names its line and key.
TEST(Protocol, IntegratorBouncesAndEnvironmentLightReachTheStimulus) {
  const std::string base = "{\n\"fovstair_protocol\": 1,\n\"conditions\": [{\"name\": \"A\"}]";
  const stair_protocol plain = parse_protocol(base + "\n}", "p.json");
  const render_params plain_params = stimulus_params(plain, plain.conditions[0]);
  EXPECT_EQ(plain_params.method, integrator::direct);
  EXPECT_EQ(plain_params.env_light, "");
  const stair_protocol path =
      parse_protocol(base + ",\n\"integrator\": \"path\",\n\"bounces\": 3,\n\"env_light\": \"sky.exr\"\n}", "p.json");
  const render_params path_params = stimulus_params(path, path.conditions[0]);
  EXPECT_EQ(path_params.method, integrator::path);
  EXPECT_EQ(path_params.bounces, 3u);
  EXPECT_EQ(path_params.env_light, "sky.exr");
  EXPECT_EQ(error_of(base + ",\n\"integrator\": \"whitted\"\n}"), "p.json:4: integrator: must be direct or path");
  EXPECT_EQ(error_of(base + ",\n\"bounces\": 65\n}"), "p.json:4: bounces: must lie in 0..64");
}

TEST(Protocol, TheThesisProtocolLoadsAndReachesEveryTenth) {
  const stair_protocol p = load_protocol(FOV_SOURCE_DIR "/apps/fovstair/protocols/thesis.json");
  ASSERT_EQ(p.conditions.size(), 3u);
  EXPECT_EQ(p.conditions[2].reconstruct.how, method::rbf);
  EXPECT_EQ(p.conditions[0].reconstruct.k, 5u);
  const auto scales = reachable_scales(p);
  ASSERT_EQ(scales.size(), 21u);
  EXPECT_DOUBLE_EQ(scales.front(), 1.0);
  EXPECT_DOUBLE_EQ(scales.back(), 3.0);
  EXPECT_EQ(pointset_path(p, 1.7), "precomputed/fove-s1.70.fovset");
}

TEST(Counterbalance, LatinSquareBalancesPositionsAndSequences) {
  for (size_t n : {3u, 4u}) {
    stair_protocol p;
    p.conditions.resize(n);
    const size_t rows = n % 2 ? 2 * n : n;
    std::map<std::pair<uint32_t, size_t>, int> position;
    std::map<std::pair<uint32_t, uint32_t>, int> follows;
    for (size_t subject = 1; subject <= rows; ++subject) {
      const auto order = condition_order(p, "S" + std::to_string(subject));
      ASSERT_EQ(std::set<uint32_t>(order.begin(), order.end()).size(), n);
      for (size_t j = 0; j < n; ++j) ++position[{order[j], j}];
      for (size_t j = 1; j < n; ++j) ++follows[{order[j - 1], order[j]}];
    }
    for (const auto& [key, count] : position) EXPECT_EQ(count, int(rows / n)) << "n=" << n;
    EXPECT_EQ(follows.size(), n * (n - 1));  // every ordered pair occurs ...
    for (const auto& [key, count] : follows) EXPECT_EQ(count, int(rows * (n - 1) / (n * (n - 1)))) << "n=" << n;  // ... equally often
  }
}

TEST(Statistics, IncompleteBetaAndTails) {
  EXPECT_NEAR(incomplete_beta(1, 1, 0.3), 0.3, 1e-12);
  EXPECT_NEAR(incomplete_beta(2.5, 2.5, 0.5), 0.5, 1e-12);
  EXPECT_NEAR(incomplete_beta(2, 1, 0.4), 0.16, 1e-12);  // x^2
  // t with 4 df has a closed form: P(|T| > sqrt(1.5)) = 0.287864 (computed by hand).
  EXPECT_NEAR(t_two_sided(std::sqrt(1.5), 4), 0.287864, 1e-6);
  EXPECT_NEAR(f_upper_tail(1.5, 1, 4), 0.287864, 1e-6);  // F(1, 4) = T(4)^2
}

TEST(Analysis, HandCheckedSmallSet) {
  // Two conditions, three subjects, one threshold each: log means 0, .2, .4 and .2, .4, .6.
  std::vector<threshold_value> v;
  for (int s = 0; s < 3; ++s) {
    v.push_back({"s" + std::to_string(s), "A", std::exp(0.2 * s)});
    v.push_back({"s" + std::to_string(s), "B", std::exp(0.2 * s + 0.2)});
  }
  const threshold_analysis a = analyze_thresholds(v);
  // SSB = 3 (0.1^2) x 2 = 0.06, SSW = 2 (0.04 + 0 + 0.04) = 0.16; F = 0.06 / (0.16 / 4) = 1.5.
  EXPECT_NEAR(a.F, 1.5, 1e-12);
  EXPECT_EQ(a.df1, 1);
  EXPECT_EQ(a.df2, 4);
  EXPECT_NEAR(a.p, 0.287864, 1e-6);
  ASSERT_EQ(a.pairs.size(), 1u);
  EXPECT_NEAR(a.pairs[0].p, a.p, 1e-12);  // two groups: LSD is the ANOVA
  EXPECT_EQ(a.pairs[0].paired_n, 3u);
  // Every difference is -0.2 up to rounding: no spread, so the paired test is certain.
  EXPECT_TRUE(std::isinf(a.pairs[0].paired_t) && a.pairs[0].paired_t < 0);
  EXPECT_EQ(a.pairs[0].paired_p, 0.0);
  EXPECT_NEAR(a.conditions[0].mean, (1 + std::exp(0.2) + std::exp(0.4)) / 3, 1e-12);
}

TEST(Analysis, ThesisTable5GivesTheThesisStatistics) {
  const auto v = read_thresholds_csv(FOV_SOURCE_DIR "/tests/data/thesis-table5.csv");
  ASSERT_EQ(v.size(), 17u * 3 * 4);
  const threshold_analysis a = analyze_thresholds(v);
  // Computed from Table 5 (the thesis's Table 3 swaps the MSM and RBF labels).
  std::map<std::string, std::pair<double, double>> expected{{"NN", {1.751, 0.350}}, {"MSM", {1.779, 0.362}}, {"RBF", {1.675, 0.248}}};
  for (const auto& c : a.conditions) {
    EXPECT_EQ(c.n, 17u);
    EXPECT_NEAR(c.mean, expected[c.name].first, 5e-4) << c.name;
    EXPECT_NEAR(c.sd, expected[c.name].second, 5e-4) << c.name;
  }
  // Thesis Sec. 6.3: F(2, 48) = 0.403, p = 0.670; Table 4: 0.792, 0.544, 0.386.
  EXPECT_EQ(a.df1, 2);
  EXPECT_EQ(a.df2, 48);
  EXPECT_NEAR(a.F, 0.403, 5e-4);
  EXPECT_NEAR(a.p, 0.670, 5e-4);
  ASSERT_EQ(a.pairs.size(), 3u);
  EXPECT_NEAR(a.pairs[0].p, 0.792, 5e-4);  // NN-MSM
  EXPECT_NEAR(a.pairs[1].p, 0.544, 5e-4);  // NN-RBF
  EXPECT_NEAR(a.pairs[2].p, 0.386, 5e-4);  // MSM-RBF
}

TEST(Analysis, CsvErrorsNameTheLine) {
  const std::string path = ::testing::TempDir() + "/bad.csv";
  std::ofstream(path) << "subject,condition,threshold\n1,NN,1.5\n2,NN,abc\n";
  try {
    read_thresholds_csv(path);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), path + ":3: threshold 'abc' is not a number");
  }
}

TEST(SessionFile, NeverOverwritesAndResumeCutsATornLine) {
  const std::string path = ::testing::TempDir() + "/S1-1.jsonl";
  std::filesystem::remove(path);
  // A session read back is checked against its stored protocol: real records, as run writes them.
  const std::string text = R"({"fovstair_protocol": 1, "conditions": [{"name": "A"}],
    "rule": {"thresholds": 1, "discard_reversals": 0, "max_trials": 4}, "catch_rate": 0})";
  const stair_protocol p = parse_protocol(text, "p.json");
  stair_session plan(p, "S1");
  auto next_record = [&](bool detected) {
    const trial_plan t = plan.next();
    return trial_record(p, t, detected, plan.record(t, detected));
  };
  const nlohmann::json header = {{"type", "session"}, {"subject", "S1"}, {"session", "1"}, {"protocol_text", text}};
  {
    session_file f = session_file::create(path, header);
    f.append(next_record(false));
  }
  EXPECT_THROW(session_file::create(path, {{"type", "session"}}), std::runtime_error);
  std::ofstream(path, std::ios::app) << "{\"type\": \"trial\", \"ind";  // a crash mid-write
  nlohmann::json read_header;
  std::vector<nlohmann::json> trials;
  // Another subject's --resume is refused before the file is touched: the torn line stays.
  const auto size_before = std::filesystem::file_size(path);
  EXPECT_THROW(session_file::resume(path, "S2", read_header, trials), std::runtime_error);
  EXPECT_EQ(std::filesystem::file_size(path), size_before);
  {
    session_file f = session_file::resume(path, "S1", read_header, trials);
    EXPECT_EQ(read_header["subject"], "S1");
    ASSERT_EQ(trials.size(), 1u);
    f.append(next_record(true));  // a reversal: the series' one threshold, and the end
    ASSERT_TRUE(plan.finished());
    f.append({{"type", "end"}});
  }
  const session_data d = read_session(path);
  ASSERT_EQ(d.trials.size(), 2u);
  EXPECT_EQ(d.trials[1]["index"], 1);
  EXPECT_TRUE(d.ended);
  EXPECT_THROW(session_file::resume(path, "S1", read_header, trials), std::runtime_error);  // finished
}

TEST(SessionPlan, IsDeterministicAndSkipsCatchTrialsInTheStaircase) {
  stair_protocol p = load_protocol(FOV_SOURCE_DIR "/apps/fovstair/protocols/thesis.json");
  p.catch_rate = 0.3;
  const observer_model m = parse_observer("logistic:threshold=1.6,slope=10");
  auto run = [&](std::vector<trial_plan>& plans) {
    stair_session s(p, "S3");
    while (!s.finished()) {
      const trial_plan t = s.next();
      plans.push_back(t);
      s.record(t, observer_answer(m, 5, t.index, t.scale, t.is_catch, false));
    }
    return s.trials();
  };
  std::vector<trial_plan> a, b;
  EXPECT_EQ(run(a), run(b));
  size_t catches = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].scale, b[i].scale);
    EXPECT_EQ(a[i].is_catch, b[i].is_catch);
    catches += a[i].is_catch;
    if (i > 0 && a[i - 1].is_catch && a[i - 1].condition == a[i].condition) {
      EXPECT_EQ(a[i].series_trial, a[i - 1].series_trial);  // a catch trial is not a staircase step
    }
  }
  EXPECT_GT(catches, a.size() / 6);
  EXPECT_LT(catches, a.size() / 2);
}

TEST(Observer, ParsesAndRejects) {
  const observer_model m = parse_observer("logistic:threshold=1.7,slope=8,lapse=0.02");
  EXPECT_DOUBLE_EQ(m.threshold, 1.7);
  EXPECT_DOUBLE_EQ(m.lapse, 0.02);
  EXPECT_NEAR(detect_probability(m, 1.7, false), 0.5, 1e-12);
  EXPECT_NEAR(detect_probability(m, 1.7, true), 0.75, 1e-12);
  EXPECT_THROW(parse_observer("weibull:threshold=1"), std::invalid_argument);
  EXPECT_THROW(parse_observer("logistic:slope=8"), std::invalid_argument);
  EXPECT_THROW(parse_observer("logistic:threshold=x"), std::invalid_argument);
  EXPECT_THROW(parse_observer("logistic:threshold=1.5,lapse=2"), std::invalid_argument);
}

// The estimate of a simulated observer's threshold converges on the rule's target once the
// start is forgotten: fine steps, the first 6 reversals dropped, 16 kept, many series.
// (With the thesis's settings the ascending start biases it: docs/fovstair.md.)
TEST(Observer, StaircaseEstimatesConverge) {
  struct rule_case { uint32_t up, down; double target_p; };
  for (const rule_case rc : {rule_case{1, 1, 0.5}, rule_case{1, 2, std::sqrt(0.5)}}) {
    stair_rule r;
    r.up = rc.up, r.down = rc.down;
    r.initial_step = 0.1, r.step = 0.02, r.discard_reversals = 6, r.thresholds = 16, r.max_trials = 600;
    const observer_model m = parse_observer("logistic:threshold=1.7,slope=8");
    double sum = 0;
    const int runs = 300;
    for (int run = 0; run < runs; ++run) {
      staircase s(r, 1.0, 3.0, 1.0);
      for (uint64_t t = 0; !s.done(); ++t) s.answer(observer_answer(m, run, t, s.scale(), false, false));
      ASSERT_TRUE(s.complete());
      double mean = 0;
      for (double v : s.thresholds()) mean += v / double(s.thresholds().size());
      sum += mean;
    }
    // The scale where P(detect) = target: threshold + ln(p / (1 - p)) / slope.
    const double target = 1.7 + std::log(rc.target_p / (1 - rc.target_p)) / 8;
    EXPECT_NEAR(sum / runs, target, 0.03) << rc.up << "-up/" << rc.down << "-down";
  }
}

// A protocol's hfov reaches the stimulus for every scene kind (the built-in scene and env:
// images have a camera of their own that the old code kept): two protocols differing
// only in hfov give different trial frames; without hfov the scene's camera is used.
TEST(Protocol, HfovReachesTheTrialFrames) {
  auto set = std::make_shared<pointset>();
  set->model.display = {48, 40, 1.0};
  set->points = throw_darts(set->model, {});
  knn_params kp;
  kp.k = 8;
  set->table = build_knn_table(set->points, set->canvas_width(), set->canvas_height(), kp);
  set_knn_radii(set->table, set->points);
  const std::string base = "{\n\"fovstair_protocol\": 1,\n\"spp\": 2,\n\"taa\": false,\n\"conditions\": [{\"name\": \"A\", \"method\": \"nn\", \"k\": 1}]";
  const stair_protocol wide = parse_protocol(base + "\n}", "wide.json");
  const stair_protocol narrow = parse_protocol(base + ",\n\"hfov\": 40\n}", "narrow.json");
  EXPECT_EQ(stimulus_params(narrow, narrow.conditions[0]).view.hfov_deg, 40.0f);
  EXPECT_EQ(stimulus_params(wide, wide.conditions[0]).view.hfov_deg, 0.0f);
  std::shared_ptr<const scene> scn = load_scene(wide.scene);
  auto trial_frame = [&](const stair_protocol& p) {
    const render_params rp = stimulus_params(p, p.conditions[0]);
    renderer r(scn, rp);
    r.use_pointset(set);
    return std::make_pair(r.foveated({24, 20}, rp), r.cam().hfov_deg);
  };
  const auto [a, a_hfov] = trial_frame(wide);
  const auto [b, b_hfov] = trial_frame(narrow);
  EXPECT_EQ(a_hfov, scn->description().scene_camera->hfov_deg);
  EXPECT_EQ(b_hfov, 40.0f);
  double diff = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i) diff += glm::length(a.rgb[i] - b.rgb[i]);
  EXPECT_GT(diff / double(a.rgb.size()), 0.01);
}

TEST(Simulation, LevittTargetsAndARuleConverges) {
  EXPECT_NEAR(levitt_target_probability(1, 1), 0.5, 1e-12);
  EXPECT_NEAR(levitt_target_probability(1, 2), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(levitt_target_probability(1, 3), std::cbrt(0.5), 1e-12);
  EXPECT_NEAR(levitt_target_probability(2, 1), 1 - std::sqrt(0.5), 1e-12);  // the mirror rule
  // 2-up/2-down is symmetric in detections and misses: it targets 1/2.
  EXPECT_NEAR(levitt_target_probability(2, 2), 0.5, 1e-12);
  EXPECT_NEAR(down_run_probability(0.3, 1, 1), 0.3, 1e-12);
  const observer_model m = parse_observer("logistic:threshold=1.7,slope=8");
  EXPECT_NEAR(scale_at_probability(m, 0.5, false), 1.7, 1e-9);
  EXPECT_NEAR(detect_probability(m, scale_at_probability(m, 0.8, true), true), 0.8, 1e-9);
  stair_protocol p = parse_protocol("{\"fovstair_protocol\": 1, \"conditions\": [{\"name\": \"A\"}], \"catch_rate\": 0}", "p.json");
  p.rule.initial_step = 0.1, p.rule.step = 0.02, p.rule.discard_reversals = 6, p.rule.thresholds = 16, p.rule.max_trials = 600;
  const simulation_result r = simulate_rule(p, m, 100);
  EXPECT_EQ(r.series, 100u);
  EXPECT_EQ(r.incomplete, 0u);
  EXPECT_EQ(r.estimates.size(), 100u);
  EXPECT_NEAR(r.target_probability, 0.5, 1e-12);
  EXPECT_NEAR(r.mean, r.target_scale, 0.03);
  EXPECT_GT(r.sd, 0.0);
}

// QUEST, QUEST+ and the session settings in protocols and session files.
std::string with(const std::string& rest) {
  return "{\"fovstair_protocol\": 1, \"conditions\": [{\"name\": \"A\"}], \"mode\": \"2afc\"" + (rest.empty() ? "" : ",\n" + rest) + "}";
}

TEST(QuestProtocol, RefusesWhatCannotRunOrIsIgnored) {
  EXPECT_EQ(error_of(with("\"procedure\": \"quest\", \"quest\": {\"max_trials\": 30}")), "");
  EXPECT_EQ(error_of(with("\"procedure\": \"bisect\"")), "p.json:2: procedure: must be up-down, quest or quest-plus");
  EXPECT_EQ(error_of(with("\"quest\": {}")),
            "p.json:2: quest: settings for procedure quest, but the protocol's procedure is up-down");
  EXPECT_EQ(error_of(with("\"procedure\": \"quest\", \"rule\": {}")),
            "p.json:2: rule: settings for procedure up-down, but the protocol's procedure is quest");
  EXPECT_EQ(error_of(with("\"procedure\": \"quest\", \"quest\": {\"p_threshold\": 0.4}")),
            "p.json:2: quest.p_threshold: must lie strictly between gamma (0.5) and 1 - delta (1 - gamma) (0.995)");
  EXPECT_EQ(error_of(with("\"procedure\": \"quest\", \"quest\": {\"method\": \"median\"}")),
            "p.json:2: quest.method: must be quantile, mean or mode");
  EXPECT_EQ(error_of(with("\"procedure\": \"quest-plus\", \"quest_plus\": {\"lower_asymptotes\": [0.5], \"lapse_rates\": [0.6]}")),
            "p.json:2: quest_plus.lapse_rates[0]: must be a number in [0, 0.5]");
  EXPECT_EQ(error_of(with("\"procedure\": \"quest-plus\", \"quest_plus\": {\"lower_asymptotes\": [0.9], \"lapse_rates\": [0.2]}")),
            "p.json:2: quest_plus.lapse_rates: every lower asymptote + lapse rate must stay below 1");
  // 201 scales x 201 thresholds x 7 slopes = 282807 likelihoods: refused up front.
  std::string slopes = "[1";
  for (int i = 2; i <= 7; ++i) slopes += "," + std::to_string(i);
  slopes += "]";
  EXPECT_EQ(error_of(with("\"scales\": {\"grid\": 0.01}, \"procedure\": \"quest-plus\", \"quest_plus\": {\"slopes\": " + slopes +
                          "}")),
            "p.json:2: quest_plus: 201 scales x 1407 parameter combinations = 282807 likelihoods; at most 262144 (so that no "
            "trial waits on the entropy search): coarsen scales.grid or the parameter lists");
  EXPECT_EQ(error_of(with("\"rule\": {\"up\": 1, \"down\": 1}")),
            "p.json:2: rule: a 1-up/1-down rule converges on 50 % correct, at or below chance in 2AFC: use more down than up "
            "steps (1-up/3-down, 79.4 %, is usual)");
  EXPECT_EQ(parse_protocol(with(""), "p").rule.down, 3u);  // 2AFC's default rule: 1-up/3-down
  // The defaults alone over a fine grid: refused too, not only with a quest_plus block.
  EXPECT_EQ(error_of(with("\"scales\": {\"min\": 0.5, \"max\": 10, \"grid\": 0.01}, \"procedure\": \"quest-plus\"")),
            "p.json:2: procedure: 951 scales x 951 parameter combinations = 904401 likelihoods; at most 262144 (so that no "
            "trial waits on the entropy search): coarsen scales.grid or the parameter lists");
  EXPECT_EQ(error_of(with("\"scales\": {\"grid\": 0.015}")),
            "p.json:2: scales.grid: must be a multiple of 0.01 between 0.01 and max - min");
}

TEST(SessionProtocol, InstructionsQuestionAndPractice) {
  const stair_protocol yes_no = parse_protocol("{\"fovstair_protocol\": 1, \"conditions\": [{\"name\": \"A\"}]}", "p");
  EXPECT_EQ(question_text(yes_no), "Anything unnatural? Y or N.");
  EXPECT_EQ(instruction_lines(yes_no).back(), "Press Space to begin.");
  EXPECT_EQ(question_text(parse_protocol(with(""), "p")), "Which interval was foveated? Press 1 or 2.");
  const stair_protocol p = parse_protocol(with("\"instructions\": [\"Hello\"], \"question\": \"Which?\", "
                                               "\"practice\": {\"trials\": 3, \"scales\": [3, 2.5]}"), "p");
  EXPECT_EQ(instruction_lines(p), std::vector<std::string>{"Hello"});
  EXPECT_EQ(question_text(p), "Which?");
  EXPECT_EQ(practice_scale(p, 0), 3);
  EXPECT_EQ(practice_scale(p, 1), 2.5);
  EXPECT_EQ(practice_scale(p, 2), 3);
  EXPECT_EQ(practice_scale(parse_protocol(with("\"practice\": {\"trials\": 1}"), "p"), 0), 3);  // the top scale
  EXPECT_EQ(error_of(with("\"practice\": {\"trials\": 1, \"scales\": [2.55]}")),
            "p.json:2: practice.scales[0]: must be a scale the protocol's sets cover (validate lists them)");
  EXPECT_EQ(error_of(with("\"instructions\": []")), "p.json:2: instructions: must be a list of 1 to 20 lines of text");
  EXPECT_EQ(error_of(with("\"fixation_control\": {\"action\": \"refuse\"}")),
            "p.json:2: fixation_control.action: must be mark or repeat");
}

TEST(QuestProtocol, TheGridIsWhatTheSetsMustCover) {
  const stair_protocol p = parse_protocol(with("\"scales\": {\"min\": 1, \"max\": 2.05, \"grid\": 0.25}, \"procedure\": \"quest\""), "p");
  EXPECT_EQ(reachable_scales(p), (std::vector<double>{1, 1.25, 1.5, 1.75, 2, 2.05}));
}

// A QUEST+ session written trial by trial reads back; a stored estimate that the answers
// do not give is refused with its line.
TEST(QuestSession, EstimatesAreStoredAndChecked) {
  const std::string text = with("\"procedure\": \"quest-plus\", \"catch_rate\": 0, \"quest_plus\": {\"max_trials\": 6}");
  const stair_protocol p = parse_protocol(text, "p.json");
  stair_session plan(p, "S1");
  const std::string path = ::testing::TempDir() + "/quest-S1.jsonl";
  std::filesystem::remove(path);
  std::vector<nlohmann::json> records;
  {
    session_file f = session_file::create(path, {{"type", "session"}, {"subject", "S1"}, {"session", "1"}, {"protocol_text", text}});
    for (int i = 0; !plan.finished(); ++i) {
      const trial_plan t = plan.next();
      const bool yes = i % 3 != 2;
      records.push_back(trial_record(p, t, yes, plan.record(t, yes)));
      f.append(records.back());
    }
    f.append({{"type", "end"}});
  }
  ASSERT_EQ(records.size(), 6u);
  EXPECT_TRUE(records.back()["recorded"].get<bool>());
  EXPECT_DOUBLE_EQ(records.back()["threshold"].get<double>(), records.back()["estimate"]["threshold"].get<double>());
  EXPECT_FALSE(records[2]["recorded"].get<bool>());
  const session_data d = read_session(path);
  EXPECT_TRUE(d.ended);
  ASSERT_EQ(plan.series(0).thresholds().size(), 1u);
  // Tamper with the third trial's estimate.
  std::ifstream in(path);
  std::string all((std::istreambuf_iterator<char>(in)), {}), line;
  nlohmann::json third = records[2];
  third["estimate"]["threshold"] = third["estimate"]["threshold"].get<double>() * 1.01;
  const size_t at = all.find(records[2].dump());
  ASSERT_NE(at, std::string::npos);
  all.replace(at, records[2].dump().size(), third.dump());
  std::ofstream(path, std::ios::trunc) << all;
  try {
    read_session(path);
    ADD_FAILURE() << "a tampered estimate was read";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), path + ":4: trial 2: the estimate is not the posterior the answers give");
  }
}

}  // namespace
}  // namespace fov
