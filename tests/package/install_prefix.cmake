# Installs sphray into a scratch directory, then moves it (every installed file must work from
# wherever the prefix ends up: the CMake package and sphray.pc are relocatable).
# Arguments: -DBINARY_DIR=<sphray build> -DPREFIX=<where the moved prefix ends up>
#            -DEXPECTED=<files the prefix must hold, relative to it, separated by commas>
file(REMOVE_RECURSE ${PREFIX} ${PREFIX}.staging)
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BINARY_DIR} --prefix ${PREFIX}.staging
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "failed (${rc}): cmake --install ${BINARY_DIR}")
endif()
file(RENAME ${PREFIX}.staging ${PREFIX})
string(REPLACE "," ";" expected "${EXPECTED}")
foreach(file IN LISTS expected)
  if(NOT EXISTS ${PREFIX}/${file})
    message(FATAL_ERROR "failed: cmake --install left out ${file}")
  endif()
endforeach()
message("installed and moved to ${PREFIX}")
