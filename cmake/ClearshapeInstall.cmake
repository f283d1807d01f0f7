# Installation and packaging (docs/package.md): `cmake --install` puts the headers, the module
# libraries, the exported CMake package (clearshape::clearshape and clearshape::<module>), a
# pkg-config file and the CLI in the GNU directories; `cpack -G DEB` wraps the same into a .deb.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

# `make install` and cpack install what is built and do not build every target (tests,
# benchmarks) first: build the library, the CLI and the Python module, then install.
set(CMAKE_SKIP_INSTALL_ALL_DEPENDENCY ON)

set(CLEARSHAPE_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/clearshape)

# Libraries: every module (static, position independent) and the umbrella INTERFACE target.
set_target_properties(clearshape PROPERTIES EXPORT_NAME clearshape)
set(_clearshape_module_targets "")
foreach(module IN LISTS CLEARSHAPE_MODULES)
  list(APPEND _clearshape_module_targets clearshape_${module})
endforeach()
install(TARGETS ${_clearshape_module_targets} clearshape
        EXPORT clearshapeTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/clearshape ${PROJECT_BINARY_DIR}/generated/clearshape
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT dev)
install(EXPORT clearshapeTargets NAMESPACE clearshape:: DESTINATION ${CLEARSHAPE_CMAKE_DIR}
        COMPONENT dev)

configure_package_config_file(${PROJECT_SOURCE_DIR}/packaging/clearshapeConfig.cmake.in
  ${PROJECT_BINARY_DIR}/packaging/clearshapeConfig.cmake INSTALL_DESTINATION ${CLEARSHAPE_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/packaging/clearshapeConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/packaging/clearshapeConfig.cmake
              ${PROJECT_BINARY_DIR}/packaging/clearshapeConfigVersion.cmake
        DESTINATION ${CLEARSHAPE_CMAKE_DIR} COMPONENT dev)

# pkg-config: the modules from the highest floor down (static libraries link in that order).
set(CLEARSHAPE_PC_LIBS "")
set(_clearshape_reversed ${CLEARSHAPE_MODULES})
list(REVERSE _clearshape_reversed)
foreach(module IN LISTS _clearshape_reversed)
  if(TARGET clearshape_${module})
    get_target_property(_type clearshape_${module} TYPE)
    if(_type STREQUAL "STATIC_LIBRARY")
      string(APPEND CLEARSHAPE_PC_LIBS " -lclearshape_${module}")
    endif()
  endif()
endforeach()
# The prefix is found from the .pc file's own place, so a relocated install (--prefix) works.
string(REGEX REPLACE "[^/]+" ".." CLEARSHAPE_PC_UP "${CMAKE_INSTALL_LIBDIR}/pkgconfig")
configure_file(${PROJECT_SOURCE_DIR}/packaging/clearshape.pc.in
               ${PROJECT_BINARY_DIR}/packaging/clearshape.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/packaging/clearshape.pc
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT dev)

# The CLI.
install(TARGETS clearshape_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT cli)

# The .deb's maintainer (also the copyright file's Upstream-Contact).
set(CLEARSHAPE_DEB_MAINTAINER "The clearshape developers <maintainers@clearshape.invalid>" CACHE STRING
    "Maintainer field of the .deb: 'Name <address>' of whoever builds and distributes the package")
if(CLEARSHAPE_DEB_MAINTAINER MATCHES "\\.invalid>$")
  message(STATUS "clearshape .deb maintainer: ${CLEARSHAPE_DEB_MAINTAINER} (set -DCLEARSHAPE_DEB_MAINTAINER='Name <address>')")
endif()

# Debian copyright file in the machine-readable format (DEB-5, copyright-format 1.0), made from
# LICENSE: its "Copyright (c) …" line and the MIT text, which Debian names Expat.
file(STRINGS ${PROJECT_SOURCE_DIR}/LICENSE _license_lines)
list(GET _license_lines 0 _license_title)
if(NOT _license_title STREQUAL "MIT License")
  message(FATAL_ERROR "LICENSE: line 1 is '${_license_title}'; cmake/ClearshapeInstall.cmake maps only 'MIT License' (Debian: Expat)")
endif()
file(READ ${PROJECT_SOURCE_DIR}/LICENSE _license_text)
string(REGEX MATCH "Copyright \\(c\\) ([^\n]+)" _ "${_license_text}")
set(CLEARSHAPE_COPYRIGHT_HOLDER "${CMAKE_MATCH_1}")
string(REGEX REPLACE "^.*Copyright \\(c\\) [^\n]+\n\n" "" _license_body "${_license_text}")
string(REGEX REPLACE "\n+$" "" _license_body "${_license_body}")
string(REPLACE "\n\n" "\n.\n" _license_body "${_license_body}")
string(REPLACE "\n" "\n " CLEARSHAPE_LICENSE_BODY " ${_license_body}")
configure_file(${PROJECT_SOURCE_DIR}/packaging/copyright.in ${PROJECT_BINARY_DIR}/packaging/copyright @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/packaging/copyright
        DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/doc/clearshape COMPONENT cli)

# The man page clearshape.1, generated from the CLI's own --help and --version (help2man, a
# Debian package: scripts/install-deps.sh). The CLI is run as `clearshape` from PATH, so the page
# names no build directory.
find_program(CLEARSHAPE_HELP2MAN help2man)
if(CLEARSHAPE_HELP2MAN)
  set(_man ${PROJECT_BINARY_DIR}/man/clearshape.1)
  add_custom_command(OUTPUT ${_man}.gz
    COMMAND ${CMAKE_COMMAND} -E make_directory ${PROJECT_BINARY_DIR}/man
    COMMAND ${CMAKE_COMMAND} -E env "PATH=$<TARGET_FILE_DIR:clearshape_cli>:$ENV{PATH}"
            ${CLEARSHAPE_HELP2MAN} --no-info --locale=C.UTF-8 --section=1
            "--name=${PROJECT_DESCRIPTION}" --output=${_man} clearshape
    COMMAND gzip -9nf ${_man}
    DEPENDS clearshape_cli VERBATIM)
  add_custom_target(clearshape_man ALL DEPENDS ${_man}.gz)
  install(FILES ${_man}.gz DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 COMPONENT cli)
else()
  message(WARNING "help2man not found (scripts/install-deps.sh installs it): no man page clearshape.1 is installed")
endif()

# Debian package: `cpack -G DEB` in the build tree (one package with every component). The
# -dev dependencies are what clearshapeConfig.cmake finds with find_dependency(); the shared
# libraries the CLI and the Python module load are added by dpkg-shlibdeps (generic libblas3 |
# libblas.so.3 since BLA_VENDOR is Generic, cmake/ClearshapeDependencies.cmake).
set(CPACK_PACKAGE_NAME clearshape)
set(CPACK_PACKAGE_VENDOR "The clearshape developers")
set(CPACK_PACKAGE_CONTACT "${CLEARSHAPE_DEB_MAINTAINER}")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${PROJECT_DESCRIPTION}")
set(CPACK_PACKAGE_FILE_NAME "clearshape_${PROJECT_VERSION}_amd64")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEB_COMPONENT_INSTALL OFF)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE amd64)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS
    "libeigen3-dev, libfmt-dev, nlohmann-json3-dev, libnlopt-cxx-dev, libsundials-dev, libceres-dev, libtomlplusplus-dev, libserialport-dev, liborocos-kdl-dev, liburdfdom-dev, pkg-config, python3-numpy")
# What the Python package imports only when used (bindings/python/clearshape): every sweep
# writes results.h5 (h5py) and draws its map when `plot` is set (matplotlib); --scheduler
# needs distributed.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "python3-h5py, python3-matplotlib")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "python3-distributed")
include(CPack)
