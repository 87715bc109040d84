#pragma once
// Interruption: SIGINT/SIGTERM ask the running scene to stop after the current
// step, so the results file is closed cleanly with the steps done so far.

namespace fretsim::app
{
  /// Installs the handlers (idempotent).
  void install_interrupt_handlers();
  /// True once SIGINT or SIGTERM was received.
  bool interrupt_requested();
  /// The signal number received, 0 if none.
  int interrupt_signal();
} // namespace fretsim::app
