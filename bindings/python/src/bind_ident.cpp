// Python: identification — a MATLAB-style process model from input/output records
// (ident/process_fit.hpp, as `clearshape identify`) and the dominant vibration modes of a free
// response or an input/output record (ident/modes.hpp, as `clearshape modes`).
#include <optional>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "arrays.hpp"
#include "clearshape/ident/experiment.hpp"
#include "clearshape/ident/modes.hpp"
#include "clearshape/ident/process_fit.hpp"
#include "clearshape/lti/process_model.hpp"

namespace clearshape::python {
namespace {

namespace id = clearshape::ident;

py::dict identify(const DoubleArray& input, const DoubleArray& output, double sample_time_s, const std::string& model,
                  const std::string& initial_state, bool output_offset, std::size_t starts,
                  const std::map<std::string, double>& fix) {
  const lti::ProcessStructure structure = lti::ProcessStructure::parse(model);
  const auto e = id::make_experiment("python", to_series(input, sample_time_s, 0.0, "input"),
                                     to_series(output, sample_time_s, 0.0, "output"));
  id::ProcessFitOptions options;
  if (initial_state == "zero") options.initial_state = id::InitialState::zero;
  else if (initial_state == "estimate") options.initial_state = id::InitialState::estimate;
  else if (initial_state == "auto") options.initial_state = id::InitialState::automatic;
  else throw InvalidArgument("initial_state = " + initial_state + " is not known; allowed: zero, estimate, auto");
  options.estimate_output_offset = output_offset;
  options.starts = starts;
  for (const auto& [name, value] : fix) options.parameters[name].fixed = value;
  id::ProcessEstimate est;
  {
    py::gil_scoped_release release;
    est = id::estimate_process_model(structure, std::span<const id::Experiment>(&e, 1), options);
  }
  py::dict parameters, std_devs;
  for (const auto& p : est.parameters) {
    parameters[py::str(p.name)] = p.value;
    std_devs[py::str(p.name)] = p.std_dev;
  }
  py::dict d;
  d["model"] = structure.code();
  d["parameters"] = parameters;
  d["std_dev"] = std_devs;
  d["fit_percent"] = est.fit_percent();
  d["loss"] = est.loss;
  d["aic"] = est.aic;
  d["converged"] = est.converged;
  d["natural_frequency_rad_s"] = est.natural_frequency_rad_s() ? py::cast(*est.natural_frequency_rad_s()) : py::none();
  d["damping_ratio"] = est.damping_ratio() ? py::cast(*est.damping_ratio()) : py::none();
  return d;
}

py::dict modes_result(const id::ModeIdentification& r) {
  py::list modes;
  for (const auto& mo : r.modes) {
    py::dict d;
    d["natural_frequency_hz"] = mo.natural_frequency_hz();
    d["natural_frequency_std_hz"] = mo.natural_frequency_std_hz();
    d["damped_frequency_hz"] = mo.damped_frequency_hz();
    d["damping_ratio"] = mo.damping_ratio;
    d["damping_ratio_std"] = mo.damping_ratio_std;
    d["amplitude"] = mo.amplitude;
    d["rms_contribution"] = mo.rms_contribution;
    modes.append(d);
  }
  py::dict d;
  d["modes"] = modes;
  d["fit_percent"] = r.fit_percent;
  d["rmse"] = r.rmse;
  d["fitted"] = to_array(r.fitted.values);
  d["method"] = r.method;
  d["decimation"] = r.decimation;
  return d;
}

py::dict modes(const DoubleArray& output, double sample_time_s, std::optional<DoubleArray> input,
               std::size_t count, std::size_t order, bool refine, bool estimate_offset, double max_damping_ratio) {
  id::ModeOptions o;
  o.modes = count;
  o.order = order;
  o.refine = refine;
  o.estimate_offset = estimate_offset;
  o.max_damping_ratio = max_damping_ratio;
  const UniformSeries y = to_series(output, sample_time_s, 0.0, "output");
  id::ModeIdentification r;
  if (input) {
    const auto e = id::make_experiment("python", to_series(*input, sample_time_s, 0.0, "input"), y);
    py::gil_scoped_release release;
    r = id::identify_modes(e, o);
  } else {
    py::gil_scoped_release release;
    r = id::identify_free_response_modes(y, o);
  }
  return modes_result(r);
}

}  // namespace

void bind_ident(py::module_& m) {
  m.def("identify", &identify, py::arg("input"), py::arg("output"), py::arg("sample_time_s"),
        py::arg("model") = "P3UZ", py::arg("initial_state") = "auto", py::arg("output_offset") = false,
        py::arg("starts") = 3, py::arg("fix") = std::map<std::string, double>{},
        R"doc(Fits a MATLAB-style process model (thesis §4.2; structure code such as 'P3UZ', 'P2U',
'P1D') to one input/output record sampled every sample_time_s (s), as `clearshape identify`.
fix: {'Td': 0.0, …} holds parameters. Returns a dict: model, parameters and std_dev by MATLAB
name (Kp in output units per input unit, time constants s), fit_percent (NRMSE %), loss, aic,
converged, natural_frequency_rad_s and damping_ratio of the underdamped pair (or None).)doc");
  m.def("modes", &modes, py::arg("output"), py::arg("sample_time_s"), py::arg("input") = py::none(),
        py::arg("count") = 1, py::arg("order") = 0, py::arg("refine") = true, py::arg("estimate_offset") = true,
        py::arg("max_damping_ratio") = 0.7,
        R"doc(The dominant lightly damped vibration modes (subspace identification + least-squares
refinement), as `clearshape modes`: of a free response `output`, or of an input/output record
when `input` is given; sampled every sample_time_s (s). Returns a dict: modes (list of
natural_frequency_hz, damped_frequency_hz, damping_ratio, their 1σ, amplitude, rms_contribution), fit_percent,
rmse, fitted (array), method, decimation.)doc");
}

}  // namespace clearshape::python
