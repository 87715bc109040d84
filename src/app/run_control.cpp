#include "app/run_control.h"

#include <csignal>

namespace fretsim::app
{
  namespace
  {
    volatile std::sig_atomic_t received_signal = 0;

    extern "C" void on_signal(int signal_number) { received_signal = signal_number; }
  } // namespace

  void install_interrupt_handlers()
  {
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
  }

  bool interrupt_requested() { return received_signal != 0; }

  int interrupt_signal() { return received_signal; }
} // namespace fretsim::app
