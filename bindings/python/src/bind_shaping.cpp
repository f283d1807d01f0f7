// Python: shaper design (shaping/design.hpp, every method), residual vibration and sensitivity
// (Eq. 2.19, shaping/residual.hpp), offline and streaming shaping (apply.hpp, streaming.hpp).
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <pybind11/stl.h>

#include "arrays.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/shaping/apply.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/shaping/residual.hpp"
#include "clearshape/shaping/streaming.hpp"

namespace clearshape::python {
namespace {

namespace sh = clearshape::shaping;

// The mode from Hz or rad/s, exactly one of them (the CLI's --frequency-hz | --wn).
sh::Mode mode_of(std::optional<double> frequency_hz, std::optional<double> wn_rad_s, double zeta) {
  if (frequency_hz.has_value() == wn_rad_s.has_value()) {
    throw InvalidArgument("give exactly one of frequency_hz (Hz) and wn_rad_s (rad/s)");
  }
  if (frequency_hz) {
    require_positive("frequency_hz", *frequency_hz);
    return sh::Mode::from_hz(*frequency_hz, zeta);
  }
  require_positive("wn_rad_s", *wn_rad_s);
  return sh::Mode{*wn_rad_s, zeta};
}

sh::Shaper design(const std::string& method, std::optional<double> frequency_hz, std::optional<double> wn_rad_s,
                  double zeta, double vtol, std::optional<double> band_low_hz, std::optional<double> band_high_hz,
                  int si_impulses, int si_points, std::optional<std::vector<std::pair<double, double>>> impulses,
                  std::optional<double> second_frequency_hz, std::optional<double> second_zeta) {
  sh::DesignRequest r;
  r.method = sh::method_from_string(method);
  r.vtol = vtol;
  if (r.method == sh::Method::custom) {
    if (!impulses) throw InvalidArgument("method custom needs impulses=[(t_s, amplitude), …]");
    for (const auto& [t, a] : *impulses) r.impulses.push_back({t, a});
    if (frequency_hz || wn_rad_s) r.mode = mode_of(frequency_hz, wn_rad_s, zeta);
  } else {
    if (impulses) throw InvalidArgument("impulses are for method custom only");
    r.mode = mode_of(frequency_hz, wn_rad_s, zeta);
  }
  if (r.method == sh::Method::si) {
    if (!band_low_hz || !band_high_hz) throw InvalidArgument("method si needs band_low_hz and band_high_hz");
    require_positive("band_low_hz", *band_low_hz);
    require_positive("band_high_hz", *band_high_hz);
    sh::SiOptions si;
    si.frequency_low_rad_s = hz_to_rad_s(*band_low_hz);
    si.frequency_high_rad_s = hz_to_rad_s(*band_high_hz);
    si.vtol = vtol;
    si.impulses = si_impulses;
    si.constraint_points = si_points;
    r.si = si;
  } else if (band_low_hz || band_high_hz) {
    throw InvalidArgument("band_low_hz and band_high_hz are for method si only");
  }
  if (second_frequency_hz.has_value() != second_zeta.has_value()) {
    throw InvalidArgument("a second mode needs both second_frequency_hz and second_zeta");
  }
  if (second_frequency_hz) {
    require_positive("second_frequency_hz", *second_frequency_hz);
    r.second_mode = sh::Mode::from_hz(*second_frequency_hz, *second_zeta);
  }
  return sh::design(r);
}

sh::Mode actual_mode(double frequency_hz, double zeta) {
  require_positive("frequency_hz", frequency_hz);
  return sh::Mode::from_hz(frequency_hz, zeta);
}

// Samples to shape: real and finite, else ValueError naming the first bad one (NumPy would drop
// an imaginary part silently, and a NaN would spread through every tap it reaches).
std::vector<double> shaping_input(const py::object& samples) {
  const py::array values = py::array::ensure(samples);
  if (!values) throw InvalidArgument("values must be an array of numbers");
  if (values.dtype().kind() == 'c') {
    throw InvalidArgument("values are complex; shaping takes real samples (pass values.real, or shape real and imaginary parts apart)");
  }
  std::vector<double> v = to_vector(DoubleArray::ensure(values), "values");
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v[i])) {
      throw InvalidArgument(fmt::format("values[{}] = {} is not finite; shaping takes finite samples (StreamingShaper.step "
                                        "holds the previous one instead, as the real-time path does)", i, v[i]));
    }
  }
  return v;
}

// One sample for StreamingShaper.step: a real number (a NaN is the C++ step's to hold); a complex
// one (also NumPy's complex64/complex128, which float() would truncate) is refused.
double step_input(const py::handle& value) {
  if (PyFloat_Check(value.ptr()) || PyLong_Check(value.ptr())) return value.cast<double>();
  if (PyComplex_Check(value.ptr()) || py::module_::import("numpy").attr("iscomplexobj")(value).cast<bool>()) {
    throw InvalidArgument("value = " + py::str(value).cast<std::string>() +
                          " is complex; step takes a real sample (pass value.real)");
  }
  const double x = PyFloat_AsDouble(value.ptr());  // float(value), without NumPy's truncating warning path
  if (x == -1.0 && PyErr_Occurred()) {
    PyErr_Clear();
    throw py::type_error("value must be a real number, got " + py::str(py::type::of(value).attr("__name__")).cast<std::string>());
  }
  return x;
}

py::array_t<double> shape(const sh::Shaper& shaper, const py::object& values, double sample_time_s, bool extend,
                          const std::string& discretization, std::optional<double> frequency_hz,
                          std::optional<double> zeta) {
  require_positive("sample_time_s", sample_time_s);
  const UniformSeries input{0.0, sample_time_s, shaping_input(values)};
  if (discretization == "linear") {
    if (frequency_hz || zeta) throw InvalidArgument("frequency_hz and zeta are for discretization 'exact' only");
    return to_array(sh::shape_offline(shaper, input, extend).values);
  }
  if (discretization != "exact") {
    throw InvalidArgument("discretization = " + discretization + " is not known; allowed: linear, exact");
  }
  if (!frequency_hz || !zeta) throw InvalidArgument("discretization 'exact' needs frequency_hz and zeta (the mode)");
  const auto taps = sh::discretize(shaper, sample_time_s, sh::Discretization::exact_at_mode,
                                   actual_mode(*frequency_hz, *zeta));
  return to_array(sh::shape_offline(taps, input, extend).values);
}

// The impulse times (s) or amplitudes of a shaper as an array.
py::array_t<double> impulse_field(const sh::Shaper& s, double sh::Impulse::*field) {
  std::vector<double> values;
  for (const auto& i : s.impulses()) values.push_back(i.*field);
  return to_array(values);
}

// (ratios, V) of the sensitivity curve; actual_zeta, when given, differs from the design's.
py::tuple sensitivity(const sh::Shaper& s, double frequency_hz, double zeta, double ratio_from, double ratio_to,
                      std::size_t points, std::optional<double> actual_zeta) {
  const sh::Mode design_mode = actual_mode(frequency_hz, zeta);
  const auto curve = actual_zeta
      ? sh::sensitivity_curve(s, design_mode, *actual_zeta, ratio_from, ratio_to, points)
      : sh::sensitivity_curve(s, design_mode, ratio_from, ratio_to, points);
  std::vector<double> r, v;
  for (const auto& p : curve) {
    r.push_back(p.frequency_ratio);
    v.push_back(p.residual);
  }
  return py::make_tuple(to_array(r), to_array(v));
}

bool shapers_equal(const sh::Shaper& a, const sh::Shaper& b) {
  return a.method() == b.method() && std::ranges::equal(a.impulses(), b.impulses());
}

// (method, ((time_s, amplitude), …)): the state a Shaper pickles to, and its hash.
py::tuple shaper_state(const sh::Shaper& s) {
  py::list impulses;
  for (const auto& i : s.impulses()) impulses.append(py::make_tuple(i.time_s, i.amplitude));
  return py::make_tuple(s.method(), py::tuple(impulses));
}

sh::Shaper shaper_from_state(const py::tuple& state) {
  if (state.size() != 2) throw InvalidArgument("Shaper state: expected (method, impulses)");
  std::vector<sh::Impulse> list;
  for (const auto& i : state[1]) {
    const auto pair = py::cast<std::pair<double, double>>(i);
    list.push_back({pair.first, pair.second});
  }
  // As stored: the amplitudes were normalised (or not) when the shaper was made.
  return sh::Shaper(py::cast<std::string>(state[0]), list, sh::Shaper::Normalize::no);
}

// shaper_methods() and the class Shaper.
void bind_shaper(py::module_& m) {
  m.def("shaper_methods", [] {
    std::vector<std::string> names;
    for (auto n : sh::method_names()) names.emplace_back(n);
    return names;
  }, "The shaper method names: zv, zvd, zvdd, zvddd, mzv, ei, ei2, ei3, si, um-zv, custom.");

  py::class_<sh::Shaper>(m, "Shaper", "An input shaper: impulses (time in s, amplitude), t1 = 0, ΣA = 1 (Eq. 2.21).")
      .def(py::init([](const std::string& method, const std::vector<std::pair<double, double>>& impulses,
                       bool normalize) {
             std::vector<sh::Impulse> list;
             for (const auto& [t, a] : impulses) list.push_back({t, a});
             return sh::Shaper(method, list, normalize ? sh::Shaper::Normalize::yes : sh::Shaper::Normalize::no);
           }),
           py::arg("method"), py::arg("impulses"), py::arg("normalize") = true,
           "A shaper from [(time_s, amplitude), …]; times >= 0, strictly increasing.")
      .def_property_readonly("method", &sh::Shaper::method, "Method name (zv, zvd, …; 'a*b' for two modes).")
      .def_property_readonly("times_s", [](const sh::Shaper& s) { return impulse_field(s, &sh::Impulse::time_s); },
                             "Impulse times (s).")
      .def_property_readonly("amplitudes", [](const sh::Shaper& s) { return impulse_field(s, &sh::Impulse::amplitude); },
                             "Impulse amplitudes (dimensionless, sum 1).")
      .def_property_readonly("duration_s", &sh::Shaper::duration_s, "Time of the last impulse: the delay the shaper adds (s).")
      .def_property_readonly("is_positive", &sh::Shaper::is_positive, "True when no amplitude is negative.")
      .def("__len__", &sh::Shaper::size)
      // A value (docs/design.md §3): equal when the method and every impulse are equal.
      .def("__eq__", [](const sh::Shaper& a, const sh::Shaper& b) { return shapers_equal(a, b); }, py::is_operator())
      .def("__hash__", [](const sh::Shaper& s) { return py::hash(shaper_state(s)); })
      .def(py::pickle([](const sh::Shaper& s) { return shaper_state(s); }, &shaper_from_state))
      .def("__repr__", [](const sh::Shaper& s) {
        return "<clearshape.Shaper " + s.method() + ", " + std::to_string(s.size()) + " impulses, " +
               std::to_string(s.duration_s()) + " s>";
      });
}

// design(): every method of shaping/design.hpp.
void bind_design(py::module_& m) {
  m.def("design", &design, py::arg("method"), py::kw_only(), py::arg("frequency_hz") = py::none(),
        py::arg("wn_rad_s") = py::none(), py::arg("zeta") = 0.0, py::arg("vtol") = 0.05,
        py::arg("band_low_hz") = py::none(), py::arg("band_high_hz") = py::none(), py::arg("si_impulses") = 0,
        py::arg("si_points") = 60, py::arg("impulses") = py::none(), py::arg("second_frequency_hz") = py::none(),
        py::arg("second_zeta") = py::none(),
        R"doc(Designs an input shaper for a mode (as `clearshape shape`).

method: zv, zvd, zvdd, zvddd (Eq. 2.22–2.26), mzv, ei, ei2, ei3, si, um-zv or custom.
frequency_hz (Hz) or wn_rad_s (rad/s): the mode's natural frequency; zeta: its damping ratio
in [0, 1). vtol: tolerated residual vibration for ei/ei2/ei3/si (0–1). si also needs
band_low_hz, band_high_hz (and optionally si_impulses, si_points). custom takes
impulses=[(t_s, amplitude), …]. second_frequency_hz/second_zeta convolve the same method
designed for a second mode. Raises ValueError with the C++ message on a bad parameter.)doc");
}

// Robustness: residual_vibration (Eq. 2.19), sensitivity, insensitivity (shaping/residual.hpp).
void bind_robustness(py::module_& m) {
  m.def("residual_vibration", [](const sh::Shaper& s, double frequency_hz, double zeta) {
    return sh::residual_vibration(s, actual_mode(frequency_hz, zeta));
  }, py::arg("shaper"), py::arg("frequency_hz"), py::arg("zeta"),
        "Residual vibration V (Eq. 2.19, 0–1, 1 = unshaped) of a mode at frequency_hz (Hz) and damping zeta.");

  m.def("sensitivity", &sensitivity, py::arg("shaper"), py::arg("frequency_hz"), py::arg("zeta"),
        py::arg("ratio_from") = 0.0, py::arg("ratio_to") = 2.0, py::arg("points") = 201,
        py::arg("actual_zeta") = py::none(),
        R"doc(Sensitivity curve: V(r) at `points` frequency ratios r = ω/ωn evenly spaced over
[ratio_from, ratio_to] for the design mode (frequency_hz in Hz, zeta); actual_zeta sets a
different actual damping. Returns (ratios, V), two arrays.)doc");

  m.def("insensitivity", [](const sh::Shaper& s, double frequency_hz, double zeta, double vtol, double hump_tolerance) {
    const auto band = sh::insensitivity(s, actual_mode(frequency_hz, zeta), vtol, hump_tolerance);
    return py::make_tuple(band.ratio_low, band.ratio_high);
  }, py::arg("shaper"), py::arg("frequency_hz"), py::arg("zeta"), py::arg("vtol") = 0.05,
        py::arg("hump_tolerance") = 0.0,
        "The band of frequency ratios (r_low, r_high) around 1 where V <= vtol; its width is the insensitivity.");
}

// shape(): offline shaping of a whole array (shaping/apply.hpp).
void bind_offline_shaping(py::module_& m) {
  m.def("shape", &shape, py::arg("shaper"), py::arg("values"), py::arg("sample_time_s"), py::arg("extend") = true,
        py::arg("discretization") = "linear", py::arg("frequency_hz") = py::none(), py::arg("zeta") = py::none(),
        R"doc(Shapes a command sampled every sample_time_s (s) offline: y(t) = Σ Aᵢ u(t − tᵢ), the input
linear between samples and held at its first value before the start. extend: the output is
longer by the shaper's duration (input held at its last value). discretization 'exact'
(Murphy & Watanabe) keeps V at the mode frequency_hz/zeta on the sample grid. Returns an array
in the input's units.)doc");
}

// The class StreamingShaper (shaping/streaming.hpp).
void bind_streaming_shaper(py::module_& m) {
  py::class_<sh::StreamingShaper>(m, "StreamingShaper",
                                  "Real-time shaping one sample at a time (equals shape() to rounding).")
      .def(py::init<const sh::Shaper&, double, double>(), py::arg("shaper"), py::arg("sample_time_s"),
           py::arg("initial_value") = 0.0,
           "A streaming shaper at sample_time_s (s); the history starts at initial_value.")
      .def("step", [](sh::StreamingShaper& s, const py::handle& value) { return s.step(step_input(value)); },
           py::arg("value"),
           "Pushes one input sample and returns the shaped output. A non-finite input is held as the real-time path "
           "holds it (shaping/streaming.hpp): the previous input takes its place, so the output stays finite.")
      .def("process", [](sh::StreamingShaper& s, const py::object& values) {
        std::vector<double> in = shaping_input(values);  // checked before any step: a refusal leaves the history as it was
        for (double& v : in) v = s.step(v);
        return to_array(in);
      }, py::arg("values"), "Steps every sample of an array in order and returns the outputs; as shape(), ValueError for a "
         "non-finite or complex sample (none is stepped).")
      .def("reset", &sh::StreamingShaper::reset, py::arg("value") = 0.0, "Refills the history with value.")
      .def_property_readonly("sample_time_s", &sh::StreamingShaper::sample_time_s)
      .def_property_readonly("tap_count", &sh::StreamingShaper::tap_count);
}

}  // namespace

void bind_shaping(py::module_& m) {
  bind_shaper(m);  // first: the functions below take and return Shaper
  bind_design(m);
  bind_robustness(m);
  bind_offline_shaping(m);
  bind_streaming_shaper(m);
}

}  // namespace clearshape::python
