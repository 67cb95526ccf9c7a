// The pcbench executable: the command line, plus Ctrl-C handling (finish the report of the runs
// that finished, exit 130).
#include <atomic>
#include <csignal>
#include <iostream>
#include <string>
#include <vector>

#include "harness/cli.h"

namespace {

std::atomic<bool> g_interrupted{false};

extern "C" void on_interrupt(int) {
  g_interrupted.store(true);
  std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C stops at once
}

}  // namespace

int main(int argc, char** argv) {
  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
  const std::vector<std::string> args(argv + 1, argv + argc);
  return pcbench::run_cli(args, std::cout, std::cerr, &g_interrupted);
}
