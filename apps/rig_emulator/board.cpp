#include "board.hpp"

#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <thread>

#include <simavr/avr_ioport.h>
#include <simavr/sim_avr.h>
#include <simavr/sim_elf.h>
#include <simavr/sim_io.h>
#include <simavr/sim_irq.h>

#include "clearshape/core/error.hpp"

namespace clearshape::emulator {

namespace {
constexpr std::uint32_t kCpuHz = 16000000;
// (A, B) of the quadrature phases 0..3 (firmware/board.h: forward 00 → 10 → 11 → 01).
constexpr std::uint8_t kPhaseA[4] = {0, 1, 1, 0};
constexpr std::uint8_t kPhaseB[4] = {0, 0, 1, 1};
// x4 decoding, index (previous << 2) | current with state (A << 1) | B; 2 = illegal.
constexpr int kQuadTable[16] = {0, -1, 1, 2, 1, 0, 2, -1, -1, 2, 0, 1, 2, 1, -1, 0};
}  // namespace

struct Board::Impl {
  BoardOptions options;
  avr_t* avr = nullptr;
  std::optional<RigPlant> plant;
  std::optional<Itg3205> gyro;
  std::optional<Mcp4725> dac;
  std::optional<PtyLink> pty;
  avr_irq_t* encoder_a = nullptr;
  avr_irq_t* encoder_b = nullptr;
  avr_cycle_count_t step_cycles = 1600;
  // Pins the firmware drives.
  std::uint8_t pulse_state = 0;  // (A << 1) | B
  std::int64_t pulse_edges = 0;
  std::int64_t pulse_illegal = 0;
  bool servo_on = false;
  // Encoder output.
  std::int64_t encoder_out = 0;     // count currently on the pins
  std::int64_t encoder_target = 0;  // count of the plant
  avr_cycle_count_t edge_spacing = 1;
  bool edge_timer_running = false;
  std::int64_t encoder_edges = 0;
  // Gyroscope output data clock.
  double next_gyro_s = 0.0;
  std::uint64_t gyro_samples = 0;
  // Interrupt profile (vector fetch to reti, per vector).
  std::array<IsrProfile, 64> isr{};
  int isr_vector = -1;
  avr_cycle_count_t isr_start = 0;
  // Pacing.
  std::chrono::steady_clock::time_point wall_start;
  double wall_s = 0.0;
  bool failed = false;

  double now_s() const { return static_cast<double>(avr->cycle) / kCpuHz; }

  static void on_pulse_a(avr_irq_t*, std::uint32_t value, void* param) {
    static_cast<Impl*>(param)->on_pulse_pin(2u, value != 0);  // A = bit 1 of the state
  }
  static void on_pulse_b(avr_irq_t*, std::uint32_t value, void* param) {
    static_cast<Impl*>(param)->on_pulse_pin(1u, value != 0);
  }
  void on_pulse_pin(std::uint8_t bit, bool high) {
    Impl* m = this;
    const auto now = static_cast<std::uint8_t>(high ? (m->pulse_state | bit) : (m->pulse_state & ~bit));
    if (now == m->pulse_state) return;
    const int step = kQuadTable[(m->pulse_state << 2) | now];
    m->pulse_state = now;
    if (step == 2) {
      ++m->pulse_illegal;
    } else {
      m->pulse_edges += step;
    }
  }

  static void on_servo_pin(avr_irq_t*, std::uint32_t value, void* param) {
    static_cast<Impl*>(param)->servo_on = value != 0;
  }

  void put_encoder_pins() {
    const auto phase = static_cast<unsigned>(encoder_out & 3);
    avr_raise_irq(encoder_a, kPhaseA[phase]);
    avr_raise_irq(encoder_b, kPhaseB[phase]);
  }

  static avr_cycle_count_t on_edge(avr_t*, avr_cycle_count_t when, void* param) {
    auto* m = static_cast<Impl*>(param);
    if (m->encoder_out == m->encoder_target) {
      m->edge_timer_running = false;
      return 0;
    }
    m->encoder_out += m->encoder_target > m->encoder_out ? 1 : -1;
    ++m->encoder_edges;
    m->put_encoder_pins();
    if (m->encoder_out == m->encoder_target) {
      m->edge_timer_running = false;
      return 0;
    }
    return when + m->edge_spacing;
  }

  static avr_cycle_count_t on_step(avr_t*, avr_cycle_count_t when, void* param) {
    auto* m = static_cast<Impl*>(param);
    m->step();
    return m->failed ? 0 : when + m->step_cycles;
  }

  void step() {
    const double t = now_s();
    const int mode = pty->take_configured_mode();
    if ((mode == 0 || mode == 1) &&
        static_cast<rig::CommandMode>(mode) != plant->mode()) {
      plant->restart(static_cast<rig::CommandMode>(mode), t);
      pulse_edges = 0;
    }
    if (!plant->advance(t, pulse_edges, dac->code(), servo_on)) {
      std::fprintf(stderr, "clearshape-rig-emulator: plant integration failed at %.6f s: %s\n", t,
                   plant->error_message());
      failed = true;
      return;
    }
    // The ITG-3205 latches a new word at its output data rate.
    const double gyro_rate = gyro->output_rate_hz();
    while (next_gyro_s <= t) {
      gyro->set_z(plant->gyro_sample(gyro_rate).raw);
      ++gyro_samples;
      next_gyro_s += 1.0 / gyro_rate;
    }
    // Encoder edges towards the plant's count, spread evenly over the next step.
    encoder_target = plant->encoder_count();
    const std::int64_t distance = std::llabs(encoder_target - encoder_out);
    if (distance > 0) {
      edge_spacing = std::max<avr_cycle_count_t>(1, step_cycles / static_cast<avr_cycle_count_t>(distance));
      if (!edge_timer_running) {
        edge_timer_running = true;
        avr_cycle_timer_register(avr, 1, &Impl::on_edge, this);
      }
    }
    pty->service();
    pace(t);
  }

  // Called after every instruction: an ISR starts when the PC is in the vector table (4 bytes
  // per vector on the ATmega2560; vector 0 is reset) and ends when reti sets I again.
  void profile_step() {
    const auto pc = static_cast<std::uint32_t>(avr->pc);
    if (isr_vector < 0) {
      if (pc >= 4 && pc < 4 * 57 && pc % 4 == 0) {
        isr_vector = static_cast<int>(pc / 4);
        isr_start = avr->cycle;
      }
      return;
    }
    if (!avr->sreg[S_I]) return;
    IsrProfile& p = isr[static_cast<std::size_t>(isr_vector)];
    const std::uint64_t cycles = avr->cycle - isr_start;
    p.vector = isr_vector;
    p.min_cycles = p.count == 0 ? cycles : std::min(p.min_cycles, cycles);
    p.max_cycles = std::max(p.max_cycles, cycles);
    p.total_cycles += cycles;
    ++p.count;
    isr_vector = -1;
  }

  void pace(double t) {
    const auto wall = std::chrono::steady_clock::now() - wall_start;
    wall_s = std::chrono::duration<double>(wall).count();
    if (options.speed <= 0.0) return;
    const double ahead_s = t / options.speed - wall_s;
    if (ahead_s > 1e-3) std::this_thread::sleep_for(std::chrono::duration<double>(ahead_s));
  }
};

Board::Board(const BoardOptions& options, const rig::RigTruth& truth, const RigPlantOptions& plant)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.options = options;
  elf_firmware_t firmware{};
  // An ELF header (magic, then e_machine at byte 18, little endian) for the AVR (EM_AVR = 83).
  unsigned char header[20] = {};
  if (std::FILE* f = std::fopen(options.elf_path.c_str(), "rb")) {
    const std::size_t got = std::fread(header, 1, sizeof header, f);
    std::fclose(f);
    if (got != sizeof header || header[0] != 0x7F || header[1] != 'E' || header[2] != 'L' ||
        header[3] != 'F' || (header[18] | (header[19] << 8)) != 83) {
      throw InvalidArgument("--elf: " + options.elf_path + " is not an AVR ELF image");
    }
  } else {
    throw InvalidArgument("--elf: cannot read " + options.elf_path +
                          " (build the firmware: cmake --build build --target clearshape_firmware)");
  }
  // simavr reports the loaded sections on stdout; stdout belongs to the pty path, so its
  // chatter goes to stderr while it loads.
  std::fflush(stdout);
  const int saved_stdout = dup(STDOUT_FILENO);
  dup2(STDERR_FILENO, STDOUT_FILENO);
  const int read_status = elf_read_firmware(options.elf_path.c_str(), &firmware);
  m.avr = read_status == 0 ? avr_make_mcu_by_name("atmega2560") : nullptr;
  if (m.avr) {
    avr_init(m.avr);
    m.avr->frequency = kCpuHz;
    avr_load_firmware(m.avr, &firmware);
  }
  std::fflush(stdout);
  dup2(saved_stdout, STDOUT_FILENO);
  close(saved_stdout);
  if (read_status != 0) {
    throw InvalidArgument("--elf: " + options.elf_path + " is not an AVR ELF image");
  }
  if (!m.avr) throw RuntimeError("simavr has no atmega2560 core");
  m.avr->frequency = kCpuHz;  // the clock of the Mega, whatever the ELF says
  m.avr->log = 0;

  m.plant.emplace(truth, plant);
  m.gyro.emplace(m.avr);
  m.dac.emplace(m.avr);
  m.pty.emplace(m.avr, options.damage);
  avr_irq_register_notify(avr_io_getirq(m.avr, AVR_IOCTL_IOPORT_GETIRQ('A'), IOPORT_IRQ_PIN0),
                          &Impl::on_pulse_a, &m);
  avr_irq_register_notify(avr_io_getirq(m.avr, AVR_IOCTL_IOPORT_GETIRQ('A'), IOPORT_IRQ_PIN1),
                          &Impl::on_pulse_b, &m);
  avr_irq_register_notify(avr_io_getirq(m.avr, AVR_IOCTL_IOPORT_GETIRQ('A'), IOPORT_IRQ_PIN2),
                          &Impl::on_servo_pin, &m);
  m.encoder_a = avr_io_getirq(m.avr, AVR_IOCTL_IOPORT_GETIRQ('E'), IOPORT_IRQ_PIN4);
  m.encoder_b = avr_io_getirq(m.avr, AVR_IOCTL_IOPORT_GETIRQ('E'), IOPORT_IRQ_PIN5);
  m.put_encoder_pins();
  m.step_cycles = std::max<avr_cycle_count_t>(
      16, static_cast<avr_cycle_count_t>(options.plant_step_s * kCpuHz + 0.5));
  avr_cycle_timer_register(m.avr, m.step_cycles, &Impl::on_step, &m);
}

Board::~Board() {
  Impl& m = *impl_;
  m.pty.reset();
  m.dac.reset();
  m.gyro.reset();
  if (m.avr) avr_terminate(m.avr);
}

const std::string& Board::pty_path() const { return impl_->pty->slave_path(); }

int Board::run(const volatile int& stop_requested) {
  Impl& m = *impl_;
  m.pty->set_stop_flag(&stop_requested);
  m.wall_start = std::chrono::steady_clock::now();
  const auto end_cycle = static_cast<avr_cycle_count_t>(m.options.duration_s * kCpuHz);
  for (;;) {
    const int state = avr_run(m.avr);
    if (m.options.isr_profile) m.profile_step();
    if (state == cpu_Done || state == cpu_Crashed) {
      std::fprintf(stderr, "clearshape-rig-emulator: the firmware %s at %.6f s (pc 0x%05x)\n",
                   state == cpu_Done ? "stopped" : "crashed", m.now_s(), m.avr->pc);
      return 1;
    }
    if (m.failed) return 1;
    if (stop_requested) break;
    if (m.options.duration_s > 0.0 && m.avr->cycle >= end_cycle) break;
  }
  m.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - m.wall_start).count();
  if (!stop_requested) m.pty->service();
  return 0;
}

std::vector<IsrProfile> Board::isr_profile() const {
  std::vector<IsrProfile> out;
  for (const IsrProfile& p : impl_->isr) {
    if (p.count > 0) out.push_back(p);
  }
  return out;
}

BoardStats Board::stats() const {
  const Impl& m = *impl_;
  BoardStats s;
  s.simulated_s = m.now_s();
  s.wall_s = m.wall_s;
  s.pulse_edges = m.pulse_edges;
  s.pulse_illegal = m.pulse_illegal;
  s.encoder_edges = m.encoder_edges;
  s.gyro_samples = m.gyro_samples;
  s.dac_writes = m.dac->writes();
  s.servo_on = m.servo_on;
  return s;
}

}  // namespace clearshape::emulator
