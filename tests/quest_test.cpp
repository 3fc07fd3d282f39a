// QUEST and QUEST+ (apps/fovstair/quest.h): the published algorithms' properties, checked
// against observers that follow each procedure's own model, and the protocol's limits.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numeric>

#include <gtest/gtest.h>

#include "fov/random.h"
#include "protocol.h"
#include "quest.h"
#include "session.h"

namespace fov {
namespace {

// A 2AFC observer that is QUEST+'s Weibull (x, t in log10 scale).
double weibull(double x, double t, double beta, double gamma, double lapse) {
  return gamma + (1 - gamma - lapse) * (1 - std::exp(-std::pow(10.0, beta * (x - t))));
}

TEST(Quest, EpsilonPutsTheCriterionAtTheThreshold) {
  quest_params p;
  const quest q(p, procedure_grid(1, 3, 0.1), true);
  EXPECT_NEAR(q.psi(0), 0.82, 1e-9);  // Psi(x = T) = p_threshold
  EXPECT_NEAR(q.psi(-10), 0.5, 1e-6);  // gamma, the 2AFC guess rate
  EXPECT_NEAR(q.psi(10), 0.01 * 0.5 + 0.99, 1e-9);
  // Watson & Pelli's epsilon for beta 3.5, gamma 0.5, delta 0.01 at 82 %, in closed form.
  EXPECT_NEAR(q.epsilon(), std::log10(-std::log((1 - (0.82 - 0.005) / 0.99) / 0.5)) / 3.5, 1e-9);
}

TEST(Quest, FirstTrialAtTheGuessAndAnswersMoveItTheRightWay) {
  quest_params p;
  p.threshold_guess = 1.7;
  p.guess_sd = 0.2;
  quest q(p, procedure_grid(1, 3, 0.1), true);
  EXPECT_DOUBLE_EQ(q.scale(), 1.7);  // the prior's median, on the grid
  quest yes = q, no = q;
  yes.answer(true);
  no.answer(false);
  EXPECT_LT(yes.scale(), 1.7);  // a correct answer: the threshold is probably lower
  EXPECT_GT(no.scale(), 1.7);
  EXPECT_LT(yes.estimate(), q.estimate());
  EXPECT_GT(no.estimate(), q.estimate());
  const posterior_summary s = q.summary();  // the prior: its interval is +- 1.645 sd (log10)
  EXPECT_NEAR(std::log10(s.hi) - std::log10(s.lo), 2 * 1.645 * 0.2, 0.01);
}

// Watson & Pelli's Weibull with PsychoPy's defaults (beta 3.5, delta 0.01, gamma 0.5), its
// shift epsilon in closed form: P = 0.82 where x = T.
double quest_observer(double x_minus_t) {
  const double beta = 3.5, delta = 0.01, gamma = 0.5, p = 0.82;
  const double epsilon = std::log10(-std::log((1 - (p - delta * gamma) / (1 - delta)) / (1 - gamma))) / beta;
  return delta * gamma + (1 - delta) * (1 - (1 - gamma) * std::exp(-std::pow(10.0, beta * (x_minus_t + epsilon))));
}

// Against an observer that is its own model, QUEST's estimate is unbiased: the mean log
// estimate of 300 series lies within 3 standard errors of the truth.
TEST(Quest, ConvergesOnAnObserverThatIsItsModel) {
  quest_params p;
  p.max_trials = 60;
  p.method = quest_method::mean;
  const double truth = std::log10(1.65);
  std::vector<double> est;
  rng r(7);
  for (int run = 0; run < 300; ++run) {
    quest q(p, procedure_grid(1, 3, 0.05), true);
    while (!q.done()) q.answer(r.uniform() < quest_observer(std::log10(q.scale()) - truth));
    est.push_back(std::log10(q.estimate()));
  }
  const double mean = std::accumulate(est.begin(), est.end(), 0.0) / double(est.size());
  double ss = 0;
  for (double e : est) ss += (e - mean) * (e - mean);
  const double sd = std::sqrt(ss / double(est.size() - 1));
  EXPECT_LT(std::fabs(mean - truth), 3 * sd / std::sqrt(double(est.size())) + 0.005) << "mean " << mean << " sd " << sd;
  EXPECT_LT(sd, 0.06);  // 60 trials pin the threshold to a few hundredths of a log unit
}

TEST(Quest, StopsWhenTheIntervalIsNarrow) {
  quest_params p;
  p.max_trials = 400;
  p.stop_interval = 0.1;
  quest q(p, procedure_grid(1, 3, 0.1), true);
  rng r(3);
  while (!q.done()) q.answer(r.uniform() < q.psi(std::log10(q.scale()) - std::log10(1.5)));
  EXPECT_LT(q.trials(), 400u);
  const posterior_summary s = q.summary();
  EXPECT_LT(std::log10(s.hi) - std::log10(s.lo), 0.1);
}

// QUEST+ picks the stimulus with the least expected posterior entropy, which is the one
// whose answer carries the most information about the parameters: checked against the
// mutual information computed directly, on a small problem.
TEST(QuestPlus, ChoosesTheMostInformativeStimulus) {
  quest_plus_params p;
  p.thresholds = {1.2, 1.5, 2.4};
  p.slopes = {2, 6};
  const std::vector<double> grid = procedure_grid(1, 3, 0.25);
  quest_plus q(p, grid, true);
  auto h = [](double v) { return v <= 0 || v >= 1 ? 0.0 : -v * std::log(v) - (1 - v) * std::log(1 - v); };
  size_t best = 0;
  double best_info = -1;
  for (size_t k = 0; k < grid.size(); ++k) {
    double mean = 0, noise = 0;  // I(R; theta) = H(R) - E_theta H(R | theta), uniform prior
    for (double t : p.thresholds)
      for (double b : p.slopes) {
        const double v = weibull(std::log10(grid[k]), std::log10(t), b, 0.5, 0.01);
        mean += v / 6, noise += h(v) / 6;
      }
    if (h(mean) - noise > best_info + 1e-12) best_info = h(mean) - noise, best = k;
  }
  EXPECT_DOUBLE_EQ(q.scale(), grid[best]);
}

TEST(QuestPlus, ConvergesOnAnObserverThatIsItsModel) {
  quest_plus_params p;
  p.slopes = {2, 3.5, 6, 10};
  p.max_trials = 60;
  const double truth = std::log10(1.8);
  std::vector<double> est;
  rng r(11);
  const std::vector<double> grid = procedure_grid(1, 3, 0.05);
  for (int run = 0; run < 150; ++run) {
    quest_plus q(p, grid, true);
    while (!q.done()) q.answer(r.uniform() < weibull(std::log10(q.scale()), truth, 6, 0.5, 0.01));
    est.push_back(std::log10(q.estimate()));
  }
  const double mean = std::accumulate(est.begin(), est.end(), 0.0) / double(est.size());
  double ss = 0;
  for (double e : est) ss += (e - mean) * (e - mean);
  const double sd = std::sqrt(ss / double(est.size() - 1));
  // The threshold grid is the stimulus grid (steps of about 0.012 log units): a bias below
  // one grid step plus 3 standard errors.
  EXPECT_LT(std::fabs(mean - truth), 3 * sd / std::sqrt(double(est.size())) + 0.012) << "mean " << mean << " sd " << sd;
  EXPECT_LT(sd, 0.05);
}

std::string error_of(const std::string& text) {
  try {
    parse_protocol(text, "p.json");
  } catch (const protocol_error& e) {
    return e.what();
  }
  return "";
}

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
