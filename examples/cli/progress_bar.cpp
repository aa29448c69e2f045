#include "progress_bar.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace ifem::cli {
namespace {

using Clock = std::chrono::steady_clock;

constexpr double kDefaultDelaySeconds = 2.0;
constexpr double kMinSecondsBetweenDraws = 0.1;  // ≤ 10 updates per second
constexpr int kBarWidth = 30;
const Clock::time_point kProcessStart = Clock::now();  // the delay counts from here

// The one bar of the process: whether it is on screen, and what was drawn last.
struct BarState {
  Clock::time_point last_draw{};
  bool shown = false;
  int last_percent = -1;
  std::string last_stage;
};

BarState& state() {
  static BarState s;
  return s;
}

double seconds_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

// IFEM_PROGRESS_DELAY (seconds ≥ 0), else the default; read once.
double delay_seconds() {
  static const double delay = [] {
    const char* text = std::getenv("IFEM_PROGRESS_DELAY");
    if (text == nullptr || *text == '\0') return kDefaultDelaySeconds;
    char* end = nullptr;
    const double d = std::strtod(text, &end);
    return (end != text && std::isfinite(d) && d >= 0.0) ? d : kDefaultDelaySeconds;
  }();
  return delay;
}

void draw(double fraction, std::string_view stage) {
  BarState& s = state();
  const Clock::time_point now = Clock::now();
  if (fraction >= 1.0) {
    clear_progress_bar();
    return;
  }
  if (seconds_between(kProcessStart, now) < delay_seconds()) return;
  const int percent = static_cast<int>(std::floor(100.0 * std::clamp(fraction, 0.0, 1.0)));
  const bool same_stage = s.shown && s.last_stage == stage;
  if (same_stage &&
      (percent == s.last_percent || seconds_between(s.last_draw, now) < kMinSecondsBetweenDraws)) {
    return;
  }
  const int filled = static_cast<int>(std::lround(kBarWidth * fraction));
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.append(static_cast<std::size_t>(kBarWidth - filled), '.');
  std::fprintf(stderr, "\r\033[Kifem: %.*s [%s] %3d%%", static_cast<int>(stage.size()),
               stage.data(), bar.c_str(), percent);
  std::fflush(stderr);
  s.shown = true;
  s.last_draw = now;
  s.last_percent = percent;
  s.last_stage = std::string(stage);
}

}  // namespace

ProgressCallback progress_bar(const Args& args) {
  if (args.has("quiet") || isatty(fileno(stderr)) == 0) return {};
  return draw;
}

void clear_progress_bar() {
  BarState& s = state();
  if (!s.shown) return;
  std::fprintf(stderr, "\r\033[K");
  std::fflush(stderr);
  s.shown = false;
  s.last_percent = -1;
  s.last_stage.clear();
}

}  // namespace ifem::cli
