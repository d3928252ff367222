# cpack -G DEB: the packages hold what they should and nothing else, libsphray-dev depends on
# libsphray2 of the same version, they install into a scratch root with dpkg (its own package
# database there; the host's libraries satisfy the dependencies, hence --force-depends), a
# program builds and runs against what they installed, and they remove cleanly, leaving no file.
# Nothing outside the scratch root changes: the maintainer scripts run outside a chroot
# (--force-script-chrootless), and the ldconfig that libsphray2's run is a stand-in that only
# records the call. dpkg needs root rights to set the files' owners:
# run as another user, the packages are unpacked with dpkg-deb -x instead, and not removed.
# Arguments: -DBINARY_DIR=<sphray build> -DWORK_DIR=<scratch> -DVERSION=<project version>
#            -DLIBDIR=<lib> -DCC=<C compiler> -DEXAMPLE=<docs/examples/c/render_normals.c>
#            -DEXTRA_FLAGS=<the build's compiler and linker flags>
#            -DHEADER_DIR=<kernel/include/sphray> -DNEED_TOOLS=<ON if the command is built>
#            -DSCENE_DIR=<render/scenes> -DPARTICLES=<ON if libsphray_particles is built>
cmake_policy(SET CMP0054 NEW)  # "quoted" strings in if() are strings
include(${CMAKE_CURRENT_LIST_DIR}/script_steps.cmake)
fresh_work_dir()

run(cpack -G DEB --config ${BINARY_DIR}/CPackConfig.cmake -B ${WORK_DIR})
message("${output}")
set(lib usr/${LIBDIR})
# Each package, and the files it must hold (its directories aside, nothing more).
set(files_libsphray2 ./${lib}/libsphray.so.2 ./${lib}/libsphray.so.${VERSION})
# The C particle loader, where the build has the particle readers (PARTICLES=ON).
if(PARTICLES)
  list(APPEND files_libsphray2 ./${lib}/libsphray_particles.so.0
       ./${lib}/libsphray_particles.so.${VERSION})
endif()
# libsphray-dev: every public header of the source tree, the generated version.h and
# version.hpp, the rest.
file(GLOB headers RELATIVE ${HEADER_DIR} ${HEADER_DIR}/*.h ${HEADER_DIR}/*.hpp)
list(TRANSFORM headers PREPEND ./usr/include/sphray/)
set(files_libsphray-dev ${headers} ./usr/include/sphray/version.h ./usr/include/sphray/version.hpp
    ./${lib}/libsphray.so ./${lib}/libsphray.a ./${lib}/pkgconfig/sphray.pc
    ./${lib}/cmake/sphray/sphrayConfig.cmake ./${lib}/cmake/sphray/sphrayConfigVersion.cmake
    ./${lib}/cmake/sphray/sphrayTargets.cmake ./${lib}/cmake/sphray/sphrayTargets-CONFIG.cmake)
if(PARTICLES)
  list(APPEND files_libsphray-dev ./usr/include/sphray/sphray_particles.h
       ./${lib}/libsphray_particles.so ./${lib}/pkgconfig/sphray_particles.pc)
endif()
# sphray: the command and the example scenes.
file(GLOB scenes RELATIVE ${SCENE_DIR} ${SCENE_DIR}/*.json)
list(TRANSFORM scenes PREPEND ./usr/share/sphray/scenes/)
set(files_sphray ./usr/bin/sphray ${scenes})
foreach(package libsphray2 libsphray-dev sphray)
  file(GLOB deb ${WORK_DIR}/${package}_${VERSION}_*.deb)
  if(NOT deb)
    if(package STREQUAL "sphray" AND NOT NEED_TOOLS)
      continue()
    endif()
    message(FATAL_ERROR "failed: no ${package}_${VERSION}_*.deb in ${WORK_DIR}")
  endif()
  run(dpkg-deb -c ${deb})
  message("dpkg-deb -c ${package}:\n${output}")
  # "lrwxrwxrwx root/root 0 date time ./path -> target": the path, directories left out.
  string(REGEX MATCHALL "\\./[^ \n]*[^/ \n](\n| ->)" listed "${output}")
  list(TRANSFORM listed REPLACE "(\n| ->)$" "")
  list(TRANSFORM listed REPLACE "sphrayTargets-[a-z]+\\.cmake$" "sphrayTargets-CONFIG.cmake")
  list(SORT listed)
  set(expected ${files_${package}})
  list(SORT expected)
  if(NOT listed STREQUAL expected)
    message(FATAL_ERROR "failed: ${package} holds\n  ${listed}\nexpected\n  ${expected}")
  endif()
  run(dpkg-deb -f ${deb} Package Version Depends)
  message("${output}")
  if(package STREQUAL "libsphray-dev" AND NOT output MATCHES "libsphray2 \\(= ${VERSION}\\)")
    message(FATAL_ERROR "failed: libsphray-dev does not depend on libsphray2 (= ${VERSION})")
  endif()
  if(package STREQUAL "libsphray2" AND NOT output MATCHES "libstdc\\+\\+6")
    message(FATAL_ERROR "failed: libsphray2 does not depend on libstdc++6")
  endif()
  list(APPEND debs ${deb})
  list(APPEND packages ${package})
endforeach()

set(root ${WORK_DIR}/root)
execute_process(COMMAND id -u OUTPUT_VARIABLE uid OUTPUT_STRIP_TRAILING_WHITESPACE)
file(WRITE ${WORK_DIR}/bin/ldconfig "#!/bin/sh\necho \"$@\" >> ${WORK_DIR}/ldconfig.calls\n")
file(CHMOD ${WORK_DIR}/bin/ldconfig PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE)
set(dpkg ${CMAKE_COMMAND} -E env "PATH=${WORK_DIR}/bin:$ENV{PATH}" dpkg --root=${root}
    --force-not-root --force-script-chrootless)
if(uid STREQUAL "0")
  file(MAKE_DIRECTORY ${root}/var/lib/dpkg/info ${root}/var/lib/dpkg/updates)
  file(TOUCH ${root}/var/lib/dpkg/status ${root}/var/lib/dpkg/available)
  run(${dpkg} --force-depends -i ${debs})
  message("dpkg -i into ${root}:\n${output}")
else()
  foreach(deb IN LISTS debs)
    run(dpkg-deb -x ${deb} ${root})
  endforeach()
endif()

# The unpacked packages work as installed ones: the C example builds with their sphray.pc.
execute_process(COMMAND ${CMAKE_COMMAND} -E env PKG_CONFIG_PATH=${WORK_DIR}/root/${lib}/pkgconfig
                        pkg-config --cflags --libs sphray
                OUTPUT_VARIABLE pc_flags OUTPUT_STRIP_TRAILING_WHITESPACE)
separate_arguments(pc_flags UNIX_COMMAND "${pc_flags}")
separate_arguments(extra UNIX_COMMAND "${EXTRA_FLAGS}")
run(${CC} -std=c99 -O2 ${extra} ${EXAMPLE} ${pc_flags} -lm -Wl,-rpath,${WORK_DIR}/root/${lib}
    -o ${WORK_DIR}/render_normals)
run(${WORK_DIR}/render_normals ${WORK_DIR}/image.ppm 32 18)
message("${output}")
if(NOT output MATCHES "sphray ${VERSION} on")
  message(FATAL_ERROR "failed: the program built from the packages did not run")
endif()
if(uid STREQUAL "0")
  run(${dpkg} -r ${packages})
  message("dpkg -r:\n${output}")
  file(GLOB_RECURSE left LIST_DIRECTORIES false ${root}/usr/*)
  if(left)
    message(FATAL_ERROR "failed: files left after dpkg -r: ${left}")
  endif()
  message("removed cleanly: no file left under ${root}/usr")
  if(NOT EXISTS ${WORK_DIR}/ldconfig.calls)
    message(FATAL_ERROR "failed: libsphray2's scripts never ran ldconfig")
  endif()
endif()
message("packages checked: contents, dependencies, and a program built from them")
