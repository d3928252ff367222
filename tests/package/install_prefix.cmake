# Installs sphray into a scratch directory, then moves it (every installed file must work from
# wherever the prefix ends up: the CMake package and sphray.pc are relocatable).
# Arguments: -DBINARY_DIR=<sphray build> -DPREFIX=<where the moved prefix ends up>
file(REMOVE_RECURSE ${PREFIX} ${PREFIX}.staging)
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BINARY_DIR} --prefix ${PREFIX}.staging
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "failed (${rc}): cmake --install ${BINARY_DIR}")
endif()
file(RENAME ${PREFIX}.staging ${PREFIX})
message("installed and moved to ${PREFIX}")
