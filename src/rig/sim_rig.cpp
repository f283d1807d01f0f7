#include "clearshape/rig/sim_rig.hpp"

#include <cmath>
#include <optional>
#include <random>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/plant/encoder.hpp"
#include "clearshape/plant/gyroscope.hpp"
#include "clearshape/plant/simulation.hpp"
#include "clearshape/rig/truth.hpp"
#include "clearshape/signal/position_path.hpp"
#include "clearshape/signal/speed_path.hpp"
#include "sensors.hpp"

namespace clearshape::rig {

void SimRigOptions::validate() const {
  require_in_closed("sample_rate_hz", sample_rate_hz, 1.0, 1e5);
}

namespace {
// Independent streams of the variation (far from the initial-play and gyro streams 1, 2, …).
constexpr std::uint64_t kVariationStream = std::uint64_t{1} << 62;
constexpr std::uint64_t kAnalogNoiseStream = (std::uint64_t{1} << 62) + (std::uint64_t{1} << 61);

// The plant of one activation: the truth with the drawn flank damping.
plant::PlantModel varied_plant(const RigTruth& truth, CommandMode mode, double damping_factor) {
  if (damping_factor == 1.0) return plant_model(truth, mode);
  RigTruth t = truth;
  t.position_contact.damping *= damping_factor;
  t.speed_contact.damping *= damping_factor;
  return plant_model(t, mode);
}
}  // namespace

struct SimRig::Impl {
  explicit Impl(const RigTruth& t) : truth(t) {}

  RigTruth truth;
  // Configured (allocated) in on_configure.
  std::optional<plant::Simulator> simulator;
  std::optional<plant::Encoder> encoder;
  std::optional<plant::Gyroscope> gyro;
  std::optional<signal::PulseTrain> pulses;
  std::optional<Pacer> pacer;
  PacerStats no_pacing{};
  bool rigid = false;
  // Run state.
  std::uint64_t activations = 0;
  std::uint64_t sequence = 0;
  double target = 0.0;         // last accepted command, rig units
  double drive_command = 0.0;  // speed mode: the D/A output in drive units
  double update_period_s = 0.0;
  double next_update_s = 0.0;
  double update_start_s = 0.0;
  double previous_motor_rate = 0.0;
  std::uint32_t pending_flags = 0;
  std::uint64_t events_at_activation = 0;
  // Run-to-run variation (truth.variation): this activation's draw and the D/A noise source.
  RunDraw draw{};
  double drive_gain = 1.0;          // draw.position_gain or draw.speed_gain
  double applied_command = 0.0;     // speed mode: the drive command in force (after latency)
  std::mt19937_64 noise_rng{1};
  std::normal_distribution<double> noise{0.0, 1.0};
};

SimRig::SimRig(const SimRigOptions& options)
    : options_(options), impl_(std::make_unique<Impl>(thesis_rig_truth())) {}

SimRig::SimRig(const SimRigOptions& options, const RigTruth& truth)
    : options_(options), impl_(std::make_unique<Impl>(truth)) {}

SimRig::~SimRig() = default;

std::unique_ptr<SimRig> make_sim_rig_with_truth(const SimRigOptions& options,
                                                const RigTruth& truth) {
  return std::unique_ptr<SimRig>(new SimRig(options, truth));
}

double SimRig::sample_time_s() const noexcept { return 1.0 / options_.sample_rate_hz; }

const PacerStats& SimRig::pacing_stats() const noexcept {
  return impl_->pacer ? impl_->pacer->stats() : impl_->no_pacing;
}

std::uint64_t SimRig::contact_events() const noexcept {
  if (!impl_->simulator || impl_->rigid) return 0;
  return static_cast<std::uint64_t>(impl_->simulator->stats().events) - impl_->events_at_activation;
}

void SimRig::on_configure() {
  options_.validate();
  Impl& m = *impl_;
  m.truth.validate();
  if (m.truth.variation.start_latency_max_s > sample_time_s()) {
    throw_invalid("truth.variation.start_latency_max_s", m.truth.variation.start_latency_max_s,
                  fmt::format("[0, {}] s (one sample period at {} Hz)", sample_time_s(), options_.sample_rate_hz),
                  "Lower the latency or the sample rate");
  }
  m.rigid = m.truth.clearance_rad == 0.0;
  m.simulator.emplace(plant_model(m.truth, options_.mode), m.truth.solver);
  m.encoder.emplace(m.truth.encoder);
  m.gyro.emplace(detail::gyro_config(m.truth, options_.sample_rate_hz, options_.seed, true));
  if (options_.mode == CommandMode::position) m.pulses.emplace(m.truth.pulse_train);
  m.update_period_s = m.truth.pulse_train.update_period_s();
  if (options_.pacing == Pacing::wall_clock) m.pacer.emplace(sample_time_s());
}

void SimRig::on_activate() {
  Impl& m = *impl_;
  const std::uint64_t run = m.activations++;
  // The link rests anywhere in the play (seeded draw per activation) unless fixed by the truth.
  double fraction = m.truth.initial_play_fraction;
  if (m.truth.random_initial_play) {
    std::mt19937_64 rng(detail::mix_seed(options_.seed, 2 * run + 1));
    fraction = std::uniform_real_distribution<double>(-1.0, 1.0)(rng);
  }
  plant::InitialState initial;
  initial.relative_angle_rad = m.rigid ? 0.0 : fraction * m.truth.half_play_rad();
  // Run-to-run variation: one draw per activation (own stream; nothing drawn when all σ are 0,
  // so such a rig gives the same bytes as one without variation).
  const RunVariation& v = m.truth.variation;
  m.draw = RunDraw{};
  if (v.any()) {
    std::mt19937_64 rng(detail::mix_seed(options_.seed, kVariationStream + run));
    m.draw = draw_run_variation(v, rng);
    m.noise_rng.seed(detail::mix_seed(options_.seed, kAnalogNoiseStream + run));
    m.noise.reset();
    if (m.draw.flank_damping_factor != 1.0 || v.flank_damping_rel_sigma > 0.0) {
      m.simulator.emplace(varied_plant(m.truth, options_.mode, m.draw.flank_damping_factor), m.truth.solver);
    }
  }
  m.drive_gain = options_.mode == CommandMode::position ? m.draw.position_gain : m.draw.speed_gain;
  m.simulator->reset(initial, 0.0);
  m.events_at_activation = static_cast<std::uint64_t>(m.simulator->stats().events);
  m.simulator->clear_events();
  m.gyro.emplace(detail::gyro_config(m.truth, options_.sample_rate_hz,
                                     detail::mix_seed(options_.seed, 2 * run + 2), true));
  m.gyro->reset(0.0);
  if (m.pulses) m.pulses->reset(0.0);
  m.sequence = 0;
  m.target = 0.0;
  m.drive_command = 0.0;
  m.applied_command = 0.0;
  // Position mode: the 30 Hz update clock's phase is the drawn latency.
  m.next_update_s = m.draw.start_latency_s;
  m.update_start_s = 0.0;
  m.previous_motor_rate = 0.0;
  m.pending_flags = 0;
  if (m.pacer) m.pacer->start();
}

void SimRig::on_deactivate() noexcept {
  impl_->target = 0.0;
  impl_->drive_command = 0.0;
}

void SimRig::on_cleanup() noexcept {
  Impl& m = *impl_;
  m.simulator.reset();
  m.encoder.reset();
  m.gyro.reset();
  m.pulses.reset();
  m.pacer.reset();
}

Status SimRig::on_read(Measurement& out) noexcept {
  Impl& m = *impl_;
  const double ts = sample_time_s();
  const double t = static_cast<double>(m.sequence) * ts;
  std::uint32_t flags = m.pending_flags;
  m.pending_flags = 0;
  if (m.sequence > 0) {
    const double t_previous = t - ts;
    double command = m.drive_command;
    Status status = Status::ok;
    if (!m.pulses) {
      // Speed mode: the D/A output is the written command times the drawn gain, plus the drawn
      // offset and white noise; a new value takes effect start_latency_s after the sample.
      const RunVariation& v = m.truth.variation;
      command = m.drive_gain * m.drive_command + m.draw.analog_offset_v / m.truth.analog_output.volts_per_unit;
      if (v.analog_noise_v > 0.0) {
        command += v.analog_noise_v * m.noise(m.noise_rng) / m.truth.analog_output.volts_per_unit;
      }
      if (m.draw.start_latency_s > 1e-9 * ts && command != m.applied_command) {
        status = m.simulator->advance(t_previous + m.draw.start_latency_s, m.applied_command);
        if (status != Status::ok) return Status::device_error;
      }
      m.applied_command = command;
    }
    if (m.pulses) {
      // Position mode: the pulse generator takes a new target at each 30 Hz update instant.
      if (t_previous >= m.next_update_s - 1e-9 * ts) {
        m.update_start_s = m.next_update_s;
        while (m.next_update_s <= t_previous + 1e-9 * ts) m.next_update_s += m.update_period_s;
        if (m.pulses->program(m.target) == Status::out_of_range) {
          flags |= bit(MeasurementFlag::command_limited);
        }
      }
      command = m.drive_gain * drive_units(CommandMode::position,
                                           m.pulses->commanded_rad(t_previous - m.update_start_s));
    }
    status = m.simulator->advance(t, command);
    if (status != Status::ok) return Status::device_error;
  }
  if (m.pacer && m.pacer->wait() == Status::overrun) flags |= bit(MeasurementFlag::overrun);

  const plant::Simulator::State& s = m.simulator->state();
  const double link_rate = m.rigid ? s.motor_rate_rad_s : s.link_rate_rad_s;
  const plant::GyroSample g = m.gyro->sample(link_rate);
  out.time_s = t;
  out.sequence = m.sequence++;
  out.encoder_counts = m.encoder->count(s.motor_angle_rad);
  out.motor_angle_rad = m.encoder->angle_rad(out.encoder_counts);
  out.gyro_raw = g.raw;
  out.gyro_rate_rad_s = g.rate_rad_s;
  out.command_applied = m.pulses ? m.pulses->commanded_rad(t - m.update_start_s) : m.drive_command;
  if (g.saturated) flags |= bit(MeasurementFlag::gyro_saturated);
  out.flags = flags;
  return Status::ok;
}

Status SimRig::on_write(const Command& command) noexcept {
  Impl& m = *impl_;
  if (const Status rejected = check_command(command, options_.mode); rejected != Status::ok) {
    m.pending_flags |= bit(MeasurementFlag::command_rejected);
    return rejected;
  }
  m.target = command.value;
  if (options_.mode == CommandMode::speed) {
    double volts = 0.0;
    const Status status = signal::analog_output_v(m.truth.analog_output, command.value, volts);
    m.drive_command = volts / m.truth.analog_output.volts_per_unit;
    if (status == Status::out_of_range) {
      m.pending_flags |= bit(MeasurementFlag::command_limited);
      return Status::out_of_range;
    }
  }
  return Status::ok;
}

}  // namespace clearshape::rig
