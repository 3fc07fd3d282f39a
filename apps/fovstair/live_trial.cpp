#include "live_trial.h"

#include <chrono>
#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

namespace fov {

namespace {

using clock_type = std::chrono::steady_clock;
double ms_between(clock_type::time_point a, clock_type::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}


// The next scripted answer, when a script drives the trial (0 when the script is empty).
int scripted(live_context& ctx) {
  if (ctx.scripted_keys.empty()) return 0;
  const int k = ctx.scripted_keys.front();
  ctx.scripted_keys.erase(0, 1);
  return k;
}

// Waits for one of `keys` (lower case); Esc returns 27.
int wait_for(live_context& ctx, const std::string& keys) {
  view_window& w = ctx.window;
  if (const int k = scripted(ctx)) return k;
  for (;;) {
    const int k = w.key(20);
    if (k == 27) return 27;
    if (k > 0 && k < 256 && keys.find(char(std::tolower(k))) != std::string::npos) return std::tolower(k);
    if (w.closed()) return 'q';
  }
}

trial_answer quit_answer() {
  trial_answer a;
  a.quit = true;
  return a;
}

}  // namespace

bool show_instructions(live_context& ctx, int width, int height) {
  ctx.window.show(message_screen(width, height, instruction_lines(ctx.protocol)));
  if (!ctx.scripted_keys.empty()) return true;  // testing: no waiting
  return wait_for(ctx, " q") != 'q';
}

void show_feedback(live_context& ctx, int width, int height, const std::string& text) {
  ctx.window.show(message_screen(width, height, {text}));
  ctx.window.key(ctx.scripted_keys.empty() ? 800 : 1);
}

trial_answer run_live_trial(live_context& ctx, const trial_plan& t, const pointset& set) {
  const int w = set.model.display.width, h = set.model.display.height;
  const stair_protocol& p = ctx.protocol;
  const stair_condition& c = p.conditions[t.condition];
  const render_params s = stimulus_params(p, c);
  const double fx = t.fixation_x * w, fy = t.fixation_y * h;
  const display_geometry& display = set.model.display;
  if (t.break_before) {
    ctx.window.show(message_screen(w, h, {"Break.", "Press Space to continue."}));
    if (ctx.scripted_keys.empty() && wait_for(ctx, " q") == 'q') return quit_answer();
  }
  for (;;) {  // restarts after a pause
    trial_answer a;
    // Fixation: a cross where to look, 600 ms.
    cv::Mat cross = message_screen(w, h, {});
    cv::drawMarker(cross, cv::Point(int(fx), int(fy)), {255, 255, 255}, cv::MARKER_CROSS, 30, 2);
    if (p.mode == stair_mode::yes_no) {  // the question, at the bottom, before the stimulus
      const fitted_text q = fit_text({question_text(p)}, w - w / 4, 0.7, 1);
      for (size_t i = 0; i < q.lines.size(); ++i)
        cv::putText(cross, q.lines[i], {w / 8, h - 12 - int(q.lines.size() - 1 - i) * q.line_height}, cv::FONT_HERSHEY_SIMPLEX,
                    q.scale, {255, 255, 255}, 1, cv::LINE_AA);
    }
    ctx.window.show(cross);
    ctx.window.key(600);
    ctx.renderer.reset_history();
    frame reference;
    if (t.is_catch || p.mode == stair_mode::two_afc) reference = ctx.renderer.reference(w, h, s).image;
    const auto start = clock_type::now();
    double sum[2] = {0, 0}, sum2[2] = {0, 0};
    uint64_t frames = 0;
    const uint64_t clamped_before = ctx.gaze ? ctx.gaze->clamped : 0;
    std::vector<gaze_sample> fresh;
    // One stimulus interval: shows the foveated (or the reference) frames until `until`
    // returns true; returns the key that ended it (0 when `until` did).
    auto show = [&](bool foveated, double max_ms, const std::string& keys) -> int {
      const auto begin = clock_type::now();
      for (;;) {
        gaze_point g{fx, fy};
        double age_ms = std::numeric_limits<double>::quiet_NaN(), tracker_s = age_ms;  // none without a source
        if (ctx.gaze) {
          fresh.clear();
          const double now_ms = gaze_clock_ms();
          ctx.gaze->read(now_ms, fresh);
          const gaze_estimate e = ctx.conditioner->update(now_ms, fresh);
          if (e.landed) ctx.renderer.history_gaze(e.saccade_onset);
          g = e.at;
          if (e.has_sample) age_ms = std::round(e.age_ms * 10) / 10, tracker_s = e.newest.tracker_s;
        }
        sum[0] += g.x, sum[1] += g.y, sum2[0] += g.x * g.x, sum2[1] += g.y * g.y;
        ++a.gaze_samples;
        if (a.gaze_trace.size() < max_trial_gaze_samples)
          a.gaze_trace.push_back({std::round(ms_between(start, clock_type::now()) * 10) / 10, std::round(g.x * 10) / 10,
                                  std::round(g.y * 10) / 10, age_ms, tracker_s});
        // The angle between the gaze and the target, as the acuity model measures eccentricity.
        const double off = std::atan(std::hypot(g.x - fx, g.y - fy) / (display.width * display.viewing_distance)) * 180 / M_PI;
        a.fixation_max_deg = std::max(a.fixation_max_deg, off);
        const frame& f = foveated ? ctx.renderer.foveated(g, s) : reference;
        ++frames;
        ctx.window.show(display_image(f));
        int k = ctx.window.key(1);
        if (!keys.empty() && !ctx.scripted_keys.empty()) k = scripted(ctx);
        if (k == 27) return 27;
        if (k > 0 && k < 256 && keys.find(char(std::tolower(k))) != std::string::npos) return std::tolower(k);
        if (max_ms > 0 && ms_between(begin, clock_type::now()) >= max_ms) return 0;
        if (ctx.window.closed()) return 'q';
      }
    };
    int key = 0;
    clock_type::time_point asked;
    if (p.mode == stair_mode::yes_no) {
      asked = start;
      key = show(!t.is_catch, 0, "yn");
    } else {
      for (uint32_t interval = 0; interval < 2 && key == 0; ++interval) {
        key = show(interval == t.foveated_interval && !t.is_catch, p.interval_ms, "");
        if (key == 0 && interval == 0) ctx.window.show(message_screen(w, h, {})), ctx.window.key(400);
      }
      if (key == 0) {
        ctx.window.show(message_screen(w, h, {question_text(p)}));
        asked = clock_type::now();
        key = wait_for(ctx, "12");
      }
    }
    if (key == 'q') return quit_answer();
    if (key == 27) {  // pause
      ctx.window.show(message_screen(w, h, {"Paused.", "Any key resumes this trial; Q quits (the session can be resumed)."}));
      for (int k = -1; k < 0;) {
        k = ctx.window.key(50);
        if (k == 'q' || k == 'Q' || ctx.window.closed()) return quit_answer();
      }
      continue;
    }
    a.rt_ms = ms_between(asked, clock_type::now());
    a.response = std::string(1, char(key));
    if (key == 'y') a.response = "yes";
    if (key == 'n') a.response = "no";
    a.detected = p.mode == stair_mode::yes_no ? key == 'y' : uint32_t(key - '1') == t.foveated_interval;
    const double n = double(std::max<uint64_t>(1, a.gaze_samples));
    for (int i = 0; i < 2; ++i) {
      a.gaze_mean[i] = sum[i] / n;
      a.gaze_sd[i] = std::sqrt(std::max(0.0, sum2[i] / n - a.gaze_mean[i] * a.gaze_mean[i]));
    }
    a.gaze_clamped = ctx.gaze ? ctx.gaze->clamped - clamped_before : 0;
    a.mean_frame_ms = ms_between(start, clock_type::now()) / double(std::max<uint64_t>(1, frames));
    a.fixation_broken = p.fixation.radius_deg > 0 && a.fixation_max_deg > p.fixation.radius_deg;
    return a;
  }
}

}  // namespace fov
