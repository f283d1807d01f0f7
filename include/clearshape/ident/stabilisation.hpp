#pragma once
// Stabilisation diagram (operational modal analysis; Peeters & De Roeck 2001, "Stochastic System
// Identification for Operational Modal Analysis: A Review", J. Dyn. Sys. Meas. Control 123(4);
// Brincker & Ventura 2015, "Introduction to Operational Modal Analysis", §11.4): subspace models
// of increasing order; a pole is stable when its frequency, damping ratio (and optionally its
// residue magnitude) change less than set tolerances from the nearest pole of the previous order.
// Physical modes are the poles that stay stable over several orders; spurious (noise) poles
// wander from order to order. The model order for the final fit is the lowest order at which every
// persistent mode is present as a stable pole — chosen without asking how many modes to report.
#include <cstddef>
#include <optional>
#include <vector>

#include "clearshape/core/series.hpp"
#include "clearshape/ident/experiment.hpp"

namespace clearshape::ident {

struct StabilisationOptions {
  std::size_t min_order = 2;
  std::size_t max_order = 24;          ///< highest model order of the diagram
  double frequency_tolerance = 0.01;   ///< relative |Δf|/f between consecutive orders (1 %)
  double damping_tolerance = 0.05;     ///< relative |Δζ|/ζ between consecutive orders (5 %)
  double amplitude_tolerance = 0.0;    ///< relative |Δ residue|/|residue|; 0 = not checked
  double max_damping_ratio = 0.7;      ///< a stable pole also has 0 < ζ < this
  std::size_t min_stable_orders = 5;   ///< a persistent mode is stable in at least this many orders
  /// and in this fraction of the orders from its first stable pole up: a noise pole is stable in at
  /// most about half (seeded records: ≤ 54 %); the DaISy robot arm's ζ 0.003 mode in 15 of 20
  double min_stable_fraction = 0.7;
  /// A pole counts towards persistence only when its residue is at least this fraction of the largest
  /// at its order: a weak persistent line (a harmonic of a nonlinear decay) must not set the order.
  double min_relative_amplitude = 0.05;
  /// Persistence counts fully stable poles (true) or poles stable in frequency and physical (false).
  /// Unset: the record decides. A free response needs the damping (ERA of noise has ζ ≈ 0 poles that
  /// hold their frequency). Input/output does not: the subspace ζ of a lightly damped mode under
  /// coloured output noise moves by more than 5 % between orders while its frequency holds to 1 %
  /// (4 Hz, ζ 0.02, AR(1) ρ 0.9 noise: the mode was not persistent in 64 of 200 records and went
  /// unreported); PO-MOESP's past-input instruments leave no noise poles that persist in frequency.
  std::optional<bool> persistence_needs_damping;
};

/// One pole pair of the diagram (continuous-time: s = ln z / T).
struct DiagramPole {
  double natural_frequency_rad_s = 0.0;
  double damping_ratio = 0.0;
  double amplitude = 0.0;        ///< residue magnitude of the pair (subspace model, relative only)
  bool stable_frequency = false; ///< |Δf|/f below the tolerance against the previous order
  bool stable_damping = false;   ///< and |Δζ|/ζ
  bool physical = false;         ///< 0 < ζ < max_damping_ratio
  bool stable = false;           ///< frequency, damping (and residue, if checked) stable, and physical
  double frequency_hz() const noexcept;
};

struct DiagramOrder {
  std::size_t order = 0;
  std::vector<DiagramPole> poles;  ///< by frequency
};

/// A mode that persists across orders: medians over its stable poles.
struct PersistentMode {
  double natural_frequency_rad_s = 0.0;
  double damping_ratio = 0.0;
  std::size_t stable_orders = 0;  ///< how many orders hold a stable pole of this mode
  double frequency_hz() const noexcept;
};

struct StabilisationDiagram {
  StabilisationOptions options;
  std::vector<DiagramOrder> orders;
  std::vector<PersistentMode> modes;  ///< by frequency
  std::size_t chosen_order = 0;       ///< lowest order holding every persistent mode stable (0: none)
  std::size_t decimation = 1;         ///< block averaging used for the free-response diagram
};

/// The diagram from given poles per order (each order's poles: ωn, ζ, amplitude): flags, persistent
/// modes and the chosen order. Pure; throws InvalidArgument on bad options.
StabilisationDiagram build_stabilisation_diagram(std::vector<DiagramOrder> orders, const StabilisationOptions& options);

/// True when the pole lies within the frequency tolerance of the mode (relative).
bool matches(const PersistentMode& mode, double natural_frequency_rad_s, double tolerance);

/// Free response: ERA (fixed Hankel rows) on the block-averaged record at every order.
StabilisationDiagram free_response_stabilisation(const UniformSeries& response, const StabilisationOptions& options = {});

/// Input/output: PO-MOESP subspace (fixed horizon) at every order.
StabilisationDiagram input_output_stabilisation(const Experiment& experiment, const StabilisationOptions& options = {});

}  // namespace clearshape::ident
