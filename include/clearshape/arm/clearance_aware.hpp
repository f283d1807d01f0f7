#pragma once
// The clearance-aware command for the arm (issue 24 item 4 c; docs/arm.md §7): the single
// joint's design (study/clearance_aware.hpp) generalised. One positive shaper for every joint (so
// the joints keep their synchronised path, only retimed), impulses on a grid from t = 0,
// amplitudes a_k = x_k / Σx with x_k ∈ [0, 1], optimised by simulating the nonlinear arm — its
// drives, the play and contact law in every joint, the bearings' friction — from several start
// places of the links in their plays. The objective for the move: r_s = residual_s / max(residual_s
// unshaped, ¼ of the largest unshaped one) over the start places s, J = max r + 0.1 · mean r, the
// tool residual being Eq. 5.1 on the tool position after the command ends (arm/benchmark.hpp).
// Search: NLopt LN_SBPLX (Rowan's subplex, derivative-free) from the uniform staircase. Start
// places run in parallel on a fixed assignment: the result does not depend on the thread count.
#include <vector>

#include <Eigen/Dense>

#include "clearshape/arm/benchmark.hpp"
#include "clearshape/shaping/shaper.hpp"

namespace clearshape::arm {

struct ArmClearanceAwareOptions {
  MovePlayOptions play;     ///< limits, sample time, settle; its start_play_fraction is ignored
  int slots = 8;            ///< impulse slots, [2, 32]
  double grid_s = 0.0;      ///< slot spacing; 0: a quarter period of the end pose's lowest mode
  /// Start places φ_i(0)/β_i of the links, each in [−1, 1], one value per joint (empty: every
  /// joint at −1, 0 and +1 together, and the two mixed corners).
  std::vector<Eigen::VectorXd> start_places;
  int max_evaluations = 100;  ///< of J, >= 10
  int threads = 2;            ///< parallel simulations, [1, 64]
  /// Throws InvalidArgument naming the field and its range.
  void validate(int dof) const;
};

struct ArmClearanceAwareResult {
  shaping::Shaper shaper{"arm-clearance-aware", {{0.0, 1.0}}};
  std::vector<Eigen::VectorXd> start_places;
  std::vector<double> unshaped_residual_m;  ///< per start place
  std::vector<double> shaped_residual_m;    ///< per start place
  double worst_ratio = 0.0;                 ///< max over start places of shaped / unshaped
  bool worse_than_unshaped = false;         ///< some start place ends worse: never offered silently
  int evaluations = 0;
};

/// The design for one move. Throws InvalidArgument on bad options, RuntimeError if NLopt fails.
ArmClearanceAwareResult design_clearance_aware_move(const ArmModel& arm, const PointToPoint& move,
                                                    const ArmClearanceAwareOptions& options);

/// The benchmark's row of the clearance-aware design: each move designed on its own and played
/// from `options.play`'s start place; its improvement against `unshaped` (run_benchmark's first).
BenchmarkDesign clearance_aware_benchmark(const ArmModel& arm, std::span<const PointToPoint> moves,
                                          const ArmClearanceAwareOptions& options, const BenchmarkDesign& unshaped);

}  // namespace clearshape::arm
