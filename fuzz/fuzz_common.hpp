#pragma once
// Shared by the fuzz targets: the exceptions a reader may throw for bad input are its answer,
// not a finding; anything else (a crash, a sanitizer report, another exception) is.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "clearshape/core/error.hpp"

namespace clearshape::fuzz {

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

template <typename F>
void expect_clean_rejection(F&& f) {
  try {
    f();
  } catch (const InvalidArgument&) {
  } catch (const InputError&) {
  } catch (const RuntimeError&) {
  }
}

}  // namespace clearshape::fuzz
