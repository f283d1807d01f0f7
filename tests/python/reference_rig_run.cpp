// The C++ side of tests/python/test_simulation.py::test_simulate_rig_is_the_cpp_run: one run of a
// step on a SimRig built with a named truth (study::execute_run, the path the study records),
// printed as CSV with 17 significant digits so that Python reads back the same doubles.
// Usage: reference_rig_run TRUTH MODE AMPLITUDE START_S DURATION_S SEED
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "clearshape/rig/builtin_truths.hpp"
#include "clearshape/rig/sim_rig.hpp"
#include "clearshape/signal/parameters.hpp"
#include "clearshape/signal/signal.hpp"
#include "clearshape/study/record.hpp"

namespace rg = clearshape::rig;
namespace sig = clearshape::signal;

int main(int argc, char** argv) {
  if (argc != 7) {
    std::fprintf(stderr, "usage: reference_rig_run TRUTH MODE AMPLITUDE START_S DURATION_S SEED\n");
    return 2;
  }
  try {
    const double duration_s = std::stod(argv[5]);
    rg::SimRigOptions options;
    options.mode = rg::command_mode_from_string(argv[2]);
    options.seed = std::stoull(argv[6]);
    const sig::Signal step = sig::make_signal("step", {{"amplitude", std::stod(argv[3])}, {"start_s", std::stod(argv[4])}});
    clearshape::study::RunRequest request;
    request.id = "python";
    request.seed = options.seed;
    request.command = sig::sample(step, options.sample_rate_hz, duration_s);
    request.record_s = duration_s;
    auto rig = rg::make_sim_rig_with_truth(options, rg::builtin_truth(argv[1]));
    const auto r = clearshape::study::execute_run(*rig, request);
    std::printf("time_s,command_applied,motor_angle_deg,link_rate_deg_s\n");
    for (std::size_t k = 0; k < r.size(); ++k) {
      std::printf("%.17g,%.17g,%.17g,%.17g\n", r.time_s[k], r.command_applied[k], r.motor_angle_deg[k],
                  r.link_rate_deg_s[k]);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "reference_rig_run: %s\n", e.what());
    return 1;
  }
  return 0;
}
