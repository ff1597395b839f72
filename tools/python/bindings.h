#pragma once
// Shared pieces of the Python bindings (tools/python/README.md): numpy
// arrays of points in and out.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "sampler/point.h"

namespace nuld::python {

namespace py = pybind11;

// Any array convertible to float64, C order.
using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

// Points as an array: (N, 2) when `instances` is 0, else (instances, N, 2).
// (Points in: args.h, points.)
DoubleArray arrayOf(const std::vector<Point2> &points, std::size_t n, std::size_t instances);

void bindPoints(py::module_ &m);
void bindRender(py::module_ &m);
void bindStudy(py::module_ &m);  // the studies' statistics

}  // namespace nuld::python
