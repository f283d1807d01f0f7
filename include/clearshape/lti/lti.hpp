#pragma once
// The lti module: transfer functions, process models (thesis Eq. 4.2), state space, exact
// discretization and simulation.
#include "clearshape/lti/discretize.hpp"
#include "clearshape/lti/modes.hpp"
#include "clearshape/lti/polynomial.hpp"
#include "clearshape/lti/process_model.hpp"
#include "clearshape/lti/simulate.hpp"
#include "clearshape/lti/state_space.hpp"
#include "clearshape/lti/transfer_function.hpp"
