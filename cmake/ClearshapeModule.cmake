# One static library per module (docs/design.md §3). A module links only modules on lower floors,
# so the floors are enforced by the build: clearshape_add_module(shaping DEPS core LIBS NLopt::nlopt)
add_library(clearshape_warnings INTERFACE)
target_compile_options(clearshape_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow
                       -Wnon-virtual-dtor -Wold-style-cast -Wcast-align -Wunused -Woverloaded-virtual
                       -Wnull-dereference -Wdouble-promotion -Wformat=2 -Wimplicit-fallthrough)
# CLEARSHAPE_WERROR: warnings are errors, but for those GCC 12 computes in the optimiser, after
# inlining (null-dereference, restrict, stringop-*, array-bounds, maybe-uninitialized, …). These
# fire inside libstdc++ on correct code depending on what else is inlined into the translation
# unit: study/model.cpp began to warn -Wnull-dereference at unchanged vector::resize() calls when
# an unrelated function was added beside them, and `"'" + s + "'"` warns -Wrestrict in C++20
# (the same false positives: nlohmann/json#3525, SFML/SFML#2106, google/benchmark#1398). They stay
# warnings, fixed at the cause where they appear; they cannot gate CI.
if(CLEARSHAPE_WERROR)
  target_compile_options(clearshape_warnings INTERFACE -Werror
    -Wno-error=null-dereference -Wno-error=restrict -Wno-error=stringop-overflow
    -Wno-error=stringop-overread -Wno-error=array-bounds -Wno-error=maybe-uninitialized)
endif()

# clearshape_precompile(target [header...]): with CLEARSHAPE_PCH, the standard library, fmt and
# Eigen (and the headers given) are parsed once per target, not once per source: a CLI or study
# source spends about half its compile time parsing them, and the precompiled header saves
# 20–35 % of it. Only where it pays: a target with many sources that include these headers. Not
# with CLEARSHAPE_UNITY: a batch parses the headers once anyway, and the precompiled header saved
# 0.1 s per CLI or study batch for its own 7 s and 5 s (measured one translation unit at a time).
function(clearshape_precompile target)
  if(CLEARSHAPE_PCH AND NOT CLEARSHAPE_UNITY)
    target_precompile_headers(${target} PRIVATE <algorithm> <cmath> <memory> <string> <vector>
                              <fmt/format.h> <Eigen/Dense> ${ARGN})
  endif()
endfunction()

# clearshape_cold(target [SOURCES file...]): with CLEARSHAPE_COLD_O1 in an optimised GCC build
# (Release, RelWithDebInfo), the target (or only the given sources of it) compiles at -O1. For modules whose own code takes a negligible share
# of the run time, measured (docs/design.md, "Build time"): the CLI, io and export parse, format and
# dispatch; study, ident, lti, advise and rig set up, identify, fit and tabulate around the
# simulations, which run in plant (over every `make run` study, perf puts 48 % of the CPU in plant,
# 19 % in CVODE and 20 % in libm, 0.7 % in study's own functions, 0.2 % in ident's, 0.01 % in
# rig's). There -O3's inlining and unrolling cost compile time and buy nothing at run time: the
# CLI's four unity batches take 64 s of CPU at -O3 and about 46 s at -O1; study, ident, lti, advise
# and rig 203 s and 137 s; the studies take as long and bench_study, bench_clearance_aware and
# bench_simulate agree within 3 %. core/linalg.cpp (Eigen's decompositions, instantiated once)
# too: 45 → 33 s. What it costs a user: bench_ident's fits take 20–29 % longer (16.4 → 20.3 ms for
# one record), its free-decay modes 11.1 → 12.2 ms. IEEE arithmetic rounds the same at every level
# (no -ffast-math; x86-64's SSE2 has no fused multiply-add to contract into), so outputs do not
# change: the studies' results.json are the same bytes.
function(clearshape_cold target)
  cmake_parse_arguments(ARG "" "" "SOURCES" ${ARGN})
  if(CLEARSHAPE_COLD_O1 AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_BUILD_TYPE MATCHES "^(Release|RelWithDebInfo)$")
    if(ARG_SOURCES)  # these sources only (a source with its own options leaves the unity batches)
      set_source_files_properties(${ARG_SOURCES} TARGET_DIRECTORY ${target} PROPERTIES COMPILE_OPTIONS -O1)
    else()
      target_compile_options(${target} PRIVATE -O1)  # after the build type's -O3: GCC takes the last -O
    endif()
  endif()
endfunction()

# clearshape_unity(target [SKIP file...]): with CLEARSHAPE_UNITY, the target's sources compile
# in batches of 8 per translation unit (CMake's unity build), so the headers every source parses
# and the inline code every source emits (Eigen, fmt, json, CLI11's validators, GoogleTest) are
# compiled once per batch instead of once per file: test_signal's 8 sources 14.1 → 5.7 s of CPU,
# clearshape_rig's 18 sources 20.6 → 7.2 s (docs/design.md, "Build time"). Sources are batched in
# file-name order, so a file's internal names (anonymous namespace, static) must not clash with
# another's of the same batch. SKIP: files compiled on their own (the heavy ones, 10 s and more,
# which gain little and would lengthen the build's parallel tail).
function(clearshape_unity target)
  cmake_parse_arguments(ARG "" "" "SKIP" ${ARGN})
  get_target_property(type ${target} TYPE)
  if(NOT CLEARSHAPE_UNITY OR type STREQUAL "INTERFACE_LIBRARY")
    return()
  endif()
  set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")  # a fixture in an anonymous namespace, no longer in the main file
    target_compile_options(${target} PRIVATE -Wno-subobject-linkage)
  endif()
  if(ARG_SKIP)
    set_source_files_properties(${ARG_SKIP} TARGET_DIRECTORY ${target} PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
  endif()
endfunction()

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
