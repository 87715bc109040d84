#pragma once
#include <string>

namespace fretsim::reduction
{
  /// PETSc and SLEPc versions this library was built against (for
  /// `fretsim --version`). Reading them needs no MPI initialisation.
  std::string library_versions();
} // namespace fretsim::reduction
