// ProgressReporter: line contents (step/total, percent, ETA = elapsed (1 - f)/f), duration
// format, quiet modes, and the cost bound (the clock is read far less often than update()
// is called).
#include <catch2/catch.hpp>

#include <cstdio>
#include <sstream>

#include <unistd.h>

#include "granule/io/progress.hpp"

using namespace granule;

TEST_CASE("ProgressReporter formats durations and ETA", "[io][progress]") {
  CHECK(io::ProgressReporter::format_duration(3725.0) == "1:02:05");
  CHECK(io::ProgressReporter::format_duration(65.4) == "1:05");
  CHECK(io::ProgressReporter::format_duration(5.4) == "0:05");
  CHECK(io::ProgressReporter::format_duration(-1.0) == "?");
  CHECK(io::ProgressReporter::eta(0.25, 10.0) == Approx(30.0));
  CHECK(io::ProgressReporter::eta(1.0, 10.0) == 0.0);
  CHECK(std::isinf(io::ProgressReporter::eta(0.0, 10.0)));
}

TEST_CASE("ProgressReporter prints step, percent, time and a summary", "[io][progress]") {
  std::ostringstream out;
  io::ProgressOptions opt;
  opt.total_steps = 200;
  opt.mode = io::ProgressMode::On;
  opt.interval = 0.0;  // print at every clock read
  opt.stream = &out;
  opt.label = "run";
  io::ProgressReporter p(opt);
  REQUIRE(p.enabled());
  p.update(50, 0.005);
  const std::string first = out.str();
  CHECK(first.find("run: step 50/200 (25.0 %)") != std::string::npos);
  CHECK(first.find("t = 0.005 s") != std::string::npos);
  CHECK(first.find("ETA") != std::string::npos);
  CHECK(first.back() == '\n');  // not a terminal: whole lines
  p.finish(200, 0.02);
  CHECK(out.str().find("run: done, 200 steps in") != std::string::npos);
  CHECK(out.str().find("simulated time 0.02 s") != std::string::npos);
}

TEST_CASE("ProgressReporter uses the end time when the step count is unknown", "[io][progress]") {
  std::ostringstream out;
  io::ProgressOptions opt;
  opt.end_time = 2.0;
  opt.mode = io::ProgressMode::On;
  opt.interval = 0.0;
  opt.stream = &out;
  io::ProgressReporter p(opt);
  p.update(7, 0.5);
  CHECK(out.str().find("step 7 (25.0 %)") != std::string::npos);
}

TEST_CASE("ProgressReporter stays quiet when asked and reads the clock rarely", "[io][progress]") {
  std::ostringstream out;
  io::ProgressOptions off;
  off.mode = io::ProgressMode::Off;
  off.stream = &out;
  io::ProgressReporter quiet(off);
  for (std::uint64_t s = 0; s < 1000; ++s) quiet.update(s, 0.0);
  quiet.finish(1000, 0.0);
  CHECK(out.str().empty());
  CHECK(quiet.clock_reads() == 0u);

  io::ProgressOptions autom;
  autom.stream = &out;  // Auto with a stream other than std::cerr never prints
  CHECK_FALSE(io::ProgressReporter(autom).enabled());
  io::ProgressOptions to_stderr;  // Auto on stderr: a line per interval on a terminal, per
  CHECK(io::ProgressReporter(to_stderr).enabled());  // log_interval in a log (issue 30)

  io::ProgressOptions on;
  on.mode = io::ProgressMode::On;
  on.interval = 3600.0;
  on.stream = &out;
  io::ProgressReporter p(on);
  const std::uint64_t n = 3'000'000;
  for (std::uint64_t s = 1; s <= n; ++s) p.update(s, 1e-6 * s);
  CHECK(p.clock_reads() < n / 100);
  // Only the first line (printed at the first check) within the hour-long interval.
  std::size_t lines = 0;
  for (char c : out.str()) lines += c == '\n';
  CHECK(lines == 1u);
}
