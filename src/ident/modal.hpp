#pragma once
// Internal: a SISO discrete model in real modal form and its least-squares refinement.
// Complex pair z = r e^(±iθ): 2×2 block r·[cos θ −sin θ; sin θ cos θ], input vector [0 1]ᵀ,
// output row c = (c0, c1), initial state x0 (2). Real pole p: scalar block, input 1.
// Output y[k] = Σ cᵢ xᵢ[k] + d u[k] + offset, xᵢ[k+1] = Aᵢ xᵢ[k] + bᵢ u[k], xᵢ[0] = x0ᵢ.
// A free response (no input) uses c = [1 0] (c = 1): each block is then Aᵢ rᵏ cos(kθ + φ).
#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/Dense>

#include "clearshape/ident/modes.hpp"
#include "clearshape/lti/discretize.hpp"

namespace clearshape::ident::detail {

struct ModalBlock {
  bool complex = true;
  double pole0 = 0.0;  ///< complex: ln r; real: p
  double pole1 = 0.0;  ///< complex: θ in (0, π)
  double c[2] = {1.0, 0.0};
  double x0[2] = {0.0, 0.0};
  std::size_t states() const noexcept { return complex ? 2 : 1; }
};

struct ModalModel {
  std::vector<ModalBlock> blocks;
  double d = 0.0;
  double offset = 0.0;
  bool has_input = true;
};

/// Parameter layout: per block [pole (2|1), c (2|1), x0 (2|1)], then d, offset.
std::size_t parameter_count(const ModalModel& model);
std::size_t block_offset(const ModalModel& model, std::size_t block);
std::vector<double> pack(const ModalModel& model);
void unpack(std::span<const double> values, ModalModel& model);

/// Output (and, if `jacobian` is non-null, ∂y/∂ every parameter; N × P column-major).
/// `input` may be empty for a free response. Returns false on a non-finite output.
bool simulate(const ModalModel& model, std::span<const double> input, std::size_t count, double* output,
              double* jacobian);
/// The output of one block alone (no d, no offset).
std::vector<double> block_output(const ModalModel& model, std::size_t block, std::span<const double> input,
                                 std::size_t count);

/// Real modal form of (A, b, c, d, x0): eigen-decomposition, then each block normalised to
/// b = [0 1]ᵀ (has_input) or c = [1 0] (free response). Throws RuntimeError if A is defective.
ModalModel to_modal(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, const Eigen::RowVectorXd& c, double d,
                    const Eigen::VectorXd& x0, bool has_input);
lti::DiscreteStateSpace to_state_space(const ModalModel& model, double sample_time_s);
Eigen::VectorXd initial_state(const ModalModel& model);

/// Which parameters the refinement may change.
std::vector<bool> free_mask(const ModalModel& model, bool free_c, bool free_x0, bool free_d, bool free_offset);

struct ModalFit {
  ModalModel model;
  Eigen::MatrixXd covariance;  ///< P × P (zero rows/columns for fixed parameters), scaled by σ²
  double cost = 0.0;           ///< ½ Σ e²
  std::size_t iterations = 0;
  bool converged = false;
};

/// Levenberg–Marquardt (Ceres) on the simulation error.
ModalFit refine(const ModalModel& start, std::span<const double> input, std::span<const double> output,
                const std::vector<bool>& free, std::size_t max_iterations);

/// Covariance without refinement (JᵀJ)⁻¹σ² at the given model.
Eigen::MatrixXd covariance_at(const ModalModel& model, std::span<const double> input, std::span<const double> output,
                              const std::vector<bool>& free);

/// ωn, ζ, amplitude (with 1σ from `covariance`) and RMS contribution of a complex block.
ModeEstimate mode_estimate(const ModalModel& model, std::size_t block, const Eigen::MatrixXd& covariance,
                           double sample_time_s, std::span<const double> input, std::size_t count);

}  // namespace clearshape::ident::detail
