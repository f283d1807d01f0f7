#pragma once
// Subspace identification with Eigen's SVD:
//  * Input/output data: the block Hankel matrices of past and future inputs and outputs give
//    the extended observability matrix Γᵢ — by the PO-MOESP projection (Verhaegen 1994,
//    "Identification of the deterministic part of MIMO state space models given in innovations
//    form from input-output data", Automatica 30(1)) or the N4SID oblique projection (Van
//    Overschee & De Moor 1994, Automatica 30(1)); C is its first row and A follows from its
//    shift invariance; B, D and x0 then follow by linear least squares on the SIMULATED output
//    (they enter it linearly) — the "combined" scheme of SLICOT IB01/Octave n4sid.
//  * ERA / Ho–Kalman (Ho & Kalman 1966; Juang & Pappa 1985) on a free (or impulse) response
//    y[k] = C Aᵏ x0: SVD of the Hankel matrix of y, balanced factors → A, C, x0.
#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/Dense>

#include "clearshape/ident/experiment.hpp"
#include "clearshape/lti/discretize.hpp"
#include "clearshape/lti/state_space.hpp"

namespace clearshape::ident {

enum class SubspaceMethod {
  moesp,  ///< PO-MOESP projection (Verhaegen 1994), robust to coloured noise — the default
  n4sid,  ///< unweighted N4SID oblique projection (Van Overschee & De Moor 1994)
};

struct SubspaceOptions {
  SubspaceMethod method = SubspaceMethod::moesp;
  std::size_t block_rows = 0;           ///< past/future horizon i; 0 = max(2·order, 10), data permitting
  bool feedthrough = true;              ///< estimate D (else D = 0)
  bool estimate_initial_state = true;   ///< x0 in the B, D least squares (else x0 = 0)
};

struct SubspaceModel {
  lti::DiscreteStateSpace model;        ///< at the experiment's sample time, Hold::zoh
  Eigen::VectorXd initial_state;
  std::vector<double> singular_values;  ///< of the oblique projection (order selection)
};

/// SISO subspace identification of the given order (named after the family; method in options). Throws InvalidArgument if order < 1 or the record is too
/// short for the horizon (needs N ≥ 2i + 2·order + 10), RuntimeError on a rank-deficient result.
SubspaceModel n4sid(const Experiment& experiment, std::size_t order, const SubspaceOptions& options = {});

/// n4sid at every order in [min_order, max_order] from one projection (horizon set by max_order
/// or options.block_rows): the models of a stabilisation diagram. An order the data do not support
/// gives an empty model (a of size 0).
std::vector<SubspaceModel> n4sid_orders(const Experiment& experiment, std::size_t min_order, std::size_t max_order,
                                        const SubspaceOptions& options = {});

struct FreeResponseModel {
  Eigen::MatrixXd a;     ///< order × order
  Eigen::RowVectorXd c;  ///< 1 × order
  Eigen::VectorXd x0;    ///< order
  std::vector<double> singular_values;  ///< of the Hankel matrix
};

/// ERA of a free response y[0..N): Hankel with `rows` rows (0 = min(N/3, max(4·order, 40))).
/// The order is capped at the Hankel matrix's numerical rank (singular values > 1e-10·σ₁), so
/// an exact response of fewer modes gives a smaller model. Throws InvalidArgument if the record
/// is shorter than 2·rows or order ≥ rows, RuntimeError if the response is zero.
FreeResponseModel era(std::span<const double> response, std::size_t order, std::size_t rows = 0);

/// era at every order in [min_order, max_order] from one SVD of the Hankel matrix (rows as era's for
/// max_order): the models of a stabilisation diagram. Same errors as era(max_order).
std::vector<FreeResponseModel> era_orders(std::span<const double> response, std::size_t min_order, std::size_t max_order,
                                          std::size_t rows = 0);

}  // namespace clearshape::ident
