# Debian packages with `cpack -G DEB` (from the build directory): libsphray2 (the shared
# library alone), libsphray-dev (headers, libsphray.a, the libsphray.so link, sphray.pc and the
# CMake package) and sphray (the command), split along the install components.
set(CPACK_PACKAGE_NAME sphray)
set(CPACK_PACKAGE_VENDOR "sphray")
set(CPACK_PACKAGE_CONTACT "sphray maintainers <sphray@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${PROJECT_DESCRIPTION}")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_GENERATOR DEB)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL runtime development)
if(TARGET sphray)
  list(APPEND CPACK_COMPONENTS_ALL tools)
endif()
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
# Each package's library dependencies (libtbb12, libstdc++6, libc6) from dpkg-shlibdeps.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_SECTION libs)
# libsphray2's shlibs file (what dpkg-shlibdeps of a program linked against it will require) and
# its ldconfig trigger, as Debian's policy wants of a shared library package.
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS ON)
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS_POLICY ">=")

set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME libsphray2)
set(CPACK_COMPONENT_RUNTIME_DESCRIPTION
    "sphray's shared library, libsphray.so.2: C and C++ API for exact ray/sphere intersection")
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SECTION libs)

set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_NAME libsphray-dev)
set(CPACK_COMPONENT_DEVELOPMENT_DESCRIPTION
    "sphray's headers (C: sphray/sphray.h, C++: sphray/sphray.hpp), static library, pkg-config and CMake files")
set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_SECTION libdevel)
set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_DEPENDS "libsphray2 (= ${PROJECT_VERSION})")

set(CPACK_DEBIAN_TOOLS_PACKAGE_NAME sphray)
set(CPACK_COMPONENT_TOOLS_DESCRIPTION "The sphray command: renders scenes with the sphray kernel")
set(CPACK_DEBIAN_TOOLS_PACKAGE_SECTION graphics)

include(CPack)
