// Fuzz target: the study protocol reader (TOML → validated Protocol).
#include "clearshape/study/protocol.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace clearshape;
  fuzz::expect_clean_rejection([&] { (void)study::parse_protocol(fuzz::as_text(data, size), "fuzz.toml"); });
  return 0;
}
