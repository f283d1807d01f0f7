#pragma once
// NumPy <-> std::vector conversions shared by the binding files (copies: the C++ API owns its
// data, NumPy owns its arrays).
#include <cstddef>
#include <string_view>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/series.hpp"

namespace clearshape::python {

namespace py = pybind11;
using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// A 1-D array (or anything NumPy converts to one) as a vector; `name` is used in the error.
inline std::vector<double> to_vector(const DoubleArray& a, std::string_view name) {
  if (a.ndim() != 1) {
    throw InvalidArgument(std::string(name) + " must be a one-dimensional array (got " +
                          std::to_string(a.ndim()) + " dimensions)");
  }
  const double* p = a.data();
  return std::vector<double>(p, p + a.shape(0));
}

/// A copy of `v` as a NumPy array.
template <class T>
py::array_t<T> to_array(const std::vector<T>& v) {
  py::array_t<T> out(static_cast<py::ssize_t>(v.size()));
  T* p = out.mutable_data();
  for (std::size_t i = 0; i < v.size(); ++i) p[i] = v[i];
  return out;
}

/// A uniform series from an array of samples.
inline UniformSeries to_series(const DoubleArray& a, double sample_time_s, double start_s,
                               std::string_view name) {
  require_positive("sample_time_s", sample_time_s);
  require_finite("start_s", start_s);
  return UniformSeries{start_s, sample_time_s, to_vector(a, name)};
}

void bind_signal(py::module_& m);
void bind_shaping(py::module_& m);
void bind_simulation(py::module_& m);
void bind_ident(py::module_& m);
void bind_metrics(py::module_& m);
void bind_study(py::module_& m);
void bind_export(py::module_& m);
void bind_arm(py::module_& m);

}  // namespace clearshape::python
