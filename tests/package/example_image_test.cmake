# Builds one of the C API's examples against an installed sphray, runs it, and checks that its
# image is the `sphray` command's, byte for byte: both write PPM P3 files the same way, so equal
# files mean equal pixels.
# Arguments: -DLANGUAGE=c|rust -DPREFIX=<installed sphray> -DLIBDIR=<lib> -DEXAMPLE_DIR=<docs/examples/...>
#            -DWORK_DIR=<scratch> -DSPHRAY=<the sphray command> -DTOOL=<cc or cargo>
#            -DEXTRA_FLAGS=<compiler and linker flags for C, e.g. the build's sanitizers>
include(${CMAKE_CURRENT_LIST_DIR}/script_steps.cmake)
fresh_work_dir()

set(pc_path PKG_CONFIG_PATH=${PREFIX}/${LIBDIR}/pkgconfig)
if(LANGUAGE STREQUAL "c")
  # The README's one-liner: cc app.c $(pkg-config --cflags --libs sphray).
  execute_process(COMMAND ${CMAKE_COMMAND} -E env ${pc_path} pkg-config --cflags --libs sphray
                  OUTPUT_VARIABLE pc_flags RESULT_VARIABLE rc OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): pkg-config --cflags --libs sphray")
  endif()
  message("pkg-config --cflags --libs sphray: ${pc_flags}")
  separate_arguments(pc_flags UNIX_COMMAND "${pc_flags}")
  separate_arguments(extra UNIX_COMMAND "${EXTRA_FLAGS}")
  set(program ${WORK_DIR}/render_normals)
  run(${TOOL} -std=c99 -O2 -Wall -Wextra -Werror ${extra} ${EXAMPLE_DIR}/render_normals.c
      ${pc_flags} -lm -Wl,-rpath,${PREFIX}/${LIBDIR} -o ${program})
else()
  run(${CMAKE_COMMAND} -E env ${pc_path} ${TOOL} build --offline --locked --release --quiet
      --manifest-path ${EXAMPLE_DIR}/Cargo.toml --target-dir ${WORK_DIR}/target)
  set(program ${WORK_DIR}/target/release/sphray-normals)
endif()

# The scene's own size, and an odd one (another aspect ratio, pixel sizes that do not divide).
foreach(size "" "123 77")
  separate_arguments(size_args UNIX_COMMAND "${size}")
  set(command_size)
  set(label "the scene's size")
  if(size_args)
    list(GET size_args 0 w)
    list(GET size_args 1 h)
    set(command_size -W ${w} -H ${h})
    set(label "${w}x${h}")
  endif()
  run(${program} ${WORK_DIR}/example.ppm ${size_args})
  run(${SPHRAY} render -s single -m normals --spp 1 ${command_size} -o ${WORK_DIR}/command.ppm)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${WORK_DIR}/example.ppm
                          ${WORK_DIR}/command.ppm RESULT_VARIABLE differ)
  if(differ)
    message(FATAL_ERROR "failed: ${WORK_DIR}/example.ppm differs from the command's command.ppm")
  endif()
  file(SIZE ${WORK_DIR}/example.ppm bytes)
  message("${LANGUAGE} example at ${label}: the same image as the command, byte for byte "
          "(${bytes} bytes)")
endforeach()
