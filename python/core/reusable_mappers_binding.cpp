// The reusable solvers for Python (harmonia/fixed_boundary_map.h, harmonia/spherical_map.h): the
// connectivity analysed once, then update_geometry() and solve() as often as the caller likes,
// e.g. for every frame of an animation with one topology. The compiled half of
// harmonia.DiskMapper and harmonia.SphereMapper (python/harmonia/mappers.py).

#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "core/bindings.h"
#include "core/errors.h"
#include "core/numpy_arrays.h"
#include "core/solver_choice.h"
#include "harmonia/fixed_boundary_map.h"
#include "harmonia/spherical_map.h"

namespace harmonia::python {

namespace {

// New positions for a solver built on `vertex_count` vertices.
Eigen::MatrixX3d new_positions(const py::handle& positions, Eigen::Index vertex_count) {
  const Eigen::MatrixX3d vertices = real_matrix(positions, "positions", 3);
  if (vertices.rows() != vertex_count)
    raise_invalid_input("positions has " + std::to_string(vertices.rows()) + " rows for the " +
                        std::to_string(vertex_count) + " vertices the solver was built on");
  return vertices;
}

// A library solver of `Mapper` type built once, with the lock that makes Python threads take turns
// on it (a solver object is not meant for concurrent calls; one per thread runs in parallel).
template <typename Mapper>
class SharedMapper {
 public:
  template <typename Options>
  SharedMapper(const Mesh& mesh, const Options& options) : vertex_count_(mesh.vertices.rows()) {
    asked_for_device_ = asks_for_device(options.solver);
    {
      const py::gil_scoped_release released;
      mapper_ = std::make_unique<Mapper>(mesh, options);
    }
    raise_unless_ok(mapper_->setup_report(), asked_for_device_);
  }

  void update_geometry(const py::handle& positions) {
    const Eigen::MatrixX3d vertices = new_positions(positions, vertex_count_);
    const py::gil_scoped_release released;
    const std::lock_guard lock(mutex_);
    mapper_->update_geometry(vertices);
  }

  // `solve(mapper)` with the lock released and the mapper held; a report that is neither ok nor
  // flipped_triangles (a map that is still a map) raises.
  template <typename Solve>
  auto solve(Solve solve) {
    decltype(solve(std::declval<Mapper&>())) result;
    {
      const py::gil_scoped_release released;
      const std::lock_guard lock(mutex_);
      result = solve(*mapper_);
    }
    if (result.report.status != Status::flipped_triangles) raise_unless_ok(result.report, asked_for_device_);
    return result;
  }

  [[nodiscard]] const Mapper& mapper() const { return *mapper_; }

 private:
  std::unique_ptr<Mapper> mapper_;
  std::mutex mutex_;
  Eigen::Index vertex_count_ = 0;
  bool asked_for_device_ = false;
};

class PythonDiskMapper {
 public:
  PythonDiskMapper(const py::handle& positions, const py::handle& faces, const std::string& weights,
                   const std::string& boundary, const std::string& backend, const py::object& device)
      : shared_(mesh_from_arrays(positions, faces), options(weights, boundary, backend, device)) {}

  void update_geometry(const py::handle& positions) { shared_.update_geometry(positions); }

  py::tuple solve(const py::object& boundary_uv) {
    std::optional<Eigen::MatrixX2d> placed;
    const Eigen::Index boundary_vertices = shared_.mapper().placement().vertices.size();
    if (!boundary_uv.is_none()) {
      placed = real_matrix(boundary_uv, "boundary_uv", 2);
      if (placed->rows() != boundary_vertices)
        raise_invalid_input("boundary_uv has " + std::to_string(placed->rows()) + " rows for " +
                            std::to_string(boundary_vertices) + " boundary vertices");
    }
    const MapResult result =
        shared_.solve([&](FixedBoundaryMapper& mapper) { return placed ? mapper.solve(*placed) : mapper.solve(); });
    return py::make_tuple(to_numpy<double>(result.uv), report_dict(result.report));
  }

  py::tuple boundary() const {
    const BoundaryPlacement& placement = shared_.mapper().placement();
    return py::make_tuple(
        vector_to_numpy<std::int32_t>(std::vector<int>(placement.vertices.data(),
                                                       placement.vertices.data() + placement.vertices.size())),
        to_numpy<double>(placement.uv));
  }

 private:
  static FixedBoundaryOptions options(const std::string& weights, const std::string& boundary,
                                      const std::string& backend, const py::object& device) {
    FixedBoundaryOptions options;
    const std::optional<WeightScheme> scheme = weight_scheme_from_string(weights);
    if (!scheme) raise_invalid_input("weights is \"" + weights + "\": not a weight scheme");
    options.weights = *scheme;
    if (boundary == "circle") {
      options.boundary.shape = BoundaryShape::circle;
    } else if (boundary == "square") {
      options.boundary.shape = BoundaryShape::square;
    } else {
      raise_invalid_input("boundary is \"" + boundary + "\": expected \"circle\" or \"square\"");
    }
    options.solver = solver_options(backend, device);
    return options;
  }

  SharedMapper<FixedBoundaryMapper> shared_;
};

class PythonSphereMapper {
 public:
  PythonSphereMapper(const py::handle& positions, const py::handle& faces, const std::string& backend,
                     const py::object& device)
      : shared_(mesh_from_arrays(positions, faces), options(backend, device)) {}

  void update_geometry(const py::handle& positions) { shared_.update_geometry(positions); }

  py::tuple solve() {
    const SphericalMapResult result = shared_.solve([](SphericalMapper& mapper) { return mapper.solve(); });
    return py::make_tuple(to_numpy<double>(result.positions), report_dict(result.report));
  }

 private:
  static SphericalMapOptions options(const std::string& backend, const py::object& device) {
    SphericalMapOptions options;
    options.solver = solver_options(backend, device);
    return options;
  }

  SharedMapper<SphericalMapper> shared_;
};

}  // namespace

void bind_reusable_mappers(py::module_& module) {
  py::class_<PythonDiskMapper>(module, "DiskMapper")
      .def(py::init<const py::handle&, const py::handle&, const std::string&, const std::string&, const std::string&,
                    const py::object&>(),
           py::arg("positions"), py::arg("faces"), py::kw_only(), py::arg("weights"), py::arg("boundary"),
           py::arg("backend"), py::arg("device"))
      .def("update_geometry", &PythonDiskMapper::update_geometry, py::arg("positions"))
      .def("solve", &PythonDiskMapper::solve, py::arg("boundary_uv"))
      .def_property_readonly("boundary", &PythonDiskMapper::boundary);
  py::class_<PythonSphereMapper>(module, "SphereMapper")
      .def(py::init<const py::handle&, const py::handle&, const std::string&, const py::object&>(),
           py::arg("positions"), py::arg("faces"), py::kw_only(), py::arg("backend"), py::arg("device"))
      .def("update_geometry", &PythonSphereMapper::update_geometry, py::arg("positions"))
      .def("solve", &PythonSphereMapper::solve);
}

}  // namespace harmonia::python
