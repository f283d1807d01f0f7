#pragma once
// The ident module: process-model fitting (thesis §4.2, Eq. 4.2), cross-validation over input
// types, subspace identification (N4SID/MOESP, ERA), general state-space fits and residual-mode
// identification for shaper design.
#include "clearshape/ident/cross_validation.hpp"
#include "clearshape/ident/experiment.hpp"
#include "clearshape/ident/modes.hpp"
#include "clearshape/ident/process_fit.hpp"
#include "clearshape/ident/state_space_fit.hpp"
#include "clearshape/ident/subspace.hpp"
