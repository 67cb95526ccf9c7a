// `pcbench list [--json]`: the registry tables, with parameters, defaults and descriptions.
#pragma once

#include <iosfwd>

#include "harness/commands/command_options.h"

namespace pcbench {

void print_registry(std::ostream& out, bool as_json);

struct ListArguments {
  bool json = false;
};

// Adds `list` and its options to `app`.
CLI::App* add_list_command(CLI::App& app, ListArguments& args);

// `pcbench list`.
int list_command(const ListArguments& args, const CommandContext& context);

}  // namespace pcbench
