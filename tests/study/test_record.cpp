// Running a command on a rig and the run files: the loop contract (a command written after
// read k holds from t_k), the CSV + sidecar round trip (bit-exact) and reuse by protocol hash.
#include <gtest/gtest.h>

#include <filesystem>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>
#include <fstream>

#include "clearshape/core/error.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/rig/loopback_rig.hpp"
#include "clearshape/study/record.hpp"
#include "support/paths.hpp"

namespace cs = clearshape;
namespace st = clearshape::study;

namespace {

st::RunRequest step_request() {
  st::RunRequest req;
  req.id = "unshaped/step/r01";
  req.stage = "unshaped";
  req.input = "step";
  req.record_s = 0.1;
  req.command.sample_time_s = 1e-3;
  req.command.values.assign(101, 0.0);
  for (std::size_t k = 20; k < 101; ++k) req.command.values[k] = 1.0 / 3.0 + static_cast<double>(k) * 0.1;
  return req;
}


}  // namespace

TEST(Record, ExecutesTheCommandOnTheRig) {
  cs::rig::LoopbackConfig config;  // position mode, 1 kHz: reports the commanded angle
  cs::rig::LoopbackRig rig(config);
  const st::RunRequest req = step_request();
  const st::Record r = st::execute_run(rig, req);
  ASSERT_EQ(r.size(), 101u);
  EXPECT_EQ(rig.state(), cs::rig::LifecycleState::inactive);
  EXPECT_DOUBLE_EQ(r.time_s[100], 0.1);
  for (std::size_t k = 0; k < r.size(); ++k) EXPECT_EQ(r.command[k], req.command.values[k]);
  // The loopback reports at t_k the command written after read k−1.
  for (std::size_t k = 1; k < r.size(); ++k) {
    EXPECT_NEAR(r.command_applied[k], req.command.values[k - 1], 1e-12) << k;
    EXPECT_NEAR(r.motor_angle_deg[k], req.command.values[k - 1], 360.0 / 12000.0) << k;
  }
}

TEST(Record, RejectsAMismatchedSampleTime) {
  cs::rig::LoopbackConfig config;
  config.sample_rate_hz = 500.0;
  cs::rig::LoopbackRig rig(config);
  EXPECT_THROW(st::execute_run(rig, step_request()), cs::InvalidArgument);
}

TEST(Record, RoundTripIsBitExactAndKeyedByTheProtocolHash) {
  cs::rig::LoopbackRig rig(cs::rig::LoopbackConfig{});
  const st::RunRequest req = step_request();
  const st::Record r = st::execute_run(rig, req);
  const auto dir = clearshape::testing::emptied_temp_path("clearshape_test_record");
  st::write_record(dir, r, req, "hash-a", "loopback", {{"reads", 101}});
  EXPECT_TRUE(std::filesystem::exists(dir / "unshaped__step__r01.csv"));
  EXPECT_TRUE(std::filesystem::exists(dir / "unshaped__step__r01.json"));
  const auto back = st::read_record(dir, req, cs::rig::CommandMode::position, "hash-a");
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->command, r.command);
  EXPECT_EQ(back->command_applied, r.command_applied);
  EXPECT_EQ(back->motor_angle_deg, r.motor_angle_deg);
  EXPECT_EQ(back->link_rate_deg_s, r.link_rate_deg_s);
  EXPECT_EQ(back->time_s, r.time_s);
  EXPECT_FALSE(st::read_record(dir, req, cs::rig::CommandMode::position, "hash-b").has_value());
  // A damaged CSV means the run is run again, not an error.
  std::ofstream(dir / "unshaped__step__r01.csv") << "time_s,garbage\n1,2\n";
  EXPECT_FALSE(st::read_record(dir, req, cs::rig::CommandMode::position, "hash-a").has_value());
  std::filesystem::remove_all(dir);
}

// A resumed study reads its own runs back; when the protocol changed (another hash), the rerun
// must be able to replace them. Reading them must not make them "inputs" the safe-file layer
// then refuses to overwrite (a rerun into the same folder failed with "output … is the input").
TEST(Record, AStaleRunReadBackCanBeReplacedByTheRerun) {
  cs::rig::LoopbackRig rig(cs::rig::LoopbackConfig{});
  const st::RunRequest req = step_request();
  const st::Record r = st::execute_run(rig, req);
  const auto dir = clearshape::testing::emptied_temp_path("clearshape_test_record_stale");
  st::write_record(dir, r, req, "hash-a", "loopback", {{"reads", 101}});
  ASSERT_FALSE(st::read_record(dir, req, cs::rig::CommandMode::position, "hash-b").has_value());
  EXPECT_NO_THROW(st::write_record(dir, r, req, "hash-b", "loopback", {{"reads", 101}}));
  EXPECT_TRUE(st::read_record(dir, req, cs::rig::CommandMode::position, "hash-b").has_value());
  // A user's file read as an input stays protected.
  const auto user_file = dir / "user.csv";
  std::ofstream(user_file) << "time_s,x\n0,1\n";
  (void)cs::io::read_text_file(user_file);
  EXPECT_THROW(cs::io::write_text_atomic(user_file, "overwritten"), cs::InvalidArgument);
  cs::io::clear_inputs();
  std::filesystem::remove_all(dir);
}

namespace {

// A rig whose board ran ahead of the loop: after read k it reports waiting[k] samples not yet
// read, and it keeps the commands written.
class BackloggedRig final : public cs::rig::Rig {
 public:
  explicit BackloggedRig(std::vector<std::size_t> waiting) : waiting_(std::move(waiting)) {}
  double sample_time_s() const noexcept override { return 1e-3; }
  cs::rig::CommandMode mode() const noexcept override { return cs::rig::CommandMode::position; }
  std::string_view name() const noexcept override { return "backlogged"; }
  std::size_t samples_waiting() const noexcept override {
    return reads_ > 0 && reads_ <= waiting_.size() ? waiting_[reads_ - 1] : 0;
  }
  std::vector<std::pair<std::size_t, double>> written;  // (reads so far, value)

 protected:
  void on_configure() override {}
  void on_activate() override { reads_ = 0; }
  void on_deactivate() noexcept override {}
  void on_cleanup() noexcept override {}
  cs::Status on_read(cs::rig::Measurement& m) noexcept override {
    m = {};
    m.sequence = reads_++;
    return cs::Status::ok;
  }
  cs::Status on_write(const cs::rig::Command& c) noexcept override {
    written.emplace_back(reads_, c.value);
    return cs::Status::ok;
  }

 private:
  std::vector<std::size_t> waiting_;
  std::size_t reads_ = 0;
};

}  // namespace

// Issue 21 item 6: a study loop that fell behind its board writes only the newest commands of
// its catch-up (8 or more samples waiting: skip), like the real-time runner.
TEST(Record, ALoopBehindItsBoardWritesOnlyTheNewestCommands) {
  std::vector<std::size_t> waiting(101, 0);
  for (std::size_t k = 30; k < 50; ++k) waiting[k] = 50 - k;  // a 20-sample backlog drained one per read
  BackloggedRig rig(waiting);
  const st::RunRequest req = step_request();
  (void)st::execute_run(rig, req);
  // Reads 31 … 43 left 8 or more waiting (20 … 8): their 13 commands are skipped, the rest written.
  ASSERT_EQ(rig.written.size(), 101u - 13u);
  for (const auto& [reads, value] : rig.written) {
    EXPECT_TRUE(reads <= 30 || reads >= 44) << reads;
    EXPECT_NEAR(value, req.command.values[reads - 1] * std::numbers::pi / 180.0, 1e-12);  // written in rad
  }
}
