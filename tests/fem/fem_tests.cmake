# FE tests (included from tests/CMakeLists.txt): one executable per file as in
# every folder, plus the parallel-consistency tests run again under
# `mpiexec -np 2`, which compare a two-rank run with a one-rank run inside
# the same job.
# The ~1M-DoF case needs two ranks: it runs as fem.mpi_np2.slow_scaling_1M only.
set(FRETSIM_TEST_FILTER_slow_scaling "-Scaling.Ring1M")
fretsim_add_test_folder(fem fretsim_fem)

set(fretsim_mpi_env "OMPI_ALLOW_RUN_AS_ROOT=1;OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1;OMPI_MCA_rmaps_base_oversubscribe=1")
# The stress snapshot test also writes the HDF5 snapshot file.
if(TARGET test_fem_verification_stress_snapshots)
  target_link_libraries(test_fem_verification_stress_snapshots PRIVATE fretsim_output)
endif()

foreach(name unit_parallel_consistency unit_shifted_static_solver unit_surface_grid_map unit_surface_point_map
             verification_stress_snapshots)
  if(TARGET test_fem_${name})
    add_test(NAME fem.mpi_np2.${name}
      COMMAND ${MPIEXEC_EXECUTABLE} ${MPIEXEC_NUMPROC_FLAG} 2 ${MPIEXEC_PREFLAGS}
              $<TARGET_FILE:test_fem_${name}> ${MPIEXEC_POSTFLAGS})
    set_tests_properties(fem.mpi_np2.${name} PROPERTIES
      LABELS unit PROCESSORS 2 ENVIRONMENT "${fretsim_mpi_env}" TIMEOUT 300)
  endif()
endforeach()

# The scaling cases add the ranks' peak memory (MPI_Allreduce); the ~1M-DoF
# case runs on both cores.
if(TARGET test_fem_slow_scaling)
  target_link_libraries(test_fem_slow_scaling PRIVATE MPI::MPI_C)
  add_test(NAME fem.mpi_np2.slow_scaling_1M
    COMMAND ${MPIEXEC_EXECUTABLE} ${MPIEXEC_NUMPROC_FLAG} 2 ${MPIEXEC_PREFLAGS}
            $<TARGET_FILE:test_fem_slow_scaling> --gtest_filter=Scaling.Ring1M ${MPIEXEC_POSTFLAGS})
  set_tests_properties(fem.mpi_np2.slow_scaling_1M PROPERTIES
    LABELS slow PROCESSORS 2 ENVIRONMENT "${fretsim_mpi_env}" TIMEOUT 1800)
endif()

# The iterative solvers on a mesh distributed over two ranks (block size and
# near-null space built per rank).
if(TARGET test_fem_unit_iterative_solvers)
  add_test(NAME fem.mpi_np2.unit_iterative_solvers
    COMMAND ${MPIEXEC_EXECUTABLE} ${MPIEXEC_NUMPROC_FLAG} 2 ${MPIEXEC_PREFLAGS}
            $<TARGET_FILE:test_fem_unit_iterative_solvers> ${MPIEXEC_POSTFLAGS})
  set_tests_properties(fem.mpi_np2.unit_iterative_solvers PROPERTIES
    LABELS unit PROCESSORS 2 ENVIRONMENT "${fretsim_mpi_env}" TIMEOUT 300)
endif()

# The Winkler foundation, one body and the ring-housing pair: distributed
# over two ranks against each rank alone.
foreach(pair "winkler_foundation;WinklerFoundation" "winkler_pair;WinklerPair")
  list(GET pair 0 name)
  list(GET pair 1 suite)
  if(TARGET test_fem_verification_${name})
    add_test(NAME fem.mpi_np2.verification_${name}
      COMMAND ${MPIEXEC_EXECUTABLE} ${MPIEXEC_NUMPROC_FLAG} 2 ${MPIEXEC_PREFLAGS}
              $<TARGET_FILE:test_fem_verification_${name}>
              --gtest_filter=${suite}.SameOnOneAndTwoRanks ${MPIEXEC_POSTFLAGS})
    set_tests_properties(fem.mpi_np2.verification_${name} PROPERTIES
      LABELS verification PROCESSORS 2 ENVIRONMENT "${fretsim_mpi_env}" TIMEOUT 300)
  endif()
endforeach()

# The reduced Winkler solve against the full one needs a Craig–Bampton basis.
if(TARGET test_fem_verification_reduced_winkler)
  target_link_libraries(test_fem_verification_reduced_winkler PRIVATE fretsim_reduction)
endif()
