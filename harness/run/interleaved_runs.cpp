#include "harness/run/interleaved_runs.h"

#include <fmt/format.h>

#include <algorithm>
#include <map>

namespace pcbench {

std::vector<std::vector<std::size_t>> same_integrand_groups(
    const std::vector<const RunPlan*>& plans) {
  std::vector<std::vector<std::size_t>> groups;
  std::map<std::pair<const IntegrandEntry*, std::string>, std::size_t> index;
  for (std::size_t i = 0; i < plans.size(); ++i) {
    std::string params;
    for (const auto& [key, value] : plans[i]->integrand_params.values()) {
      params += key + "=" + to_text(value) + ";";
    }
    const auto [it, added] = index.try_emplace({plans[i]->integrand, params}, groups.size());
    if (added) groups.emplace_back();
    groups[it->second].push_back(i);
  }
  return groups;
}

std::vector<RunResult> execute_interleaved(const std::vector<const RunPlan*>& plans,
                                           const RunnerOptions& base, ProgressReporter& progress) {
  std::vector<RunResult> results(plans.size());
  std::vector<bool> started(plans.size(), false);
  for (const std::vector<std::size_t>& group : same_integrand_groups(plans)) {
    std::uint64_t work = 0;
    std::uint32_t rounds = 0;
    for (std::size_t i : group) {
      work += plans[i]->total_samples();
      rounds = std::max(rounds, plans[i]->replicates);
    }
    const RunPlan& first = *plans[group.front()];
    RunnerOptions options = base;
    options.samples_done = progress.run_started(
        fmt::format("{} runs on {}, interleaved", group.size(), first.integrand->name), work);
    bool cut_short = false;
    for (std::uint32_t r = 0; r < rounds && !cut_short; ++r) {
      for (std::size_t i : group) {
        if (r >= plans[i]->replicates) continue;
        options.first_replicate = r;
        options.replicate_count = 1;
        RunResult part = execute_run(*plans[i], options);
        if (part.status == RunStatus::kNotRun) {
          cut_short = true;
          break;
        }
        if (!started[i]) {
          results[i] = std::move(part);
          started[i] = true;
        } else {
          append_part(results[i], std::move(part));
        }
      }
    }
    for (std::size_t i : group) {
      if (cut_short || !started[i]) {
        results[i] = not_run_result(*plans[i], "interrupted before the run finished");
      }
    }
    progress.run_finished(cut_short ? "interrupted" : "done", group.size());
    if (cut_short) break;
  }
  for (std::size_t i = 0; i < plans.size(); ++i) {
    if (!started[i] && results[i].error.empty()) {
      results[i] = not_run_result(*plans[i], "interrupted before the run started");
    }
  }
  return results;
}

}  // namespace pcbench
