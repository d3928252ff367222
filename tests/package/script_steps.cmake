# What the package tests' scripts (run with cmake -P) share: a fresh scratch directory, and a
# step that runs a command, shows its output (also left in `output` for the caller) and stops
# the test when it fails.

# WORK_DIR emptied and made again: a test never reads what an earlier run left.
function(fresh_work_dir)
  file(REMOVE_RECURSE ${WORK_DIR})
  file(MAKE_DIRECTORY ${WORK_DIR})
endfunction()

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  set(output "${out}" PARENT_SCOPE)
  message("${out}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}")
  endif()
endfunction()
