// Fuzz target: the rig configuration reader of `simulate --config` / `study --rig-config`.
#include "fuzz_common.hpp"
#include "clearshape/rig/config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace clearshape;
  fuzz::expect_clean_rejection([&] { (void)rig::parse_rig_config(fuzz::as_text(data, size), "fuzz.toml"); });
  return 0;
}
