// clearshape-rig-emulator: runs the rig firmware ELF (the file one would flash on the Mega
// 2560) in simavr against clearshape's simulated plant and exposes the board's UART0 as a
// pseudo-terminal, so a host (rig::SerialRig, the tests) talks to it as to the real board.
// The first line on stdout is the pty's path; statistics go to stderr at the end.
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>
#include <unistd.h>

#include <CLI/CLI.hpp>

#include "board.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/rig/builtin_truths.hpp"
#include "clearshape/rig/truth.hpp"
#include "option_checks.hpp"

#ifndef CLEARSHAPE_FIRMWARE_ELF
#define CLEARSHAPE_FIRMWARE_ELF ""
#endif

namespace {
volatile int g_stop = 0;

// ATmega2560 interrupt vectors the firmware uses (datasheet Table 14-1, numbered from reset = 0).
const char* vector_name(int vector) {
  switch (vector) {
    case 5: return "INT4 encoder A";
    case 6: return "INT5 encoder B";
    case 17: return "TIMER1_COMPA tick";
    case 25: return "USART0_RX";
    case 26: return "USART0_UDRE";
    case 32: return "TIMER3_COMPA pulse";
    case 39: return "TWI";
    default: return "other";
  }
}
extern "C" void on_signal(int) { g_stop = 1; }


// The emulator's command line.
struct EmulatorOptions {
  clearshape::emulator::BoardOptions board;
  clearshape::emulator::RigPlantOptions plant;
  std::string link;
  std::string rig = "thesis";
  bool free_run = false;
  bool no_noise = false;
  double plant_step_us = 100.0;
};

void add_options(CLI::App& app, EmulatorOptions& o) {
  using namespace clearshape;
  app.add_option("--elf", o.board.elf_path, "firmware ELF to run (default: the build's)");
  app.add_option("--link", o.link, "also make a symlink PATH to the pty (removed at exit)");
  std::vector<std::string> rig_names(rig::kBuiltinTruthNames.begin(), rig::kBuiltinTruthNames.end());
  rig_names.emplace_back("prior");
  app.add_option("--rig", o.rig,
                 "plant truth: a built-in truth (thesis: the calibrated thesis rig, default; "
                 "large-play) or prior (the uncalibrated thesis prior)")
      ->check(CLI::IsMember(rig_names));
  app.add_option("--seed", o.plant.seed, "seed of the gyroscope noise");
  app.add_flag("--no-noise", o.no_noise, "no gyroscope noise");
  app.add_option("--initial-play", o.plant.initial_play_fraction,
                 "initial link position in the play, phi(0)/beta in [-1, 1] (default 0)")
      ->check(CLI::Range(-1.0, 1.0));
  app.add_option("--speed", o.board.speed, "AVR seconds per wall second (default 1: real time)")
      ->check(CLI::Range(1e-3, 1e3));
  app.add_flag("--free", o.free_run, "run as fast as possible (no pacing)");
  app.add_option("--plant-step-us", o.plant_step_us, "plant step in AVR time, us [10, 1000] (default 100)")
      ->check(CLI::Range(10.0, 1000.0));
  app.add_option("--corrupt-every", o.board.damage.corrupt_every,
                 "XOR 0x5A into every Nth byte from the board (tests; 0 = never)");
  app.add_option("--drop-every", o.board.damage.drop_every,
                 "drop every Nth byte from the board (tests; 0 = never)");
  app.add_option("--duration-s", o.board.duration_s, "stop after this much AVR time, s (0 = run until a signal)")
      ->check(CLI::Range(0.0, 1e6));
  app.add_flag("--isr-profile", o.board.isr_profile,
               "measure each interrupt's cycles (vector fetch to reti) and print them at exit");
  cli::add_common_option_checks(app);
}

// --link: a symlink to the pty (an old link there is replaced); false (message printed) if it fails.
bool make_link(const std::string& link, const std::string& pty_path) {
  std::error_code ec;
  if (std::filesystem::is_symlink(link, ec)) std::filesystem::remove(link, ec);
  std::filesystem::create_symlink(pty_path, link, ec);
  if (ec) {
    std::fprintf(stderr, "clearshape-rig-emulator: --link: cannot create %s: %s\n", link.c_str(),
                 ec.message().c_str());
    return false;
  }
  return true;
}

void print_statistics(const clearshape::emulator::Board& sim) {
  const clearshape::emulator::BoardStats s = sim.stats();
  std::fprintf(stderr,
               "clearshape-rig-emulator: %.3f s simulated in %.3f s wall (%.2f simulated s per wall s); "
               "pulse edges %lld (illegal %lld), encoder edges %lld, gyro samples %llu, DAC writes %llu\n",
               s.simulated_s, s.wall_s, s.wall_s > 0 ? s.simulated_s / s.wall_s : 0.0,
               static_cast<long long>(s.pulse_edges), static_cast<long long>(s.pulse_illegal),
               static_cast<long long>(s.encoder_edges), static_cast<unsigned long long>(s.gyro_samples),
               static_cast<unsigned long long>(s.dac_writes));
  for (const clearshape::emulator::IsrProfile& p : sim.isr_profile()) {
    std::fprintf(stderr, "isr vector %2d (%s): %llu calls, cycles min %llu mean %.1f max %llu\n", p.vector,
                 vector_name(p.vector), static_cast<unsigned long long>(p.count),
                 static_cast<unsigned long long>(p.min_cycles),
                 static_cast<double>(p.total_cycles) / static_cast<double>(p.count),
                 static_cast<unsigned long long>(p.max_cycles));
  }
}

// Runs the board until the duration or a signal: the pty's path on stdout, statistics at the end.
int run(const EmulatorOptions& o, const clearshape::rig::RigTruth& truth) {
  clearshape::emulator::Board sim(o.board, truth, o.plant);
  if (!o.link.empty() && !make_link(o.link, sim.pty_path())) return 2;
  std::printf("%s\n", sim.pty_path().c_str());
  std::fflush(stdout);
  const int status = sim.run(g_stop);
  print_statistics(sim);
  if (!o.link.empty()) {
    std::error_code ec;
    std::filesystem::remove(o.link, ec);
  }
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace clearshape;
  CLI::App app{
      "clearshape-rig-emulator: the rig firmware ELF in simavr (ATmega2560, 16 MHz) against\n"
      "clearshape's simulated thesis rig. UART0 is a pseudo-terminal whose path is the first\n"
      "line on stdout; the host chooses the mode with CONFIGURE (the emulator follows it)."};
  EmulatorOptions o;
  o.board.elf_path = CLEARSHAPE_FIRMWARE_ELF;
  add_options(app, o);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  if (o.free_run) o.board.speed = 0.0;
  o.board.plant_step_s = o.plant_step_us * 1e-6;
  if (o.board.elf_path.empty()) {
    std::fprintf(stderr, "clearshape-rig-emulator: --elf: no firmware given and none was built\n");
    return 2;
  }
  const rig::RigTruth truth =
      o.rig == "prior" ? rig::uncalibrated_thesis_rig_prior() : rig::builtin_truth(o.rig, "--rig");
  o.plant.noise = !o.no_noise;
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  try {
    return run(o, truth);
  } catch (const InvalidArgument& e) {
    std::fprintf(stderr, "clearshape-rig-emulator: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "clearshape-rig-emulator: %s\n", e.what());
    return 1;
  }
}
