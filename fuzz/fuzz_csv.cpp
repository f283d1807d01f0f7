// Fuzz target: the CSV reader (io::parse_table) and the checks the commands run on its result.
#include "clearshape/io/table.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace clearshape;
  fuzz::expect_clean_rejection([&] {
    const io::Table table = io::parse_table(fuzz::as_text(data, size), "fuzz.csv");
    const std::string time = table.names.front();
    (void)io::uniform_sample_time(table, time);
    if (table.names.size() > 1) (void)io::series_from_table(table, time, table.names[1]);
  });
  return 0;
}
