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

# Debian package: `cpack -G DEB` in the build tree (one package with every component). The
# -dev dependencies are what clearshapeConfig.cmake finds with find_dependency(); the shared
# libraries the CLI and the Python module load are added by dpkg-shlibdeps.
set(CPACK_PACKAGE_NAME clearshape)
set(CPACK_PACKAGE_VENDOR "clearshape")
set(CPACK_PACKAGE_CONTACT "clearshape maintainers <clearshape@localhost>")
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
include(CPack)
