#pragma once
// MATLAB-style process models (System Identification Toolbox idproc/procest, thesis §4.2):
//   G(s) = Kp · (1 + Tz s) / den(s) · e^(−Td s) [· 1/s],
//   den(s) = (1 + Tp1 s)(1 + Tp2 s)(1 + Tp3 s)             (P1, P2, P3: real poles)
//   den(s) = (1 + 2 Zeta Tw s + (Tw s)²) [(1 + Tp3 s)]     (P2U, P3U: underdamped pair)
// The structure code is "P" + number of poles (0–3) + letters in any order: D (delay Td),
// Z (zero Tz), U (underdamped pair Tw, Zeta; needs ≥ 2 poles), I (integrator).
// The thesis model (Eq. 4.2) is P3UZ. Gains map command units to output units (docs/design.md §2).
#include <complex>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "clearshape/lti/modes.hpp"
#include "clearshape/lti/state_space.hpp"
#include "clearshape/lti/transfer_function.hpp"

namespace clearshape::lti {

struct ProcessStructure {
  int pole_count = 1;        ///< 0…3
  bool delay = false;        ///< D: e^(−Td s)
  bool zero = false;         ///< Z: (1 + Tz s)
  bool underdamped = false;  ///< U: (1 + 2 Zeta Tw s + (Tw s)²) replaces (1+Tp1 s)(1+Tp2 s)
  bool integrator = false;   ///< I: 1/s

  /// Parses "P3UZ", "p1d", "P2DIZ", … (case-insensitive, letters once each, any order).
  /// Throws InvalidArgument explaining the grammar.
  static ProcessStructure parse(std::string_view code);
  /// Canonical code: "P", the pole count, then D, I, Z, U as present (e.g. "P3ZU").
  std::string code() const;
  /// Names of this structure's parameters, in the order Kp, Tp1, Tp2, Tp3, Tw, Zeta, Td, Tz.
  std::vector<std::string_view> parameter_names() const;
  bool has_parameter(std::string_view name) const;
  bool operator==(const ProcessStructure&) const = default;
};

/// Parameter values (MATLAB names). Time constants and delay in seconds; Kp in output units
/// per command unit. Parameters the structure does not use must stay 0.
struct ProcessParameters {
  double kp = 1.0;
  double tp1 = 0.0;
  double tp2 = 0.0;
  double tp3 = 0.0;
  double tw = 0.0;
  double zeta = 0.0;
  double td = 0.0;
  double tz = 0.0;

  /// By MATLAB name ("Kp", "Tp1", …, case-insensitive); throws InvalidArgument for others.
  double get(std::string_view name) const;
  void set(std::string_view name, double value);
};

class ProcessModel {
 public:
  /// Validates: Kp and Tz finite (Tz may be negative: a right-half-plane zero at s = −1/Tz);
  /// Tp1, Tp2, Tp3, Tw, Zeta, Td ≥ 0; unused parameters 0; a zero needs a dynamic factor.
  /// A time constant of 0 removes its factor. Throws InvalidArgument naming the parameter.
  ProcessModel(ProcessStructure structure, ProcessParameters parameters);
  ProcessModel(std::string_view code, ProcessParameters parameters);
  /// From values in parameter_names() order (for optimizers).
  static ProcessModel from_vector(ProcessStructure structure, std::span<const double> values);
  std::vector<double> to_vector() const;

  const ProcessStructure& structure() const noexcept { return structure_; }
  const ProcessParameters& parameters() const noexcept { return parameters_; }
  std::string code() const { return structure_.code(); }
  double delay_s() const noexcept { return parameters_.td; }

  /// The rational part (delay excluded), expanded to polynomials.
  TransferFunction transfer_function() const;
  /// Cascade realization (delay excluded): well-scaled first- and second-order sections in
  /// series, gain and zero in the last one; states are outputs of the sections and their
  /// derivatives scaled by Tw. Conditioned independently of how far apart the time constants are.
  StateSpace state_space() const;

  /// Poles and zeros from the factors (closed form), sorted by real part then imaginary part.
  std::vector<std::complex<double>> poles() const;
  std::vector<std::complex<double>> zeros() const;
  std::vector<OscillatoryMode> oscillatory_modes() const;
  /// Kp (= G(0)) without integrator; ±infinity with one.
  double dc_gain() const noexcept;
  /// G(jω), delay included.
  std::complex<double> frequency_response(double frequency_rad_s) const noexcept;

  /// ωn = 1/Tw (thesis §4.2). Throws InvalidArgument if the structure has no U pair or Tw = 0.
  double natural_frequency_rad_s() const;
  /// ζ = Zeta (thesis §4.2). Throws InvalidArgument if the structure has no U pair.
  double damping_ratio() const;

 private:
  ProcessStructure structure_;
  ProcessParameters parameters_;
};

/// Thesis Eq. 4.2, speed operation mode: Kp 25.47, Tz −0.0398 s, Zeta 0.2880, Tw 0.0479 s,
/// Tp3 0.0857 s (P3UZ; velocity command → motor speed).
ProcessModel thesis_speed_mode_model();
/// Thesis Eq. 4.2, position operation mode: Kp 0.9959, Tz 0.0042 s, Zeta 0.9968, Tw 0.0102 s,
/// Tp3 0.0034 s (P3UZ; position command → motor angle).
ProcessModel thesis_position_mode_model();

}  // namespace clearshape::lti
