# One static library per module (docs/design.md §3). A module links only modules on lower floors,
# so the floors are enforced by the build: clearshape_add_module(shaping DEPS core LIBS NLopt::nlopt)
add_library(clearshape_warnings INTERFACE)
target_compile_options(clearshape_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow
                       -Wnon-virtual-dtor -Wold-style-cast -Wcast-align -Wunused -Woverloaded-virtual
                       -Wnull-dereference -Wdouble-promotion -Wformat=2 -Wimplicit-fallthrough)
if(CLEARSHAPE_WERROR)
  target_compile_options(clearshape_warnings INTERFACE -Werror)
endif()

include(GNUInstallDirs)  # CMAKE_INSTALL_INCLUDEDIR for the installed include path
set(CLEARSHAPE_MODULES "" CACHE INTERNAL "modules of the clearshape library")

function(clearshape_add_module name)
  cmake_parse_arguments(ARG "" "" "DEPS;LIBS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/${name}/*.cpp)
  if(sources)
    set(scope PUBLIC)
    add_library(clearshape_${name} STATIC ${sources})
    set_target_properties(clearshape_${name} PROPERTIES POSITION_INDEPENDENT_CODE ON)
    # Warnings are for this build only: not part of the installed targets' interface.
    target_link_libraries(clearshape_${name} PRIVATE $<BUILD_INTERFACE:clearshape_warnings>)
  else()  # a module with headers only (or not written yet)
    set(scope INTERFACE)
    add_library(clearshape_${name} INTERFACE)
  endif()
  add_library(clearshape::${name} ALIAS clearshape_${name})
  # The public headers are C++20 (std::span, defaulted operator==): a usage requirement, so a
  # consumer of the installed package compiles as C++20 whatever its own default (GCC 12: C++17).
  target_compile_features(clearshape_${name} ${scope} cxx_std_20)
  # Installed as clearshape::<name> (cmake/ClearshapeInstall.cmake), like the alias above.
  set_target_properties(clearshape_${name} PROPERTIES EXPORT_NAME ${name})
  target_include_directories(clearshape_${name} ${scope}
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
    $<BUILD_INTERFACE:${PROJECT_BINARY_DIR}/generated>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  foreach(dep IN LISTS ARG_DEPS)
    target_link_libraries(clearshape_${name} ${scope} clearshape_${dep})
  endforeach()
  if(ARG_LIBS)
    target_link_libraries(clearshape_${name} ${scope} ${ARG_LIBS})
  endif()
  set(CLEARSHAPE_MODULES ${CLEARSHAPE_MODULES} ${name} CACHE INTERNAL "")
endfunction()
