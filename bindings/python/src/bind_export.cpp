// Python: a shaper in the form a controller loads (export/export.hpp; docs/export.md) — the text
// `clearshape shape --export FORMAT` writes, from the same library call.
#include <optional>
#include <string>
#include <utility>

#include <pybind11/stl.h>

#include "arrays.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/export/export.hpp"
#include "clearshape/shaping/design.hpp"

namespace clearshape::python {
namespace {

namespace ex = clearshape::exports;
namespace sh = clearshape::shaping;

std::optional<sh::Mode> mode_of(std::optional<double> frequency_hz, std::optional<double> zeta, const char* what) {
  if (!frequency_hz && !zeta) return std::nullopt;
  if (!frequency_hz || !zeta) throw InvalidArgument(std::string(what) + ": give both the frequency (Hz) and zeta");
  require_positive(what, *frequency_hz);
  return sh::Mode::from_hz(*frequency_hz, *zeta);
}

sh::Discretization discretization_of(const std::string& name) {
  if (name == "linear") return sh::Discretization::linear;
  if (name == "exact") return sh::Discretization::exact_at_mode;
  throw InvalidArgument("discretization = '" + name + "' is not valid; allowed: linear, exact");
}

py::tuple export_shaper(const sh::Shaper& shaper, const std::string& format, std::optional<double> frequency_hz,
                        std::optional<double> zeta, std::optional<double> second_frequency_hz, std::optional<double> second_zeta,
                        double sample_time_s, const std::string& discretization, const std::string& c_name,
                        const std::string& klipper_axes, std::optional<double> vtol,
                        std::optional<std::pair<double, double>> band_hz, std::optional<double> grid_hz, const std::string& command) {
  const std::string& name = shaper.method();  // a two-mode convolution is 'zv*zv': each factor's method
  ex::ShaperDesign design{shaper, sh::method_from_string(name.substr(0, name.find('*'))), mode_of(frequency_hz, zeta, "frequency_hz"),
                          mode_of(second_frequency_hz, second_zeta, "second_frequency_hz"), vtol, band_hz, command};
  design.update_grid_hz = grid_hz;
  ex::ExportOptions options;
  options.sample_time_s = sample_time_s;
  options.discretization = discretization_of(discretization);
  options.c_name = c_name;
  options.klipper_axes = klipper_axes;
  const ex::ExportText out = ex::export_shaper(design, ex::format_from_string(format), options);
  return py::make_tuple(out.text, out.notes);
}

}  // namespace

void bind_export(py::module_& m) {
  m.def("export_formats", [] {
    std::vector<std::string> names;
    for (const auto n : ex::format_names()) names.emplace_back(n);
    return names;
  }, "The formats export() writes: json, c-header, klipper, rrf (docs/export.md).");
  m.def("export", &export_shaper, py::arg("shaper"), py::arg("format"), py::kw_only(), py::arg("frequency_hz") = py::none(),
        py::arg("zeta") = py::none(), py::arg("second_frequency_hz") = py::none(), py::arg("second_zeta") = py::none(),
        py::arg("sample_time_s") = 0.0, py::arg("discretization") = "linear", py::arg("c_name") = "cs_shaper",
        py::arg("klipper_axes") = "xy", py::arg("vtol") = py::none(), py::arg("band_hz") = py::none(),
        py::arg("grid_hz") = py::none(), py::arg("command") = "clearshape.export (Python)",
        R"doc(A shaper in the form a controller loads, as `clearshape shape --export FORMAT` writes it
(docs/export.md). Returns (text, notes): the file's content and the remarks the CLI prints on
stderr.

format: json or c-header (taps on the controller's grid: sample_time_s > 0, discretization
'linear' or 'exact' at the mode), klipper or rrf (the firmware's own shaper type, compared with
the design). frequency_hz/zeta: the design mode (second_…: a two-mode convolution's second);
vtol and band_hz=(low, high) for EI/SI designs; grid_hz: the shaper is the design on a drive's
update grid of this rate; c_name: the C identifiers' prefix; klipper_axes: x, y or xy; command:
the line written into the file's comments as the way to regenerate it. Raises ValueError when
the target cannot represent the design (the message says what to use instead).)doc");
}

}  // namespace clearshape::python
