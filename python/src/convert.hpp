// Conversions shared by the binding files: numpy columns and lists of text.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstddef>
#include <string>

namespace funnel::py_convert {

namespace py = pybind11;

/// A 1-D numpy array filled from `n` values of `get(i)`.
template <typename T, typename Get>
py::array_t<T> column(std::size_t n, Get get) {
  py::array_t<T> a(static_cast<py::ssize_t>(n));
  auto w = a.template mutable_unchecked<1>();
  for (std::size_t i = 0; i < n; ++i) w(static_cast<py::ssize_t>(i)) = get(i);
  return a;
}

/// A list of str from `n` values of `get(i)` (the Python layer makes it a numpy str array).
template <typename Get>
py::list text_column(std::size_t n, Get get) {
  py::list l;
  for (std::size_t i = 0; i < n; ++i) l.append(std::string(get(i)));
  return l;
}

}  // namespace funnel::py_convert
