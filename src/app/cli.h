#pragma once

namespace fretsim::app
{
  /// The `fretsim` command line. Exit codes: 0 ok, 2 bad input (nothing is
  /// written), 1 internal failure, 128 + signal when interrupted.
  int run_command_line(int argc, char **argv);
} // namespace fretsim::app
