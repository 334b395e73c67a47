// Reading and writing meshes (harmonia/io.h) for Python: arrays in, arrays out.

#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "core/bindings.h"
#include "core/errors.h"
#include "core/numpy_arrays.h"
#include "harmonia/io.h"

namespace harmonia::python {

namespace {

py::tuple read_mesh_arrays(const std::string& path) {
  Mesh mesh;
  {
    const py::gil_scoped_release released;
    mesh = read_mesh(path);
  }
  return py::make_tuple(to_numpy<double>(mesh.vertices), to_numpy<std::int32_t>(mesh.faces));
}

py::tuple read_textured_obj_arrays(const std::string& path) {
  TexturedMesh textured;
  {
    const py::gil_scoped_release released;
    textured = read_textured_obj(path);
  }
  return py::make_tuple(to_numpy<double>(textured.mesh.vertices), to_numpy<std::int32_t>(textured.mesh.faces),
                        to_numpy<double>(textured.uv), to_numpy<std::int32_t>(textured.uv_faces));
}

void write_mesh_arrays(const std::string& path, const py::handle& positions, const py::handle& faces) {
  const Mesh mesh = mesh_from_arrays(positions, faces);
  const py::gil_scoped_release released;
  write_mesh(path, mesh);
}

void write_textured_obj_arrays(const std::string& path, const py::handle& positions, const py::handle& faces,
                               const py::handle& uv, const py::object& uv_faces) {
  TexturedMesh textured;
  textured.mesh = mesh_from_arrays(positions, faces);
  textured.uv = real_matrix(uv, "uv", 2);
  if (uv_faces.is_none()) {
    if (textured.uv.rows() != textured.mesh.vertices.rows())
      raise_invalid_input("uv has " + std::to_string(textured.uv.rows()) + " rows for " +
                          std::to_string(textured.mesh.vertices.rows()) +
                          " positions: give uv_faces, or one uv per position");
    textured.uv_faces = textured.mesh.faces;
  } else {
    textured.uv_faces = index_matrix(uv_faces, "uv_faces", 3, textured.uv.rows(), "uv row");
    if (textured.uv_faces.rows() != textured.mesh.faces.rows())
      raise_invalid_input("uv_faces has " + std::to_string(textured.uv_faces.rows()) + " rows for " +
                          std::to_string(textured.mesh.faces.rows()) + " faces");
  }
  const py::gil_scoped_release released;
  write_obj(path, textured);
}

}  // namespace

void bind_mesh_io(py::module_& module) {
  module.def("read_mesh", &read_mesh_arrays, py::arg("path"));
  module.def("read_textured_obj", &read_textured_obj_arrays, py::arg("path"));
  module.def("write_mesh", &write_mesh_arrays, py::arg("path"), py::arg("positions"), py::arg("faces"));
  module.def("write_textured_obj", &write_textured_obj_arrays, py::arg("path"), py::arg("positions"),
             py::arg("faces"), py::arg("uv"), py::arg("uv_faces"));
}

}  // namespace harmonia::python
