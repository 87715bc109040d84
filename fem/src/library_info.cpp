#include <fretsim/fem/library_info.h>

#include <deal.II/base/config.h>

namespace fretsim::fem
{
  std::string library_versions() { return std::string("deal.II ") + DEAL_II_PACKAGE_VERSION; }
} // namespace fretsim::fem
