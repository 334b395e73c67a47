// glTF 2.0 documents (harmonia/gltf.h) for Python: a document read once, the triangles of its
// scene or of one mesh as arrays, and updates (new texture coordinates or positions) written back
// into a copy of the document with nothing else changed.

#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "core/bindings.h"
#include "core/errors.h"
#include "core/numpy_arrays.h"
#include "harmonia/gltf.h"

namespace harmonia::python {

namespace {

py::dict summary_dict(const GltfDocument& document) {
  const GltfSummary summary = document.summary();
  py::list meshes;
  for (const GltfMeshSummary& mesh : summary.meshes) {
    py::list primitives;
    for (const GltfPrimitiveSummary& primitive : mesh.primitives) {
      py::dict entry;
      entry["mode"] = primitive.mode;
      entry["vertices"] = primitive.vertices;
      entry["triangles"] = primitive.triangles;
      entry["attributes"] = primitive.attributes;
      entry["morph_targets"] = primitive.morph_targets;
      entry["draco"] = primitive.draco;
      primitives.append(entry);
    }
    py::dict entry;
    entry["name"] = mesh.name;
    entry["instances"] = mesh.instances;
    entry["primitives"] = primitives;
    meshes.append(entry);
  }
  py::dict out;
  out["meshes"] = meshes;
  out["scenes"] = summary.scenes;
  out["default_scene"] = summary.default_scene;
  out["nodes"] = summary.nodes;
  out["materials"] = summary.materials;
  out["textures"] = summary.textures;
  out["images"] = summary.images;
  out["skins"] = summary.skins;
  out["animations"] = summary.animations;
  out["extensions_used"] = summary.extensions_used;
  out["extensions_required"] = summary.extensions_required;
  return out;
}

py::list parts_list(const GltfTriangles& triangles) {
  py::list parts;
  for (const GltfPart& part : triangles.parts) {
    py::dict entry;
    entry["mesh"] = part.mesh;
    entry["primitive"] = part.primitive;
    entry["node"] = part.node;
    entry["first_vertex"] = part.first_vertex;
    entry["vertex_count"] = part.vertex_count;
    entry["first_face"] = part.first_face;
    entry["face_count"] = part.face_count;
    entry["mirrored"] = part.mirrored;
    parts.append(entry);
  }
  return parts;
}

// Layouts as (m, 6) or (m, 3, 2) arrays of corner UVs.
Eigen::Matrix<double, Eigen::Dynamic, 6> corner_uv_argument(const py::handle& values, long long faces) {
  py::array array = py::array::ensure(values);
  if (!array) raise_invalid_input("corner_uv must be an array of shape (m, 3, 2) or (m, 6)");
  if (array.ndim() == 3) array = array.attr("reshape")(array.shape(0), 6);
  const Eigen::MatrixXd matrix = real_matrix(array, "corner_uv", 6);
  if (matrix.rows() != faces) {
    raise_invalid_input("corner_uv has " + std::to_string(matrix.rows()) + " rows for " +
                        std::to_string(faces) + " faces");
  }
  return matrix;
}

}  // namespace

void bind_gltf(py::module_& module) {
  py::class_<GltfTriangles>(module, "GltfTriangles")
      .def_property_readonly("positions", [](const GltfTriangles& t) { return to_numpy<double>(t.mesh.vertices); })
      .def_property_readonly("faces", [](const GltfTriangles& t) { return to_numpy<std::int32_t>(t.mesh.faces); })
      .def_property_readonly("parts", &parts_list)
      .def_readonly("skipped_point_primitives", &GltfTriangles::skipped_point_primitives)
      .def_readonly("skipped_line_primitives", &GltfTriangles::skipped_line_primitives);

  py::class_<GltfPrimitiveUpdate>(module, "GltfPrimitiveUpdate")
      .def_readonly("mesh", &GltfPrimitiveUpdate::mesh)
      .def_readonly("primitive", &GltfPrimitiveUpdate::primitive)
      .def_property_readonly("source_vertex", [](const GltfPrimitiveUpdate& u) { return vector_to_numpy<std::uint32_t>(u.source_vertex); });

  py::class_<GltfDocument>(module, "GltfDocument")
      .def_static("read", [](const std::string& path) {
        const py::gil_scoped_release released;
        return GltfDocument::read(path);
      }, py::arg("path"))
      .def_property_readonly("name", &GltfDocument::name)
      .def_property_readonly("mesh_count", &GltfDocument::mesh_count)
      .def("primitive_count", &GltfDocument::primitive_count, py::arg("mesh"))
      .def("texcoord_sets", &GltfDocument::texcoord_sets, py::arg("mesh"), py::arg("primitive"))
      .def("texcoords", [](const GltfDocument& document, int mesh, int primitive, int set) {
        return to_numpy<double>(document.texcoords(mesh, primitive, set));
      }, py::arg("mesh"), py::arg("primitive"), py::arg("set"))
      .def("corner_texcoords", [](const GltfDocument& document, const GltfTriangles& triangles, int set) {
        return to_numpy<double>(corner_texcoords(document, triangles, set));
      }, py::arg("triangles"), py::arg("set"))
      .def("find_mesh", &GltfDocument::find_mesh, py::arg("name"))
      .def("summary", &summary_dict)
      .def("scene_triangles", &GltfDocument::scene_triangles)
      .def("mesh_triangles", &GltfDocument::mesh_triangles, py::arg("mesh"), py::arg("primitive") = -1)
      .def("all_mesh_triangles", [](const GltfDocument& document) { return all_mesh_triangles(document); });

  module.def("gltf_texcoord_updates", [](const GltfTriangles& triangles, const py::handle& corner_uv,
                                         const py::object& chart_of_face, const py::object& page_of_face) {
    const auto layout = corner_uv_argument(corner_uv, triangles.mesh.faces.rows());
    std::vector<int> charts, pages;
    if (!chart_of_face.is_none()) charts = chart_of_face.cast<std::vector<int>>();
    if (!page_of_face.is_none()) pages = page_of_face.cast<std::vector<int>>();
    return texcoord_updates(triangles, layout, charts, pages);
  }, py::arg("triangles"), py::arg("corner_uv"), py::arg("chart_of_face") = py::none(),
     py::arg("page_of_face") = py::none());
  module.def("gltf_position_updates", [](const GltfTriangles& triangles, const py::handle& positions) {
    const Eigen::MatrixXd values = real_matrix(positions, "positions", 3);
    return position_updates(triangles, values);
  }, py::arg("triangles"), py::arg("positions"));
  module.def("write_gltf", [](const std::string& path, const GltfDocument& document,
                              const std::vector<GltfPrimitiveUpdate>& updates, int texcoord, bool overwrite) {
    GltfWriteOptions options;
    options.texcoord = texcoord;
    options.overwrite = overwrite;
    const py::gil_scoped_release released;
    write_gltf(path, document, updates, options);
  }, py::arg("path"), py::arg("document"), py::arg("updates"), py::arg("texcoord") = -1,
     py::arg("overwrite") = false);
}

}  // namespace harmonia::python
