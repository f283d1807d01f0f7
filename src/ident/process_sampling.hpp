#pragma once
// Internal: the sampled process model and its exact derivatives with respect to every parameter
// of the structure (parameter_names() order), for the simulation-error fit.
//
// Realization: the cascade of lti::ProcessModel::state_space() (integrator, first-order
// sections, the U pair last; gain and zero in the last section), written for any scalar so that
// Ceres Jets give the exact ∂(A, B, C, D)/∂θ.
// Sampling: x[k] = Φ x[k−1] + Σⱼ Gⱼ u[k−d−j], y[k] = C x[k] + Σⱼ Hⱼ u[k−d−j] (j = 0, 1, 2), with
// Td = (d + f)T split into a piece of length fT and one of (1 − f)T, as lti::SampledModel.
// Piece integrals from expm of the generator [A b 0; 0 0 1; 0 0 0]·h (Van Loan 1978); their
// parameter derivatives from expm([[M, dM], [0, M]]) (Van Loan 1978, Thm. 1), their derivative in
// h from d/dh e^(Gh) = G e^(Gh); ∂/∂Td = (1/T) ∂/∂f.
#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/Dense>

#include "clearshape/lti/discretize.hpp"
#include "clearshape/lti/process_model.hpp"

namespace clearshape::ident::detail {

struct Sampled {
  Eigen::Index n = 0;
  std::size_t delay_samples = 0;
  double fraction = 0.0;
  Eigen::MatrixXd phi;   ///< n×n
  Eigen::MatrixXd taps;  ///< n×3 (G0 G1 G2)
  Eigen::RowVectorXd c;  ///< 1×n
  Eigen::Vector3d h = Eigen::Vector3d::Zero();
  // One entry per structure parameter when derivatives were asked for.
  std::vector<Eigen::MatrixXd> dphi;
  std::vector<Eigen::MatrixXd> dtaps;
  std::vector<Eigen::RowVectorXd> dc;
  std::vector<Eigen::Vector3d> dh;
};

/// Continuous realization (A, B, C, D) of the structure at `values` (parameter_names() order);
/// every time constant of the structure must be > 0.
struct Realization {
  Eigen::MatrixXd a, b, c, d;
  std::vector<Eigen::MatrixXd> da, db, dc, dd;  ///< per parameter, when asked for
};
Realization realize(const lti::ProcessStructure& structure, std::span<const double> values,
                    bool derivatives);

/// Sampled model at `values`; derivatives for all parameters when `derivatives`.
Sampled sample(const lti::ProcessStructure& structure, std::span<const double> values,
               double sample_time_s, lti::Hold hold, bool derivatives);

/// Input of the sensitivity simulation. Columns of `jacobian` (N rows, ROW-major), in order:
/// one per entry of `directions` (∂ŷ/∂ parameter directions[i], times scale[i]), then n for x0 if
/// d_x0, one for u0 if d_u0, one for y0 if d_y0.
struct KernelInput {
  const Sampled* model = nullptr;
  std::span<const double> input;  ///< plant input u − u0; history before the start is 0
  std::span<const double> x0;     ///< size n (empty = 0)
  double y0 = 0.0;
  std::span<const int> directions;
  std::span<const double> scale;
  bool d_x0 = false;
  bool d_u0 = false;
  bool d_y0 = false;
};
std::size_t jacobian_columns(const KernelInput& in);

/// Runs the simulation (and its sensitivities when `jacobian` is non-null: row k holds the
/// jacobian_columns() derivatives of ŷ[k]). Writes ŷ into `output`. Returns false if a value
/// became non-finite.
bool simulate(const KernelInput& in, double* output, double* jacobian);

}  // namespace clearshape::ident::detail
