#include "harness/commands/entry_point.h"

#include <atomic>
#include <csignal>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "harness/commands/cli.h"
#include "harness/run/replicate_farm.h"
#include "harness/session/session.h"

namespace pcbench {
namespace {

std::atomic<bool> g_interrupted{false};

extern "C" void on_interrupt(int) {
  g_interrupted.store(true);
  std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C stops at once
}

}  // namespace

int run_main(int argc, char** argv) {
  start_ranks(&argc, &argv);
  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (this_rank() == 0) return stop_ranks(run_cli(args, std::cout, std::cerr, &g_interrupted), "");
  // The other ranks of an MPI job compute their share of rank 0's runs and write nothing; what
  // they would have said is kept for the message if one cannot take part.
  if (!farms_command(args)) return stop_ranks(kExitOk, "");
  std::ostringstream out, err;
  const int status = run_cli(args, out, err, &g_interrupted);
  return stop_ranks(status, err.str());
}

}  // namespace pcbench
