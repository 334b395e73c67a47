// Cleaning a mesh up (harmonia/cleanup.h) and cutting it open to a disk (harmonia/cut.h) for
// Python: the compiled half of harmonia.cleanup() and harmonia.cut() (python/harmonia/maps.py).
// With unwrap, they are `harmonia unwrap --cleanup repair --cut` one step at a time.

#include <optional>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "core/bindings.h"
#include "core/errors.h"
#include "core/numpy_arrays.h"
#include "harmonia/cleanup.h"
#include "harmonia/cut.h"

namespace harmonia::python {

namespace {

py::array_t<std::int32_t> index_vector(const Eigen::VectorXi& values) {
  return vector_to_numpy<std::int32_t>(std::vector<int>(values.data(), values.data() + values.size()));
}

py::dict cleanup_mesh(const py::handle& positions, const py::handle& faces, const std::string& mode,
                      double merge_tolerance, bool keep_non_manifold) {
  const Mesh mesh = mesh_from_arrays(positions, faces);
  CleanupOptions options;
  if (mode == "repair") {
    options.mode = CleanupMode::repair;
  } else if (mode == "strict") {
    options.mode = CleanupMode::strict;
  } else {
    raise_invalid_input("mode is \"" + mode + "\": expected \"strict\" or \"repair\"");
  }
  if (!(merge_tolerance >= 0.0)) raise_invalid_input("merge_tolerance must be 0 or more");
  options.merge_tolerance = merge_tolerance;
  options.keep_non_manifold = keep_non_manifold;
  CleanupResult result;
  {
    const py::gil_scoped_release released;
    result = cleanup(mesh, options);
  }
  if (result.status != Status::ok) raise_status(result.status, result.message);
  py::list changes;
  for (const std::string& change : result.changes) changes.append(change);
  py::dict dict;
  dict["positions"] = to_numpy<double>(result.mesh.vertices);
  dict["faces"] = to_numpy<std::int32_t>(result.mesh.faces);
  dict["vertex_map"] = index_vector(result.vertex_map);
  dict["original_vertex"] = index_vector(result.original_vertex);
  dict["original_face"] = index_vector(result.original_face);
  dict["merged_vertices"] = result.merged_vertices;
  dict["removed_unreferenced_vertices"] = result.removed_unreferenced_vertices;
  dict["removed_degenerate_faces"] = result.removed_degenerate_faces;
  dict["removed_duplicate_faces"] = result.removed_duplicate_faces;
  dict["flipped_faces"] = result.flipped_faces;
  dict["changes"] = changes;
  return dict;
}

py::tuple cut(const py::handle& positions, const py::handle& faces, std::optional<long long> from_vertex,
              std::optional<long long> to_vertex) {
  const Mesh mesh = mesh_from_arrays(positions, faces);
  CutOptions options;
  if (from_vertex) options.from_vertex = vertex_argument("from_vertex", *from_vertex, mesh);
  if (to_vertex) options.to_vertex = vertex_argument("to_vertex", *to_vertex, mesh);
  CutResult result;
  {
    const py::gil_scoped_release released;
    result = cut_to_disk(mesh, options);
  }
  if (result.status != Status::ok) raise_status(result.status, result.message);
  return py::make_tuple(to_numpy<double>(result.disk.vertices), to_numpy<std::int32_t>(result.disk.faces),
                        index_vector(result.original_vertex),
                        result.seam_edges);
}

}  // namespace

void bind_topology(py::module_& module) {
  module.def("cleanup", &cleanup_mesh, py::arg("positions"), py::arg("faces"), py::kw_only(), py::arg("mode"),
             py::arg("merge_tolerance"), py::arg("keep_non_manifold"));
  module.def("cut", &cut, py::arg("positions"), py::arg("faces"), py::kw_only(), py::arg("from_vertex"),
             py::arg("to_vertex"));
}

}  // namespace harmonia::python
