#pragma once
// A RigTruth as a plain Python dict of its fields and back (bit for bit): what it pickles to
// (multiprocessing, Dask) and what its == compares.
#include <pybind11/pybind11.h>

#include "clearshape/rig/truth.hpp"

namespace clearshape::python {

pybind11::dict truth_state(const rig::RigTruth& truth);
/// The run-to-run variation σs by name (RigTruth.variation).
pybind11::dict variation_state(const rig::RunVariation& variation);
/// Throws InvalidArgument naming a missing or out-of-range field.
rig::RigTruth truth_from_state(const pybind11::dict& state);

}  // namespace clearshape::python
