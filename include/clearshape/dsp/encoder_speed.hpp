#pragma once
// The thesis's speed-measurement chain (§3.3, §4.1.1): encoder counts → degrees → derivative
// with respect to time → 4th-order low-pass Butterworth with a 30 rad/s passband edge (taken as
// the −3 dB cutoff), logged at 1 kHz. Two variants:
//   causal      backward difference + sosfilt from rest — what a real-time (Simulink) chain
//               computes; it lags by the filter's group delay (≈ 2.6 / 30 rad/s ≈ 87 ms at DC).
//   zero_phase  central difference (numpy.gradient) + sosfiltfilt with odd padding — offline,
//               no lag. The padding is 1 s (kThesisZeroPhasePadS), not scipy's default
//               3·(2·2+1) = 15 samples: the slowest pole of the filter decays as e^{−11.5 t}
//               (30 rad/s · sin(π/8)), so a 15-sample pad leaves an edge transient of about
//               slope × group delay (tens of °/s on a fast move), while 1 s leaves e^{−11.5} ≈ 1e−5
//               of it.
#include <cstdint>
#include <span>
#include <vector>

#include "clearshape/dsp/differentiate.hpp"
#include "clearshape/dsp/sos.hpp"
#include "clearshape/dsp/sosfilt.hpp"

namespace clearshape::dsp {

inline constexpr int kThesisSpeedFilterOrder = 4;              // §3.3
inline constexpr double kThesisSpeedFilterCutoffRadS = 30.0;   // §3.3, passband edge
inline constexpr double kThesisSampleTimeS = 1e-3;             // 1 kHz logging (note to Eq. 4.1)
/// Counts per motor revolution: the 3000 p/r incremental encoder (Table 3.1) decoded ×4.
inline constexpr double kThesisEncoderCountsPerRev = 4.0 * 3000.0;
/// Edge padding of the zero-phase chain, in seconds (see the file comment).
inline constexpr double kThesisZeroPhasePadS = 1.0;

enum class Phase { causal, zero_phase };

/// butter_lowpass_rad_s(4, 30 rad/s, 1 / sample_time_s). Throws InvalidArgument if the
/// sample time is not > 0 or puts 30 rad/s at or above Nyquist (sample_time_s ≥ π/30 s).
SosDesign thesis_speed_filter(double sample_time_s = kThesisSampleTimeS);

/// Encoder counts → angle in degrees (360 / counts_per_rev per count).
std::vector<double> encoder_counts_to_deg(std::span<const std::int64_t> counts,
                                          double counts_per_rev = kThesisEncoderCountsPerRev);

/// Angular speed in °/s from an angle in degrees sampled every sample_time_s, through the
/// thesis chain (see the file comment for the variants). The zero-phase variant pads each end
/// with min(round(kThesisZeroPhasePadS / sample_time_s), n − 1) samples and needs n ≥ 2.
std::vector<double> angle_speed_deg_s(std::span<const double> angle_deg, double sample_time_s,
                                      Phase phase = Phase::causal);
/// Same from raw encoder counts.
std::vector<double> encoder_speed_deg_s(std::span<const std::int64_t> counts, double sample_time_s,
                                        Phase phase = Phase::causal,
                                        double counts_per_rev = kThesisEncoderCountsPerRev);

/// The causal chain in real time: one encoder count in, one filtered speed (°/s) out.
/// noexcept and allocation-free after construction; equals encoder_speed_deg_s(…, causal).
class StreamingEncoderSpeed {
 public:
  explicit StreamingEncoderSpeed(double sample_time_s = kThesisSampleTimeS,
                                 double counts_per_rev = kThesisEncoderCountsPerRev);
  /// Filtered speed in °/s after this count.
  double step(std::int64_t count) noexcept;
  void reset() noexcept;

 private:
  double deg_per_count_;
  StreamingDifference difference_;
  StreamingSosFilter filter_;
};

}  // namespace clearshape::dsp
