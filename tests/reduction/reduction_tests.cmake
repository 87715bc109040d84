# Reduction tests (included from tests/CMakeLists.txt): one executable per
# file, plus the Craig–Bampton and raceway operator verifications again under
# `mpiexec -np 2` (the same numbers from a distributed model).
# hdf5: to write an older model file; coupling: the footprint interpolation the run uses
fretsim_add_test_folder(reduction fretsim_reduction fretsim_coupling Eigen3::Eigen fretsim_hdf5)

foreach(name verification_craig_bampton verification_raceway_operator)
  if(TARGET test_reduction_${name})
    add_test(NAME reduction.mpi_np2.${name}
      COMMAND ${MPIEXEC_EXECUTABLE} ${MPIEXEC_NUMPROC_FLAG} 2 ${MPIEXEC_PREFLAGS}
              $<TARGET_FILE:test_reduction_${name}> ${MPIEXEC_POSTFLAGS})
    set_tests_properties(reduction.mpi_np2.${name} PROPERTIES
      LABELS verification PROCESSORS 2 ENVIRONMENT "${fretsim_mpi_env}" TIMEOUT 600)
  endif()
endforeach()
