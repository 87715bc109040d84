#pragma once
#include <string>

namespace fretsim::fem
{
  /// The deal.II version this library was built against, e.g. "deal.II 9.4.1"
  /// (reported by `fretsim --version`).
  std::string library_versions();
} // namespace fretsim::fem
