#!/bin/sh
# Builds the unit tests (ctest label `unit`) with AddressSanitizer and
# UndefinedBehaviorSanitizer in a build directory of their own and runs them.
#
#   scripts/check_sanitizers.sh [BUILD_DIR] [CTEST_REGEX]
#
# BUILD_DIR defaults to build-sanitize; CTEST_REGEX (e.g. '^(contact|app)\.')
# limits the tests, and the build, to those folders' unit tests. JOBS sets
# the parallelism (default 2). Flags differ from the normal build, so ccache
# keeps the two apart.
#
# Suppressions (scripts/sanitizers/): only third-party libraries.
#   lsan.supp: OpenMPI, PMIx, hwloc and HDF5 keep allocations for the life of
#     the process (initialised once, never finalised before exit); they are
#     reported as leaks though nothing is lost.
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build-sanitize}
regex=${2:-}
jobs=${JOBS:-2}
cd "$here"
flags="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined"
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_C_FLAGS="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null

# The unit test executables (test_<folder>_unit_*), those of the regex's folders only.
targets=$(cmake --build "$build" --target help | sed -n 's/^\(test_[a-z]*_unit_[a-z_0-9]*\):.*/\1/p')
if [ -n "$regex" ]; then
  folders=$(printf '%s' "$regex" | tr -c 'a-z\n' ' ')
  selected=""
  for target in $targets; do
    for folder in $folders; do
      case $target in test_${folder}_unit_*) selected="$selected $target" ;; esac
    done
  done
  targets=$selected
fi
# The app tests run the program too.
case $targets in *test_app_*) targets="fretsim $targets" ;; esac
cmake --build "$build" --target $targets -j "$jobs"

# Full unwinding at each allocation: the third-party frames the suppressions
# name are otherwise lost behind libraries built without frame pointers.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:detect_odr_violation=0:fast_unwind_on_malloc=0"
export LSAN_OPTIONS="suppressions=$here/scripts/sanitizers/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cd "$build"
# The two-rank runs of verification executables carry the unit label but
# are not unit tests; their executables are not built here.
not_unit="mpi_np2\.(verification|slow)_"
if [ -n "$regex" ]; then
  ctest -L unit -R "$regex" -E "$not_unit" -j "$jobs" --output-on-failure
else
  ctest -L unit -E "$not_unit" -j "$jobs" --output-on-failure
fi
