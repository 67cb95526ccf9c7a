// Progress of a session on stderr: one updating line on a terminal (runs done, the current
// run's share and sample rate, time left), one line per finished run otherwise (logs, CI),
// nothing with --quiet.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <iosfwd>
#include <mutex>
#include <string>
#include <thread>

namespace pcbench {

enum class ProgressMode { kQuiet, kLines, kTerminal };

// kTerminal when `err` is the process's standard error and that is a terminal, else kLines
// (kQuiet when asked).
ProgressMode progress_mode(const std::ostream& err, bool quiet);

class ProgressReporter {
 public:
  // `total_work`: the session's planned samples × replicates, for the time left (later work,
  // such as escalated stages, is added with add_work).
  ProgressReporter(ProgressMode mode, std::ostream& err, std::size_t total_runs,
                   std::uint64_t total_work);
  ~ProgressReporter();
  ProgressReporter(const ProgressReporter&) = delete;
  ProgressReporter& operator=(const ProgressReporter&) = delete;

  void add_work(std::uint64_t work, std::size_t runs);
  // A run of `work` samples × replicates begins; the runner counts its finished samples (summed
  // over replicates) in the returned counter, which stays valid until run_finished.
  std::atomic<std::uint64_t>* run_started(const std::string& label, std::uint64_t work);
  // `outcome`: what the run came to (its verdict or status), for the log line. `runs`: how many
  // runs the finished work was (interleaved runs are reported as one piece of work).
  void run_finished(const std::string& outcome, std::size_t runs = 1);
  // A message that must not be overdrawn by the updating line (a pilot's choice, a warning).
  void message(const std::string& text);

 private:
  std::string status_line(bool finished) const;
  void redraw_loop();
  void clear_line();

  ProgressMode mode_;
  std::ostream& err_;
  std::size_t total_runs_;
  std::uint64_t total_work_;
  std::size_t runs_done_ = 0;
  std::uint64_t work_done_ = 0;  // of finished runs
  std::string label_;
  std::uint64_t run_work_ = 0;
  std::atomic<std::uint64_t> run_samples_{0};
  std::chrono::steady_clock::time_point session_start_, run_start_;

  mutable std::mutex mutex_;  // guards the fields above against the redraw thread
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread redraw_;
};

}  // namespace pcbench
