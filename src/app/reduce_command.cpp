#include "app/reduce_command.h"

#include <stdexcept>

namespace fretsim::app
{
  std::vector<ParameterSpec> reduce_parameter_specs()
  {
    return {};
  }

  std::vector<std::string> run_reduce_command(const RingHousingCommandOptions &, std::ostream &)
  {
    throw std::logic_error("fretsim reduce: not implemented yet");
  }
} // namespace fretsim::app
