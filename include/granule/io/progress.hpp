#pragma once
// Progress line on stderr for long runs: step (of total), percent, simulated time, steps per
// second (since the previous line), estimated time to completion, and a summary at the end.
//
// Cheap enough to call every step: update() only compares the step with a precomputed next
// check; the clock is read every `stride` steps, the stride adapting so that the clock is
// read about 20 times per second, and a line is printed at most every `interval` seconds.
// ETA = elapsed (1 - f)/f with f the completed fraction (steps, or time over end time).
// Mode Auto rewrites one line every `interval` seconds when stderr is a terminal (isatty), and
// prints a new line every `log_interval` seconds when it is not (a log file, CI), so that a long
// run shows its ETA in a log too without flooding it; On prints every `interval` wherever the
// output goes, Off silences it.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <limits>
#include <ostream>
#include <string>

#if defined(_WIN32)
#include <io.h>
#else
#include <unistd.h>
#endif

namespace granule::io {

enum class ProgressMode { Auto, On, Off };

struct ProgressOptions {
  std::uint64_t total_steps = 0;  ///< steps of the run (0: unknown)
  double end_time = 0.0;          ///< simulated end time [s], for the percentage when total_steps == 0
  ProgressMode mode = ProgressMode::Auto;
  double interval = 0.5;          ///< wall-clock time between lines on a terminal, or with On [s]
  double log_interval = 30.0;     ///< with Auto, time between lines when not on a terminal [s]
  std::string label = "granule";  ///< prefix of each line
  std::ostream* stream = nullptr; ///< output (default std::cerr)
};

/// Progress reporter; see the file comment.
class ProgressReporter {
 public:
  using Clock = std::chrono::steady_clock;

  explicit ProgressReporter(ProgressOptions options = {})
      : opt_(std::move(options)), out_(opt_.stream ? opt_.stream : &std::cerr), start_(Clock::now()),
        last_check_(start_), last_print_(start_) {
    terminal_ = stderr_is_terminal() && out_ == &std::cerr;
    enabled_ = opt_.mode == ProgressMode::On || (opt_.mode == ProgressMode::Auto && out_ == &std::cerr);
    interval_ = opt_.mode == ProgressMode::Auto && !terminal_ ? opt_.log_interval : opt_.interval;
    if (!enabled_) next_check_ = UINT64_MAX;
  }

  bool enabled() const { return enabled_; }
  /// How often the clock has been read (for tests of the cost).
  std::uint64_t clock_reads() const { return clock_reads_; }

  /// Call every step (or as often as convenient) with the step count and simulated time [s].
  void update(std::uint64_t step, double time) {
    if (step < next_check_) return;
    check(step, time);
  }

  /// Prints the summary line (when enabled).
  void finish(std::uint64_t step, double time) {
    if (!enabled_ || finished_) return;
    finished_ = true;
    const double elapsed = seconds(Clock::now() - start_);
    std::string s = opt_.label + ": done, " + std::to_string(step) + " steps in " + format_duration(elapsed);
    if (elapsed > 0.0) s += " (" + number(static_cast<double>(step) / elapsed, "%.3g") + " steps/s)";
    s += ", simulated time " + number(time, "%.6g") + " s";
    if (terminal_ && printed_) *out_ << '\n';
    *out_ << s << '\n' << std::flush;
  }

  /// "H:MM:SS" (or "M:SS" below one hour).
  static std::string format_duration(double seconds_total) {
    if (!std::isfinite(seconds_total) || seconds_total < 0.0) return "?";
    const auto s = static_cast<std::uint64_t>(std::llround(seconds_total));
    char buf[48];
    if (s >= 3600) {
      std::snprintf(buf, sizeof(buf), "%llu:%02llu:%02llu", static_cast<unsigned long long>(s / 3600),
                    static_cast<unsigned long long>(s / 60 % 60), static_cast<unsigned long long>(s % 60));
    } else {
      std::snprintf(buf, sizeof(buf), "%llu:%02llu", static_cast<unsigned long long>(s / 60),
                    static_cast<unsigned long long>(s % 60));
    }
    return buf;
  }

  /// Remaining wall time [s] after `elapsed` [s] for a completed fraction in (0, 1].
  static double eta(double fraction, double elapsed) {
    if (!(fraction > 0.0)) return std::numeric_limits<double>::infinity();
    return elapsed * (1.0 - std::min(fraction, 1.0)) / fraction;
  }

 private:
  static bool stderr_is_terminal() {
#if defined(_WIN32)
    return _isatty(_fileno(stderr)) != 0;
#else
    return isatty(fileno(stderr)) != 0;
#endif
  }

  static double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

  static std::string number(double v, const char* fmt) {
    char buf[64];
    std::snprintf(buf, sizeof(buf), fmt, v);
    return buf;
  }

  void check(std::uint64_t step, double time) {
    const Clock::time_point now = Clock::now();
    ++clock_reads_;
    // Adapt the stride so that the clock is read about every 50 ms.
    const double since_check = seconds(now - last_check_);
    const std::uint64_t steps_since_check = step - last_check_step_;
    if (since_check > 0.0 && steps_since_check > 0) {
      const double rate = static_cast<double>(steps_since_check) / since_check;
      stride_ = static_cast<std::uint64_t>(std::clamp(rate * 0.05, 1.0, 1e6));
    }
    last_check_ = now;
    last_check_step_ = step;
    next_check_ = step + stride_;
    if (seconds(now - last_print_) < interval_ && printed_) return;
    print(step, time, now);
  }

  void print(std::uint64_t step, double time, Clock::time_point now) {
    const double elapsed = seconds(now - start_);
    const double since_print = seconds(now - last_print_);
    std::string s = opt_.label + ": step " + std::to_string(step);
    double fraction = -1.0;
    if (opt_.total_steps > 0) {
      s += "/" + std::to_string(opt_.total_steps);
      fraction = static_cast<double>(step) / static_cast<double>(opt_.total_steps);
    } else if (opt_.end_time > 0.0) {
      fraction = time / opt_.end_time;
    }
    if (fraction >= 0.0) s += " (" + number(100.0 * fraction, "%.1f") + " %)";
    s += " | t = " + number(time, "%.6g") + " s";
    if (since_print > 0.0 && step > last_print_step_) {
      s += " | " + number(static_cast<double>(step - last_print_step_) / since_print, "%.3g") + " steps/s";
    }
    if (fraction > 0.0) s += " | ETA " + format_duration(eta(fraction, elapsed));
    if (terminal_) {
      const std::size_t width = s.size();
      if (s.size() < last_width_) s.append(last_width_ - s.size(), ' ');
      last_width_ = width;
      *out_ << '\r' << s << std::flush;
    } else {
      *out_ << s << '\n' << std::flush;
    }
    printed_ = true;
    last_print_ = now;
    last_print_step_ = step;
  }

  ProgressOptions opt_;
  std::ostream* out_;
  bool terminal_ = false;
  double interval_ = 0.5;
  bool enabled_ = false;
  bool printed_ = false;
  bool finished_ = false;
  Clock::time_point start_;
  Clock::time_point last_check_;
  Clock::time_point last_print_;
  std::uint64_t next_check_ = 0;
  std::uint64_t stride_ = 1;
  std::uint64_t last_check_step_ = 0;
  std::uint64_t last_print_step_ = 0;
  std::uint64_t clock_reads_ = 0;
  std::size_t last_width_ = 0;
};

}  // namespace granule::io
