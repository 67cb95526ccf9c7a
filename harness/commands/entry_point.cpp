#include "harness/commands/entry_point.h"

#include <atomic>
#include <csignal>
#include <iostream>
#include <string>
#include <vector>

#include "harness/commands/cli.h"

namespace pcbench {
namespace {

std::atomic<bool> g_interrupted{false};

extern "C" void on_interrupt(int) {
  g_interrupted.store(true);
  std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C stops at once
}

}  // namespace

int run_main(int argc, char** argv) {
  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
  const std::vector<std::string> args(argv + 1, argv + argc);
  return run_cli(args, std::cout, std::cerr, &g_interrupted);
}

}  // namespace pcbench
