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

# Beside them, one shared library with every module, libclearshape.so.<major>.<minor>.<patch>
# (SONAME libclearshape.so.<major>.<minor>: the API may change between 0.x minors), linked from
# the modules' own position-independent objects, so nothing is compiled twice: clearshape::shared.
# Its usage requirements are the modules' public ones (headers, C++20, the Debian libraries the
# headers use); the modules' private dependencies are linked into it.
# Not in the sanitizer and fuzzing trees (make test-sanitize, make fuzz), which install nothing.
if(NOT CLEARSHAPE_SANITIZE AND NOT CLEARSHAPE_FUZZ)
  set(_shared_objects "")
  set(_shared_usage "")
  foreach(module IN LISTS CLEARSHAPE_MODULES)
    get_target_property(_type clearshape_${module} TYPE)
    if(_type STREQUAL "STATIC_LIBRARY")
      list(APPEND _shared_objects $<TARGET_OBJECTS:clearshape_${module}>)
    endif()
    get_target_property(_libs clearshape_${module} INTERFACE_LINK_LIBRARIES)
    foreach(lib IN LISTS _libs)
      if(lib AND NOT lib MATCHES "clearshape|\\$<")
        list(APPEND _shared_usage ${lib})
      endif()
    endforeach()
  endforeach()
  list(REMOVE_DUPLICATES _shared_usage)
  add_library(clearshape_shared SHARED ${_shared_objects})
  set_target_properties(clearshape_shared PROPERTIES OUTPUT_NAME clearshape EXPORT_NAME shared
    VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR}
    LINKER_LANGUAGE CXX)
  target_compile_features(clearshape_shared INTERFACE cxx_std_20)
  target_include_directories(clearshape_shared INTERFACE
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
    $<BUILD_INTERFACE:${PROJECT_BINARY_DIR}/generated>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  # The static modules after the objects only bring their private dependencies (nothing of theirs
  # is left undefined); consumers get the public ones.
  target_link_libraries(clearshape_shared PRIVATE clearshape PUBLIC ${_shared_usage})
  add_library(clearshape::shared ALIAS clearshape_shared)
  install(TARGETS clearshape_shared EXPORT clearshapeTargets
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT runtime NAMELINK_COMPONENT dev)
endif()
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

# The Python the module is built for (major.minor): the python3- package's Depends and the
# wheel's Requires-Python.
if(TARGET clearshape_python)
  execute_process(COMMAND ${CLEARSHAPE_PYTHON_EXECUTABLE} -c "import sys; print(sys.version_info[0], sys.version_info[1])"
                  OUTPUT_VARIABLE _py OUTPUT_STRIP_TRAILING_WHITESPACE COMMAND_ERROR_IS_FATAL ANY)
  string(REPLACE " " ";" _py "${_py}")
  list(GET _py 0 CLEARSHAPE_PY_MAJOR)
  list(GET _py 1 CLEARSHAPE_PY_MINOR)
  math(EXPR CLEARSHAPE_PY_NEXT "${CLEARSHAPE_PY_MINOR} + 1")
  # A wheel and an sdist (docs/python.md): `python3 -m build --no-isolation <build>/python-dist`
  # packs the package CMake built into <build>/python/clearshape (setup.py copies it).
  set(_dist ${PROJECT_BINARY_DIR}/python-dist)
  configure_file(${PROJECT_SOURCE_DIR}/packaging/python/pyproject.toml.in ${_dist}/pyproject.toml @ONLY)
  configure_file(${PROJECT_SOURCE_DIR}/packaging/python/setup.py ${_dist}/setup.py COPYONLY)
  configure_file(${PROJECT_SOURCE_DIR}/packaging/python/MANIFEST.in ${_dist}/MANIFEST.in COPYONLY)
  configure_file(${PROJECT_SOURCE_DIR}/LICENSE ${_dist}/LICENSE COPYONLY)
  file(CONFIGURE OUTPUT ${_dist}/README.md @ONLY CONTENT
"# clearshape @PROJECT_VERSION@ (Python)\n\n@PROJECT_DESCRIPTION@: the Python module `clearshape`.\n\
docs/python.md in the source describes it. The extension `clearshape._core` in this package was\n\
built by CMake for Python @CLEARSHAPE_PY_MAJOR@.@CLEARSHAPE_PY_MINOR@ on Linux; neither the sdist nor the wheel compiles it.\n")
endif()

# The Debian packages, one per install component (docs/package.md): the CLI, the shared library
# (named after its SONAME, Debian Policy 8.1), the -dev files, the Python module (when built). Debian revision 1 of the upstream version.
set(CLEARSHAPE_DEB_COMPONENTS cli runtime dev)
set(CLEARSHAPE_DEB_NAMES clearshape libclearshape${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR} libclearshape-dev)
if(TARGET clearshape_python)
  list(APPEND CLEARSHAPE_DEB_COMPONENTS python)
  list(APPEND CLEARSHAPE_DEB_NAMES python3-clearshape)
endif()
set(CLEARSHAPE_DEB_VERSION ${PROJECT_VERSION}-1)

# Debian changelog (Debian Policy 12.7), dated by the last commit when there is one: one entry
# saying the package is built from the upstream tree, whose CHANGELOG.md has the changes.
execute_process(COMMAND git -C ${PROJECT_SOURCE_DIR} log -1 --format=%ct
                OUTPUT_VARIABLE _commit_epoch OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
set(_saved_epoch "$ENV{SOURCE_DATE_EPOCH}")
if(_commit_epoch MATCHES "^[0-9]+$" AND "${_saved_epoch}" STREQUAL "")
  set(ENV{SOURCE_DATE_EPOCH} ${_commit_epoch})
endif()
string(TIMESTAMP CLEARSHAPE_DEB_DATE "%a, %d %b %Y %H:%M:%S +0000" UTC)
set(ENV{SOURCE_DATE_EPOCH} "${_saved_epoch}")
configure_file(${PROJECT_SOURCE_DIR}/packaging/changelog.Debian.in
               ${PROJECT_BINARY_DIR}/packaging/changelog.Debian @ONLY)
execute_process(COMMAND gzip -9nc INPUT_FILE ${PROJECT_BINARY_DIR}/packaging/changelog.Debian
                OUTPUT_FILE ${PROJECT_BINARY_DIR}/packaging/changelog.Debian.gz COMMAND_ERROR_IS_FATAL ANY)
# copyright and changelog.Debian.gz in each package's /usr/share/doc/<package>/.
foreach(_component _package IN ZIP_LISTS CLEARSHAPE_DEB_COMPONENTS CLEARSHAPE_DEB_NAMES)
  install(FILES ${PROJECT_BINARY_DIR}/packaging/copyright ${PROJECT_BINARY_DIR}/packaging/changelog.Debian.gz
          DESTINATION ${CMAKE_INSTALL_DATAROOTDIR}/doc/${_package} COMPONENT ${_component})
endforeach()

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

# Debian packages: `cpack -G DEB` in the build tree makes one .deb per component, the Debian
# split: clearshape (the CLI, its man page), libclearshape<major>.<minor> (the shared library),
# libclearshape-dev (headers, static libraries, the shared library's link, CMake and pkg-config
# files) and python3-clearshape. The -dev and python3- packages depend on the same version of
# clearshape, -dev also on the shared library's package. dpkg-shlibdeps adds the shared libraries the CLI and the Python
# extension load (generic libblas3 | libblas.so.3 since BLA_VENDOR is Generic,
# cmake/ClearshapeDependencies.cmake); the -dev Depends are what clearshapeConfig.cmake finds
# with find_dependency().
set(CPACK_PACKAGE_NAME clearshape)
set(CPACK_PACKAGE_VENDOR "The clearshape developers")
set(CPACK_PACKAGE_CONTACT "${CLEARSHAPE_DEB_MAINTAINER}")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL ${CLEARSHAPE_DEB_COMPONENTS})
set(CPACK_DEBIAN_ENABLE_COMPONENT_DEPENDS ON)
set(CPACK_DEBIAN_PACKAGE_RELEASE 1)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE amd64)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
foreach(_component _package IN ZIP_LISTS CLEARSHAPE_DEB_COMPONENTS CLEARSHAPE_DEB_NAMES)
  string(TOUPPER ${_component} _c)
  set(CPACK_DEBIAN_${_c}_PACKAGE_NAME ${_package})
endforeach()
# Each package's Description: its own summary line, then the extended text (lines under 80).
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "")
string(CONCAT _about "clearshape designs input shapers (ZV, ZVD, EI and others) for machines\n"
       "with a resonance and play in the drive, identifies the plant from measured\n"
       "runs and simulates the result.\n")
string(CONCAT CPACK_DEBIAN_CLI_DESCRIPTION "input shaping for machines with play - command-line tool\n"
       "${_about}This package has the command-line tool clearshape and its manual page.")
set(CPACK_DEBIAN_CLI_PACKAGE_SUGGESTS "python3-clearshape")  # `clearshape sweep` runs its module
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SECTION libs)
string(CONCAT CPACK_DEBIAN_RUNTIME_DESCRIPTION "input shaping for machines with play - shared library\n"
       "${_about}This package has the shared library libclearshape.so.${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR} with every module.")
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS ON)  # shlibs: the exact version (0.x)
# The ldconfig trigger Debian wants (lintian: lacks-ldconfig-trigger); CPack 3.25 also writes
# postinst/postrm that call ldconfig (docs/package.md, what lintian says).
set(CPACK_DEBIAN_RUNTIME_PACKAGE_CONTROL_EXTRA ${PROJECT_SOURCE_DIR}/packaging/triggers)
set(CPACK_COMPONENT_DEV_DEPENDS cli runtime)
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)
string(CONCAT CPACK_DEBIAN_DEV_DESCRIPTION "input shaping for machines with play - development files\n"
       "${_about}This package has the C++20 headers, the static libraries, the CMake\n"
       "package (find_package(clearshape)) and the pkg-config file clearshape.pc.")
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS
    "libeigen3-dev, libfmt-dev, nlohmann-json3-dev, libnlopt-cxx-dev, libsundials-dev, libceres-dev, libtomlplusplus-dev, libserialport-dev, liborocos-kdl-dev, liburdfdom-dev, pkg-config")
# What the Python package imports only when used (bindings/python/clearshape): every sweep
# writes results.h5 (h5py) and draws its map when `plot` is set (matplotlib); --scheduler
# needs distributed. The extension is built for Debian 12's Python 3.11 only.
set(CPACK_COMPONENT_PYTHON_DEPENDS cli)
set(CPACK_DEBIAN_PYTHON_PACKAGE_SECTION python)
string(CONCAT CPACK_DEBIAN_PYTHON_DESCRIPTION "input shaping for machines with play - Python 3 module\n"
       "${_about}This package has the Python 3 module clearshape (import clearshape)\n"
       "and the parameter sweeps that clearshape sweep runs.")
if(TARGET clearshape_python)
  set(CPACK_DEBIAN_PYTHON_PACKAGE_DEPENDS
      "python3 (>= ${CLEARSHAPE_PY_MAJOR}.${CLEARSHAPE_PY_MINOR}~), python3 (<< ${CLEARSHAPE_PY_MAJOR}.${CLEARSHAPE_PY_NEXT}), python3-numpy")
endif()
set(CPACK_DEBIAN_PYTHON_PACKAGE_RECOMMENDS "python3-h5py, python3-matplotlib")
set(CPACK_DEBIAN_PYTHON_PACKAGE_SUGGESTS "python3-distributed")
include(CPack)
