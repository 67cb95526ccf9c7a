#include "results/context.h"

#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <memory>
#include <thread>

namespace pcbench {
namespace {

// Output of a shell command, trailing newline removed; empty on failure.
std::string command_output(const std::string& command) {
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  if (!pipe) return {};
  std::string out;
  std::array<char, 256> buffer{};
  while (std::fgets(buffer.data(), static_cast<int>(buffer.size()), pipe.get()) != nullptr) {
    out += buffer.data();
  }
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}

std::string cpu_model() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(' ', colon + 1));
    }
  }
  return "unknown";
}

std::string utc_now_iso8601() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  std::array<char, 32> text{};
  std::strftime(text.data(), text.size(), "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text.data();
}

}  // namespace

const char* pcbench_version() {
  return PCBENCH_VERSION;
}

Context gather_context(std::vector<std::string> argv, std::uint64_t seed, unsigned threads) {
  Context context;
  context.date = utc_now_iso8601();
  std::array<char, 256> host{};
  context.host = gethostname(host.data(), host.size() - 1) == 0 ? host.data() : "unknown";
  context.cpu = cpu_model();
  context.cores = std::thread::hardware_concurrency();
  context.compiler = PCBENCH_COMPILER;
  context.flags = PCBENCH_CXX_FLAGS;
  context.flags.erase(0, context.flags.find_first_not_of(' '));
  context.build_type = PCBENCH_BUILD_TYPE;
  // The commit of the source tree the binary was built from, read now (a build-time value goes
  // stale between rebuilds).
  const std::string git = "git -C '" PCBENCH_SOURCE_DIR "' ";
  context.git_commit = command_output(git + "rev-parse HEAD 2>/dev/null");
  const bool looks_like_commit =
      context.git_commit.size() == 40 &&
      context.git_commit.find_first_not_of("0123456789abcdef") == std::string::npos;
  if (!looks_like_commit) {
    context.git_commit = "unknown";
    context.git_dirty = "unknown";
  } else {
    context.git_dirty =
        command_output(git + "status --porcelain --untracked-files=no 2>/dev/null").empty()
            ? "false"
            : "true";
  }
  context.argv = std::move(argv);
  context.seed = seed;
  context.threads = threads;
  context.version = PCBENCH_VERSION;
  return context;
}

}  // namespace pcbench
