#include "app/fe_command.h"

#include <stdexcept>

namespace fretsim::app
{
  std::vector<ParameterSpec> fe_parameter_specs()
  {
    return {};
  }

  std::vector<std::string> run_fe_command(const RingHousingCommandOptions &, std::ostream &)
  {
    throw std::logic_error("fretsim fe: not implemented yet");
  }
} // namespace fretsim::app
