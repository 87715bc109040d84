#pragma once
#include <string>

namespace fretsim::fem
{
  /// The deal.II version this library was built against, e.g. "deal.II 9.4.1"
  /// (reported by `fretsim --version`). The FE module itself lands with the
  /// FE issue; this is the folder's public header set.
  std::string library_versions();
} // namespace fretsim::fem
