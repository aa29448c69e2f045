// Progress of long work (refinement, batched distances, single-source geodesics, eigenpairs,
// reading large files): the one callback type every layer reports through, and the meter that
// calls it cheaply. The library does no I/O with it: the CLI draws a bar on a terminal, Python
// passes it to the caller's function (docs/decisions.md D-159).
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <string_view>

namespace ifem {

/// Receives the progress of one stage of long work: `fraction` in [0, 1] and the stage's name
/// ("read", "refine", "heat distances", "single-source geodesics", "eigenpairs"; valid during
/// the call only). Within one stage the fractions do not decrease; a stage begins with 0 and,
/// unless the work throws, ends with exactly 1. A call that runs several stages reports them in
/// turn. Called synchronously on the calling thread, at most about 1000 times per stage. It
/// should not throw; an exception it throws leaves the work as any other exception of that call.
using ProgressCallback = std::function<void(double fraction, std::string_view stage)>;

/// A fraction done for work whose size is only estimated: done / expected up to 0.9, then a
/// curve that keeps rising towards 1 without reaching it (1 − 0.1·e^{−(x − 0.9)/0.1}, x =
/// done / expected), so an underestimate never shows a full bar while work goes on. In [0, 1).
/// @param done ≥ 0, @param expected > 0 (else 0 is returned)
inline double saturating_fraction(double done, double expected) {
  if (!(expected > 0.0) || !(done > 0.0)) return 0.0;
  const double x = done / expected;
  if (x <= 0.9) return x;
  return 1.0 - 0.1 * std::exp(-(x - 0.9) / 0.1);
}

/// Reports one stage through a ProgressCallback (which may be empty: then every call is one
/// test). update() is meant for every step of a loop: it looks at the fraction only when `done`
/// has advanced by 1/1000 of `total` since it last looked, so its cost per step is one
/// comparison, and calls the callback only when the fraction rose by 1/1000 since the last call
/// (at most ~1000 calls per stage). Reports 0 on construction and 1 in finish(), which the
/// caller calls when the stage is done (not the destructor: the callback may throw).
class ProgressMeter {
 public:
  /// @param total the work's size in the caller's steps (> 0), or its estimate when `estimated`
  ///        (then fractions follow saturating_fraction()); the callback is kept by reference
  ProgressMeter(const ProgressCallback& callback, std::string_view stage, double total,
                bool estimated = false)
      : callback_(callback),
        stage_(stage),
        total_(std::max(total, 1e-300)),
        estimated_(estimated),
        step_(total_ / 1000.0) {
    if (callback_) callback_(0.0, stage_);
    next_ = callback_ ? step_ : HUGE_VAL;
  }
  ProgressMeter(const ProgressMeter&) = delete;
  ProgressMeter& operator=(const ProgressMeter&) = delete;

  /// `done` steps of total so far (non-decreasing between calls; larger than total is fine).
  void update(double done) {
    if (done >= next_) report(done);
  }
  /// Reports 1 (once; later calls do nothing).
  void finish() {
    if (!callback_ || finished_) return;
    finished_ = true;
    next_ = HUGE_VAL;
    callback_(1.0, stage_);
  }

 private:
  // Calls the callback when the fraction rose by 1/1000 since the last call (so at most ~1000
  // calls, also past an estimated total); 1 is finish()'s to report.
  void report(double done) {
    next_ = done + step_;
    const double f = estimated_ ? saturating_fraction(done, total_) : done / total_;
    if (f < last_ + (1e-3 - 1e-12) || f >= 1.0) return;  // (round-off: a rise of exactly 1/1000)
    last_ = f;
    callback_(f, stage_);
  }

  const ProgressCallback& callback_;
  std::string_view stage_;
  double total_;
  bool estimated_;
  double step_;
  double next_ = HUGE_VAL, last_ = 0.0;
  bool finished_ = false;
};

}  // namespace ifem
