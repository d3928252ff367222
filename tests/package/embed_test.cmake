# Installs sphray to a temporary prefix, moves the prefix elsewhere (the package must be
# relocatable), then configures, builds and runs docs/examples/embed against it, linked with
# the static library (sphray::kernel) and with the shared one (sphray::kernel_shared).
# Arguments: -DBINARY_DIR=<sphray build> -DEXAMPLE_DIR=<docs/examples/embed> -DWORK_DIR=<scratch>
#            -DGENERATOR=<generator> -DCXX_FLAGS=<the build's> -DLINKER_FLAGS=<the build's>
# The build's own compiler and linker flags reach the example, so that in a sanitizer build it
# links the sanitizer runtimes the installed library needs, however ctest was started.
include(${CMAKE_CURRENT_LIST_DIR}/script_steps.cmake)
fresh_work_dir()

run(${CMAKE_COMMAND} --install ${BINARY_DIR} --prefix ${WORK_DIR}/staging)
file(RENAME ${WORK_DIR}/staging ${WORK_DIR}/moved)
run(${CMAKE_COMMAND} -S ${EXAMPLE_DIR} -B ${WORK_DIR}/build -G ${GENERATOR}
    -DCMAKE_PREFIX_PATH=${WORK_DIR}/moved -DCMAKE_BUILD_TYPE=Release
    "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${LINKER_FLAGS}")
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run(${WORK_DIR}/build/embed)
run(${WORK_DIR}/build/embed_shared)
run(${WORK_DIR}/build/double_precision)
