# One scene rendered twice with the same options: by `sphray render` in one process, and by
# `sphray-mpi render` under mpiexec with RANKS ranks; the two files must be equal byte for byte.
# -D: SPHRAY, SPHRAY_MPI, MPIEXEC, MPIEXEC_FLAGS (a list), RANKS, OPTIONS (one string), WORK_DIR,
# and MPI_OPTIONS (one string) for sphray-mpi alone; EXPECT, if given, a regular expression
# sphray-mpi's output must match.
separate_arguments(options UNIX_COMMAND "${OPTIONS}")
separate_arguments(mpi_options UNIX_COMMAND "${MPI_OPTIONS}")
file(MAKE_DIRECTORY ${WORK_DIR})
set(single ${WORK_DIR}/single.ppm)
set(ranks ${WORK_DIR}/ranks.ppm)
file(REMOVE ${single} ${ranks})

execute_process(COMMAND ${SPHRAY} render -q ${options} -o ${single} RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "sphray render failed (${status})")
endif()
execute_process(COMMAND ${MPIEXEC} -n ${RANKS} ${MPIEXEC_FLAGS} ${SPHRAY_MPI} render ${options}
                        ${mpi_options} -o ${ranks}
                RESULT_VARIABLE status OUTPUT_VARIABLE said ERROR_VARIABLE said TIMEOUT 100)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "mpiexec -n ${RANKS} sphray-mpi render failed (${status}):\n${said}")
endif()
if(DEFINED EXPECT AND NOT said MATCHES "${EXPECT}")
  message(FATAL_ERROR "sphray-mpi render did not say '${EXPECT}':\n${said}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${single} ${ranks} RESULT_VARIABLE status)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "${RANKS} ranks: the image differs from the single process's")
endif()
message(STATUS "${RANKS} ranks: the same image as one process, byte for byte")
