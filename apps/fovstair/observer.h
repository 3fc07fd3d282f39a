// A simulated observer: answers trials from a psychometric function instead of a person.
#pragma once

#include <cstdint>
#include <string>

namespace fov {

// P(detect | s) = lapse / 2 + (1 - lapse) / (1 + exp(-slope (s - threshold))) in yes-no;
// in 2AFC P(correct) = 1/2 + 1/2 of that. On catch trials (the reference shown) it says
// "yes" with probability false_alarm. threshold is the scale detected half the time.
struct observer_model {
  double threshold = 1.7, slope = 8, lapse = 0, false_alarm = 0;
};

// "logistic:threshold=1.7,slope=8[,lapse=0.02][,false_alarm=0.05]"; throws
// std::invalid_argument naming the bad part.
observer_model parse_observer(const std::string& text);
std::string observer_text(const observer_model& m);

double detect_probability(const observer_model& m, double scale, bool two_afc);

// The observer's answer to trial `trial` of a session seeded with `seed`: the same every
// time it is asked, so a resumed session answers as an uninterrupted one.
bool observer_answer(const observer_model& m, uint64_t seed, uint64_t trial, double scale, bool is_catch, bool two_afc);

}  // namespace fov
