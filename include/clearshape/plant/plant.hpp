#pragma once
// The plant module: drive models, contact laws, friction, the clearance joint dynamics
// (SUNDIALS CVODE with root-finding) and sensor models.
#include "clearshape/plant/command.hpp"
#include "clearshape/plant/contact_law.hpp"
#include "clearshape/plant/daq.hpp"
#include "clearshape/plant/drive.hpp"
#include "clearshape/plant/encoder.hpp"
#include "clearshape/plant/friction.hpp"
#include "clearshape/plant/gyroscope.hpp"
#include "clearshape/plant/hertz.hpp"
#include "clearshape/plant/impact.hpp"
#include "clearshape/plant/joint.hpp"
#include "clearshape/plant/simulation.hpp"
