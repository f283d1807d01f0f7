// The extension clearshape._core: the library's C++ API for Python (docs/python.md). Errors map
// as in the CLI: a bad parameter or bad input (InvalidArgument, InputError) raises ValueError
// with the C++ message, a failure while computing (RuntimeError) raises RuntimeError.
#include <cstdlib>
#include <string>

#include <glog/logging.h>
#include <pybind11/pybind11.h>

#include "arrays.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/core/version.hpp"

namespace py = pybind11;

namespace {

// Ceres logs through glog; as in the CLI its messages are internal detail, shown only when
// CLEARSHAPE_VERBOSE=1 is set.
void route_library_logging() {
  const char* env = std::getenv("CLEARSHAPE_VERBOSE");
  const bool verbose = env != nullptr && std::string(env) == "1";
  FLAGS_logtostderr = true;
  FLAGS_minloglevel = verbose ? google::GLOG_INFO : google::GLOG_FATAL;
  FLAGS_stderrthreshold = verbose ? google::GLOG_INFO : google::GLOG_FATAL;
  if (!google::IsGoogleLoggingInitialized()) google::InitGoogleLogging("clearshape");
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "clearshape: input shaping for servo-driven joints with clearance (C++ core).";
  m.attr("__version__") = clearshape::kVersion;
  route_library_logging();
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const clearshape::InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
  clearshape::python::bind_signal(m);
  clearshape::python::bind_shaping(m);
  clearshape::python::bind_simulation(m);
  clearshape::python::bind_ident(m);
  clearshape::python::bind_metrics(m);
  clearshape::python::bind_study(m);
  clearshape::python::bind_export(m);
  clearshape::python::bind_arm(m);
}
