// The source of clearshape_test_pch (tests/CMakeLists.txt): the target exists to build the one
// precompiled header every test program reuses; this file compiles it once.
#include <gtest/gtest.h>
