// Python: the thesis's figures of merit — repeatability Eq. 4.1 (metrics/consistency.hpp),
// residual vibration level Eq. 5.1 (metrics/mean_deviation.hpp), improvement %, and the delay a
// shaper adds (metrics/residual.hpp).
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "arrays.hpp"
#include "clearshape/metrics/consistency.hpp"
#include "clearshape/metrics/improvement.hpp"
#include "clearshape/metrics/mean_deviation.hpp"
#include "clearshape/metrics/residual.hpp"

namespace clearshape::python {
namespace {

namespace mt = clearshape::metrics;

py::dict consistency(const DoubleArray& runs) {
  if (runs.ndim() != 2) throw InvalidArgument("runs must be a two-dimensional array (one run per row)");
  std::vector<std::vector<double>> rows(static_cast<std::size_t>(runs.shape(0)));
  const double* p = runs.data();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    rows[i].assign(p + i * runs.shape(1), p + (i + 1) * runs.shape(1));
  }
  const auto r = mt::consistency_errors(rows);
  py::dict d;
  d["errors"] = to_array(r.errors);
  d["mean_error"] = r.mean_error;
  d["mean_signal"] = to_array(r.mean_signal);
  d["range"] = r.range;
  return d;
}

py::dict mean_deviation(const DoubleArray& response, double sample_time_s, double start_s,
                        double final_window_fraction, double search_from_s, double band_move_fraction,
                        double band_noise_multiple, double band_dwell_s, double band_half_width) {
  mt::MeanDeviationOptions o;
  o.final_window_fraction = final_window_fraction;
  o.search_from_s = search_from_s;
  o.band_move_fraction = band_move_fraction;
  o.band_noise_multiple = band_noise_multiple;
  o.band_dwell_s = band_dwell_s;
  o.band_half_width = band_half_width;
  const auto r = mt::mean_deviation(to_series(response, sample_time_s, start_s, "response"), o);
  py::dict d;
  d["mean_deviation"] = r.mean_deviation;
  d["steady_mean"] = r.steady_mean;
  d["start_index"] = r.start_index;
  d["start_time_s"] = r.start_time_s;
  d["samples"] = r.samples;
  d["converged"] = r.converged;
  d["start_rule"] = std::string(mt::to_string(r.start_rule));
  d["band_half_width"] = r.band_half_width;
  return d;
}

}  // namespace

void bind_metrics(py::module_& m) {
  m.def("consistency", &consistency, py::arg("runs"),
        R"doc(Repeatability of repeated runs, thesis Eq. 4.1: E_i = sqrt(Σ_j (m_j − t_ij)² / n) / r with
m the mean run and r its range. runs: 2-D array, one run per row on the same grid. Returns a
dict: errors (E_i, dimensionless), mean_error, mean_signal, range (units of the runs).)doc");
  m.def("mean_deviation", &mean_deviation, py::arg("response"), py::arg("sample_time_s"), py::arg("start_s") = 0.0,
        py::arg("final_window_fraction") = 0.2, py::arg("search_from_s") = -std::numeric_limits<double>::infinity(),
        py::arg("band_move_fraction") = 0.005, py::arg("band_noise_multiple") = 0.0, py::arg("band_dwell_s") = 0.1,
        py::arg("band_half_width") = std::numeric_limits<double>::quiet_NaN(),
        R"doc(Residual-vibration level MD of a response, thesis Eq. 5.1: sqrt(Σ_{i≥k} (M − s_i)² / n)
from the first point k where the response meets its steady mean M (metrics/mean_deviation.hpp
documents the rule). response sampled every sample_time_s (s) from start_s. Returns a dict:
mean_deviation (units of the response), steady_mean, start_index, start_time_s, samples,
converged, start_rule, band_half_width.)doc");
  m.def("improvement_percent", &mt::improvement_percent, py::arg("without"), py::arg("with_"),
        "Improvement by shaping (thesis §5.1.2): (without − with) / without · 100 (%).");
  m.def("shaping_delay_s", [](const DoubleArray& unshaped, const DoubleArray& shaped, double sample_time_s,
                              double fraction, double initial) {
    return mt::shaping_delay_s(to_series(unshaped, sample_time_s, 0.0, "unshaped"),
                               to_series(shaped, sample_time_s, 0.0, "shaped"), fraction, initial);
  }, py::arg("unshaped"), py::arg("shaped"), py::arg("sample_time_s"), py::arg("fraction") = 0.5,
        py::arg("initial") = 0.0,
        "Delay added by shaping (s): when the shaped response reaches `fraction` of the unshaped final value minus when the unshaped one does (NaN if never).");
}

}  // namespace clearshape::python
