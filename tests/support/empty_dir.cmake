# cmake -DDIR=<folder> -P empty_dir.cmake: <folder> removed with everything in it, then created
# empty (the tests' TMPDIR before a ctest run; tests/CMakeLists.txt).
if(NOT DIR)
  message(FATAL_ERROR "empty_dir.cmake: give -DDIR=<folder>")
endif()
file(REMOVE_RECURSE "${DIR}")
file(MAKE_DIRECTORY "${DIR}")
