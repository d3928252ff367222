# `mpiexec -n RANKS sphray-mpi ARGS` on input it must refuse: every rank must stop with a
# non-zero status and the one-line reason WORDS, never hang (the test's TIMEOUT would catch
# that). -D: SPHRAY_MPI, MPIEXEC, MPIEXEC_FLAGS (a list), RANKS, ARGS (one string), WORDS.
separate_arguments(args UNIX_COMMAND "${ARGS}")
execute_process(COMMAND ${MPIEXEC} -n ${RANKS} ${MPIEXEC_FLAGS} ${SPHRAY_MPI} ${args}
                RESULT_VARIABLE status ERROR_VARIABLE errors OUTPUT_VARIABLE output TIMEOUT 50)
if(status EQUAL 0)
  message(FATAL_ERROR "failed (expected a non-zero status): ${output}")
endif()
string(FIND "${errors}" "${WORDS}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "failed (status ${status}, no '${WORDS}' in): ${errors}")
endif()
message(STATUS "refused (status ${status}): ${errors}")
