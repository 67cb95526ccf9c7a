#include "harness/run/progress.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <iostream>

namespace pcbench {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

std::string duration_text(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0.0) return "?";
  if (seconds < 60.0) return fmt::format("{:.0f} s", seconds);
  if (seconds < 3600.0)
    return fmt::format("{:.0f} min {:02.0f} s", std::floor(seconds / 60.0),
                       std::fmod(seconds, 60.0));
  return fmt::format("{:.0f} h {:02.0f} min", std::floor(seconds / 3600.0),
                     std::fmod(seconds, 3600.0) / 60.0);
}

std::string rate_text(double per_second) {
  if (per_second >= 1e6) return fmt::format("{:.1f} M", per_second / 1e6);
  if (per_second >= 1e3) return fmt::format("{:.1f} k", per_second / 1e3);
  return fmt::format("{:.0f}", per_second);
}

// The terminal line is redrawn at this period: often enough to look alive, rarely enough to
// cost nothing beside the work.
constexpr auto kRedrawPeriod = std::chrono::milliseconds(250);

}  // namespace

ProgressMode progress_mode(const std::ostream& err, bool quiet) {
  if (quiet) return ProgressMode::kQuiet;
  return &err == &std::cerr && isatty(STDERR_FILENO) ? ProgressMode::kTerminal
                                                     : ProgressMode::kLines;
}

ProgressReporter::ProgressReporter(ProgressMode mode, std::ostream& err, std::size_t total_runs,
                                   std::uint64_t total_work)
    : mode_(mode),
      err_(err),
      total_runs_(total_runs),
      total_work_(total_work),
      session_start_(Clock::now()),
      run_start_(session_start_) {
  if (mode_ == ProgressMode::kTerminal) redraw_ = std::thread([this] { redraw_loop(); });
}

ProgressReporter::~ProgressReporter() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (redraw_.joinable()) redraw_.join();
  if (mode_ == ProgressMode::kTerminal) clear_line();
}

void ProgressReporter::add_work(std::uint64_t work, std::size_t runs) {
  std::lock_guard lock(mutex_);
  total_work_ += work;
  total_runs_ += runs;
}

std::atomic<std::uint64_t>* ProgressReporter::run_started(const std::string& label,
                                                          std::uint64_t work) {
  std::lock_guard lock(mutex_);
  label_ = label;
  run_work_ = work;
  run_samples_.store(0);
  run_start_ = Clock::now();
  return &run_samples_;
}

void ProgressReporter::run_finished(const std::string& outcome, std::size_t runs) {
  std::lock_guard lock(mutex_);
  runs_done_ += runs;
  work_done_ += run_work_;
  if (mode_ == ProgressMode::kLines) {
    err_ << status_line(true) << ": " << outcome << "\n" << std::flush;
  }
  run_work_ = 0;
  run_samples_.store(0);
}

void ProgressReporter::message(const std::string& text) {
  if (mode_ == ProgressMode::kQuiet) return;
  std::lock_guard lock(mutex_);
  if (mode_ == ProgressMode::kTerminal) clear_line();
  err_ << text << "\n" << std::flush;
}

// "[3/113] pcbpt × door 42% · 1.9 M samples/s · about 1 min 20 s left". The time left assumes
// the remaining work costs what the finished work did per sample: a rough guide when a suite
// mixes cheap and expensive integrands, which is why it says "about".
std::string ProgressReporter::status_line(bool finished) const {
  const std::uint64_t in_run = finished ? run_work_ : std::min(run_samples_.load(), run_work_);
  const double run_seconds = seconds_since(run_start_);
  const double done = static_cast<double>(work_done_ + (finished ? 0 : in_run));
  const double elapsed = seconds_since(session_start_);
  const double left = done > 0.0 ? elapsed * (static_cast<double>(total_work_) - done) / done : NAN;
  const double rate = run_seconds > 0.0 ? static_cast<double>(in_run) / run_seconds : 0.0;
  std::string line =
      fmt::format("[{}/{}] {}", runs_done_ + (finished ? 0 : 1), total_runs_, label_);
  if (!finished && run_work_ > 0) {
    line += fmt::format(" {:.0f}%",
                        100.0 * static_cast<double>(in_run) / static_cast<double>(run_work_));
  }
  if (in_run > 0) line += fmt::format(" · {} samples/s", rate_text(rate));
  if (finished) line += fmt::format(" · {:.2f} s", run_seconds);
  if (done < static_cast<double>(total_work_)) {
    line += fmt::format(" · about {} left", duration_text(left));
  }
  return line;
}

void ProgressReporter::redraw_loop() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    if (!label_.empty()) {
      // \r and erase-to-end-of-line redraw in place.
      err_ << "\r" << status_line(false) << "\x1b[K" << std::flush;
    }
    wake_.wait_for(lock, kRedrawPeriod, [this] { return stopping_; });
  }
}

void ProgressReporter::clear_line() {
  err_ << "\r\x1b[K" << std::flush;
}

}  // namespace pcbench
