// `clearshape signal --type chirp`: the swept sine on the command line equals scipy.signal.chirp
// (tests/golden/signal_chirp.csv, gen_chirp.py), and --sweep rejects other names (exit 2).
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "clearshape/io/table.hpp"
#include "support/cli.hpp"
#include "support/paths.hpp"

using clearshape::testing::run_cli;

TEST(SignalChirpCli, LogarithmicSweepMatchesScipy) {
  const auto out = std::filesystem::temp_directory_path() / ("clearshape_chirp_" + std::to_string(::getpid()) + ".csv");
  const auto r = run_cli("signal --type chirp --amplitude 1.5 --offset 0.25 --phase-deg 30 --start-s 0.5 --f0-hz 0.5 "
                         "--f1-hz 20 --sweep-s 4 --sweep logarithmic --duration 5 --rate 1000 --output " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto ours = clearshape::io::read_table(out);
  const auto golden = clearshape::io::read_table(clearshape::testing::golden_path("signal_chirp.csv"));
  const auto& a = ours.column("command");
  const auto& b = golden.column("logarithmic");
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) ASSERT_NEAR(a[i], b[i], 1e-9) << "sample " << i;
  EXPECT_EQ(run_cli("signal --type chirp --sweep cubic --output " + out.string()).exit_code, 2);
  EXPECT_EQ(run_cli("signal --type step --sweep linear --output " + out.string()).exit_code, 2);
  std::filesystem::remove(out);
}
