#include "core/numpy_arrays.h"

#include <cmath>
#include <cstdint>
#include <sstream>

#include "core/errors.h"

namespace harmonia::python {

namespace {

// The array behind `values` (a list of lists is accepted as numpy.asarray accepts it).
py::array as_array(const py::handle& values, const std::string& name) {
  if (values.is_none()) raise_invalid_input(name + " is None: expected an array");
  try {
    return py::array::ensure(values);
  } catch (const py::error_already_set&) {
    raise_invalid_input(name + " is not an array: " + std::string(py::str(py::type::of(values))));
  }
}

std::string shape_text(const py::array& array) {
  std::ostringstream text;
  text << '(';
  for (py::ssize_t axis = 0; axis < array.ndim(); ++axis)
    text << (axis ? ", " : "") << array.shape(axis);
  text << (array.ndim() == 1 ? ",)" : ")");
  return text.str();
}

std::string dtype_text(const py::array& array) { return py::str(array.dtype()); }

void check_shape(const py::array& array, const std::string& name, int columns) {
  if (array.ndim() != 2 || array.shape(1) != columns)
    raise_invalid_input(name + " has shape " + shape_text(array) + ": expected (n, " +
                        std::to_string(columns) + ")");
}

// numpy's kind letter of the array's dtype: 'f' float, 'i' signed, 'u' unsigned, 'b' bool, ...
char kind_of(const py::array& array) { return array.dtype().kind(); }

template <typename Integer>
Eigen::MatrixXi checked_indices(const py::array& array, const std::string& name, int columns, long long count,
                                const std::string& item) {
  // forcecast: numpy converts any integer dtype and memory order (a copy only where it must).
  const auto converted = py::array_t<Integer, py::array::forcecast>::ensure(array);
  const auto view = converted.template unchecked<2>();
  Eigen::MatrixXi indices(view.shape(0), columns);
  for (py::ssize_t r = 0; r < view.shape(0); ++r)
    for (int c = 0; c < columns; ++c) {
      const Integer value = view(r, c);
      const bool negative = std::is_signed_v<Integer> && value < 0;
      if (negative || static_cast<unsigned long long>(value) >= static_cast<unsigned long long>(count)) {
        raise_invalid_input(name + "[" + std::to_string(r) + ", " + std::to_string(c) + "] = " +
                            std::to_string(value) + " is not a " + item + " (there are " +
                            std::to_string(count) + ": 0.." + std::to_string(count - 1) + ")");
      }
      indices(r, c) = static_cast<int>(value);
    }
  return indices;
}

}  // namespace

Eigen::MatrixXd real_matrix(const py::handle& values, const std::string& name, int columns) {
  const py::array array = as_array(values, name);
  const char kind = kind_of(array);
  if (kind != 'f' && kind != 'i' && kind != 'u')
    raise_invalid_input(name + " has dtype " + dtype_text(array) + ": expected real numbers (a float or integer dtype)");
  check_shape(array, name, columns);
  const auto converted = py::array_t<double, py::array::forcecast>::ensure(array);
  const auto view = converted.unchecked<2>();
  Eigen::MatrixXd matrix(view.shape(0), columns);
  for (py::ssize_t r = 0; r < view.shape(0); ++r)
    for (int c = 0; c < columns; ++c) {
      const double value = view(r, c);
      if (!std::isfinite(value)) {
        std::ostringstream text;
        text << name << "[" << r << ", " << c << "] = " << value << " is not finite";
        raise_invalid_input(text.str());
      }
      matrix(r, c) = value;
    }
  return matrix;
}

Eigen::MatrixXi index_matrix(const py::handle& values, const std::string& name, int columns, long long count,
                             const std::string& item) {
  const py::array array = as_array(values, name);
  const char kind = kind_of(array);
  if (kind != 'i' && kind != 'u')
    raise_invalid_input(name + " has dtype " + dtype_text(array) + ": expected integer indices");
  check_shape(array, name, columns);
  // Read in the array's own integer type where it is one of the two usual ones (no conversion
  // copy), else converted by numpy to a 64-bit type that holds every value of it.
  const auto itemsize = array.dtype().itemsize();
  if (kind == 'i' && itemsize == 4) return checked_indices<std::int32_t>(array, name, columns, count, item);
  if (kind == 'u') return checked_indices<std::uint64_t>(array, name, columns, count, item);
  return checked_indices<std::int64_t>(array, name, columns, count, item);
}

Mesh mesh_from_arrays(const py::handle& positions, const py::handle& faces) {
  Mesh mesh;
  mesh.vertices = real_matrix(positions, "positions", 3);
  mesh.faces = index_matrix(faces, "faces", 3, mesh.vertices.rows());
  if (mesh.faces.rows() == 0) raise_invalid_input("faces is empty: the mesh has no faces");
  return mesh;
}

int vertex_argument(const std::string& name, long long vertex, const Mesh& mesh) {
  if (vertex < 0 || vertex >= mesh.vertices.rows())
    raise_invalid_input(name + " = " + std::to_string(vertex) + " is not a vertex (there are " +
                        std::to_string(mesh.vertices.rows()) + ")");
  return static_cast<int>(vertex);
}

}  // namespace harmonia::python
