// Fuzz target: the identify/modes entry points on arbitrary records — the free-response mode
// finder (`clearshape modes`) and a process-model fit (`clearshape identify`) must reject or
// answer, never crash. Input layout:
//   byte 0      bit 0: sample encoding (0 raw IEEE doubles: NaN, inf, subnormals, huge — a record
//               shorter than kMinRawSamples is repeated up to it, so such values reach the fits
//               and not only the length check; 1 int16 little-endian / 1000: finite records of
//               any shape)
//               bits 1-2: process structure (P1, P1D, P2U, P1I)
//   bytes 1…    the samples (at most 512; scripts/run-fuzz.sh passes -max_len=257, i.e. at most
//               128 int16 samples: enough for the ERA decimation path, q ≤ 128 / 60)
// Budget: kIterations Levenberg–Marquardt iterations per fit (the CLI default is 200). Every
// stage still runs — Welch decimation, ERA, amplitudes, LM refinement, covariance, ranking for
// modes; candidate search, LM, covariance and fit metrics for identify — but one execution costs
// ~7 ms of CPU instead of ~30 ms under ASan (measured on a corpus of 1,758 inputs). Ceres/glog is
// kept quiet as in the CLI (its per-step "Error in evaluating the ResidualBlock" reports are
// the solver rejecting a step, not a finding).
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <span>
#include <string_view>
#include <vector>

#include <glog/logging.h>

#include "clearshape/ident/modes.hpp"
#include "clearshape/ident/process_fit.hpp"
#include "fuzz_common.hpp"

namespace {
constexpr std::size_t kMaxSamples = 512;
constexpr std::size_t kMinRawSamples = 64;  // above the 50 the entry points need
constexpr std::size_t kIterations = 3;

std::vector<double> samples(const std::uint8_t* data, std::size_t size, bool int16) {
  std::vector<double> y;
  if (int16) {
    for (std::size_t i = 0; i + 1 < size && y.size() < kMaxSamples; i += 2) {
      const auto raw = static_cast<std::int16_t>(data[i] | (data[i + 1] << 8));
      y.push_back(raw / 1000.0);
    }
  } else {
    y.resize(std::min(size / sizeof(double), kMaxSamples));
    if (!y.empty()) std::memcpy(y.data(), data, y.size() * sizeof(double));
    for (std::size_t i = 0; !y.empty() && y.size() < kMinRawSamples; ++i) y.push_back(y[i]);
  }
  return y;
}
}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** argv) {
  FLAGS_logtostderr = true;
  FLAGS_minloglevel = google::GLOG_FATAL;
  FLAGS_stderrthreshold = google::GLOG_FATAL;
  google::InitGoogleLogging((*argv)[0]);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace clearshape;
  if (size < 1) return 0;
  const std::uint8_t selector = data[0];
  const std::vector<double> y = samples(data + 1, size - 1, (selector & 1U) != 0);
  constexpr std::array<std::string_view, 4> kStructures{"P1", "P1D", "P2U", "P1I"};
  const std::string_view structure = kStructures[(selector >> 1U) & 3U];

  fuzz::expect_clean_rejection([&] {
    ident::ModeOptions options;
    options.max_iterations = kIterations;
    (void)ident::identify_free_response_modes(UniformSeries{0.0, 1e-3, y}, options);
  });
  fuzz::expect_clean_rejection([&] {
    // A unit step as input, the fuzzed record as the response (identify --data with one run).
    const ident::Experiment e{"fuzz", 1e-3, std::vector<double>(y.size(), 1.0), y};
    ident::ProcessFitOptions options;
    options.max_iterations = kIterations;
    options.starts = 1;
    (void)ident::estimate_process_model(lti::ProcessStructure::parse(structure), std::span(&e, 1), options);
  });
  return 0;
}
