#pragma once
// numpy arrays in and out of the library's types. Inputs take any float or integer dtype and any
// memory order (numpy converts what is not already double or a machine integer); shapes, finite
// values and index ranges are checked, and a problem raises harmonia.errors.InvalidInputError (a
// ValueError) that names the argument and what it got. Outputs are new arrays that own their
// memory (C order).

#include <string>

#include <Eigen/Core>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "harmonia/mesh.h"

namespace harmonia::python {

namespace py = pybind11;

//! `values` as a #rows by `columns` matrix of doubles (any real dtype; integers are taken as
//! their values). `name` is the argument's name in messages. Refuses another shape, complex or
//! non-numeric dtypes and values that are not finite.
[[nodiscard]] Eigen::MatrixXd real_matrix(const py::handle& values, const std::string& name, int columns);

//! `values` as a #rows by `columns` matrix of indices into `count` items (any integer dtype,
//! signed or not). Refuses floats, another shape and indices outside 0..count-1 (naming the row,
//! column and value).
[[nodiscard]] Eigen::MatrixXi index_matrix(const py::handle& values, const std::string& name, int columns,
                                           long long count, const std::string& item = "vertex");

//! The mesh of `positions` (#V x 3) and `faces` (#F x 3); refuses a mesh without faces.
[[nodiscard]] Mesh mesh_from_arrays(const py::handle& positions, const py::handle& faces);

//! A vertex index the caller passed as `name` (a pole, an end of a cut), checked against `mesh`.
[[nodiscard]] int vertex_argument(const std::string& name, long long vertex, const Mesh& mesh);

//! New C-order numpy arrays holding a copy of `matrix`, of dtype `Scalar`.
template <typename Scalar, typename Derived>
[[nodiscard]] py::array_t<Scalar> to_numpy(const Eigen::MatrixBase<Derived>& matrix) {
  py::array_t<Scalar> array({static_cast<py::ssize_t>(matrix.rows()), static_cast<py::ssize_t>(matrix.cols())});
  auto out = array.template mutable_unchecked<2>();
  for (Eigen::Index r = 0; r < matrix.rows(); ++r)
    for (Eigen::Index c = 0; c < matrix.cols(); ++c) out(r, c) = static_cast<Scalar>(matrix(r, c));
  return array;
}

//! A new one-dimensional numpy array holding a copy of `values`.
template <typename Scalar, typename Container>
[[nodiscard]] py::array_t<Scalar> vector_to_numpy(const Container& values) {
  py::array_t<Scalar> array(static_cast<py::ssize_t>(values.size()));
  auto out = array.template mutable_unchecked<1>();
  py::ssize_t i = 0;
  for (const auto& value : values) out(i++) = static_cast<Scalar>(value);
  return array;
}

}  // namespace harmonia::python
