#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/rig/loopback_rig.hpp"
#include "support/alloc_counter.hpp"

namespace cs = clearshape;
namespace rig = clearshape::rig;
using cs::Status;
using rig::LifecycleState;

namespace {
// A rig whose device fails on the third read: exercises the error state.
class FlakyRig final : public rig::Rig {
 public:
  double sample_time_s() const noexcept override { return 1e-3; }
  rig::CommandMode mode() const noexcept override { return rig::CommandMode::position; }
  std::string_view name() const noexcept override { return "flaky"; }
  bool bad_configuration = false;
  int deactivations = 0;

 protected:
  void on_configure() override {
    if (bad_configuration) throw cs::InvalidArgument("port = '' is empty; allowed: a device path");
  }
  void on_activate() override { reads_ = 0; }
  void on_deactivate() noexcept override { ++deactivations; }
  void on_cleanup() noexcept override {}
  Status on_read(rig::Measurement& m) noexcept override {
    m.sequence = static_cast<std::uint64_t>(reads_);
    return ++reads_ >= 3 ? Status::device_error : Status::ok;
  }
  Status on_write(const rig::Command&) noexcept override { return Status::ok; }

 private:
  int reads_ = 0;
};
}  // namespace

TEST(RigLifecycle, TransitionsAndWrongStateCalls) {
  rig::LoopbackRig r({});
  rig::Measurement m;
  EXPECT_EQ(r.state(), LifecycleState::unconfigured);
  EXPECT_EQ(r.read(m), Status::not_ready);
  EXPECT_EQ(r.activate(), Status::not_ready);
  EXPECT_EQ(r.configure(), Status::ok);
  EXPECT_EQ(r.state(), LifecycleState::inactive);
  EXPECT_EQ(r.configure(), Status::not_ready);
  EXPECT_EQ(r.write(rig::Command::position_rad(0.1)), Status::not_ready);
  EXPECT_EQ(r.activate(), Status::ok);
  EXPECT_EQ(r.state(), LifecycleState::active);
  EXPECT_EQ(r.read(m), Status::ok);
  EXPECT_EQ(r.cleanup(), Status::not_ready);
  EXPECT_EQ(r.deactivate(), Status::ok);
  EXPECT_EQ(r.state(), LifecycleState::inactive);
  EXPECT_EQ(r.cleanup(), Status::ok);
  EXPECT_EQ(r.state(), LifecycleState::unconfigured);
}

TEST(RigLifecycle, ConfigurationErrorThrowsAndKeepsState) {
  rig::LoopbackConfig config;
  config.mode = rig::CommandMode::speed;  // speed_rad_s_per_volt missing
  rig::LoopbackRig r(config);
  try {
    r.configure();
    FAIL() << "expected InvalidArgument";
  } catch (const cs::InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("speed_rad_s_per_volt"), std::string::npos) << e.what();
  }
  EXPECT_EQ(r.state(), LifecycleState::unconfigured);

  FlakyRig flaky;
  flaky.bad_configuration = true;
  EXPECT_THROW(flaky.configure(), cs::InvalidArgument);
  EXPECT_EQ(flaky.state(), LifecycleState::unconfigured);
}

TEST(RigLifecycle, DeviceErrorMovesToErrorStateAndDeactivateRecovers) {
  FlakyRig r;
  ASSERT_EQ(r.configure(), Status::ok);
  ASSERT_EQ(r.activate(), Status::ok);
  rig::Measurement m;
  EXPECT_EQ(r.read(m), Status::ok);
  EXPECT_EQ(r.read(m), Status::ok);
  EXPECT_EQ(r.read(m), Status::device_error);
  EXPECT_EQ(r.state(), LifecycleState::error);
  EXPECT_EQ(r.read(m), Status::not_ready);
  EXPECT_EQ(r.counters().reads, 4u);
  EXPECT_EQ(r.counters().failed_reads, 2u);
  EXPECT_EQ(r.activate(), Status::not_ready);
  EXPECT_EQ(r.deactivate(), Status::ok);
  EXPECT_EQ(r.deactivations, 1);
  EXPECT_EQ(r.activate(), Status::ok);
  EXPECT_EQ(r.read(m), Status::ok);
  EXPECT_EQ(r.counters().reads, 1u);  // counters restart at activation
}

TEST(LoopbackRig, MirrorsPositionCommandsThroughTheEncoder) {
  rig::LoopbackRig r({});
  r.configure();
  r.activate();
  rig::Measurement m;
  ASSERT_EQ(r.read(m), Status::ok);
  EXPECT_EQ(m.time_s, 0.0);
  EXPECT_EQ(m.sequence, 0u);
  ASSERT_EQ(r.write(rig::Command::position_deg(9.0)), Status::ok);
  ASSERT_EQ(r.read(m), Status::ok);
  EXPECT_NEAR(m.time_s, 1e-3, 1e-15);
  // 12000 counts/rev: 9° = 300 counts exactly. The rate 9°/1 ms = 9000 °/s gives
  // 9000 · 14.375 = 129375 LSB: beyond the int16 word, so the gyroscope saturates.
  EXPECT_EQ(m.encoder_counts, 300);
  EXPECT_NEAR(m.motor_angle_deg(), 9.0, 1e-12);
  EXPECT_EQ(m.gyro_raw, 32767);
  EXPECT_TRUE(m.has(rig::MeasurementFlag::gyro_saturated));
  ASSERT_EQ(r.read(m), Status::ok);
  EXPECT_EQ(m.gyro_raw, 0);
  EXPECT_FALSE(m.has(rig::MeasurementFlag::gyro_saturated));
  EXPECT_EQ(r.write(rig::Command::speed_v(1.0)), Status::out_of_range);  // wrong mode
  EXPECT_EQ(r.write({rig::CommandMode::position, std::numeric_limits<double>::quiet_NaN()}),
            Status::not_finite);
  ASSERT_EQ(r.read(m), Status::ok);
  EXPECT_TRUE(m.has(rig::MeasurementFlag::command_rejected));
  EXPECT_EQ(m.encoder_counts, 300);  // the rejected commands were not applied
}

TEST(LoopbackRig, SpeedModeIntegratesAndGyroScales) {
  rig::LoopbackConfig config;
  config.mode = rig::CommandMode::speed;
  config.speed_rad_s_per_volt = cs::deg_to_rad(100.0);  // 100 °/s per V
  rig::LoopbackRig r(config);
  r.configure();
  r.activate();
  rig::Measurement m;
  r.read(m);
  r.write(rig::Command::speed_v(2.0));  // 200 °/s
  for (int i = 0; i < 100; ++i) r.read(m);
  EXPECT_NEAR(m.time_s, 0.1, 1e-12);
  EXPECT_EQ(m.gyro_raw, 2875);  // 200 · 14.375
  EXPECT_NEAR(m.gyro_rate_deg_s(), 200.0, 1e-12);
  EXPECT_NEAR(m.motor_angle_deg(), 20.0, 0.03 + 1e-9);  // one count = 0.03°
}

TEST(LoopbackRig, ReadAndWriteNeverAllocate) {
  rig::LoopbackRig r({});
  r.configure();
  r.activate();
  rig::Measurement m;
  cs::testing::AllocationCounter counter;
  for (int i = 0; i < 1000; ++i) {
    r.read(m);
    r.write(rig::Command::position_rad(1e-3 * i));
  }
  EXPECT_EQ(counter.allocations(), 0u);
}

TEST(RigTypes, ModeNames) {
  EXPECT_EQ(rig::command_mode_from_string("speed"), rig::CommandMode::speed);
  EXPECT_EQ(rig::to_string(rig::CommandMode::position), "position");
  EXPECT_THROW(rig::command_mode_from_string("torque"), cs::InvalidArgument);
  EXPECT_EQ(rig::to_string(LifecycleState::error), "error");
}
