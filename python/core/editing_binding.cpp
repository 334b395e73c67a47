// Surface editing (harmonia/surface_editor.h) for Python: the compiled half of
// harmonia.SurfaceEditor (python/harmonia/editing.py). The editor keeps its factorization between
// frames; a frame copies nothing but its result.

#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "core/bindings.h"
#include "core/errors.h"
#include "core/numpy_arrays.h"
#include "core/solver_choice.h"
#include "harmonia/surface_editor.h"

namespace harmonia::python {

namespace {

// One editor and the lock that keeps two Python threads from running frames on it at once (the
// library's editor is not meant for concurrent frames; an editor per thread runs in parallel).
class PythonSurfaceEditor {
 public:
  PythonSurfaceEditor(const py::handle& positions, const py::handle& faces, const py::handle& fixed,
                      const py::list& handles, const py::object& region_of_interest, std::optional<int> rotation_clusters,
                      int refinement_steps, double frame_budget_seconds, bool check_orientation,
                      const std::string& backend, const py::object& device) {
    const Mesh mesh = mesh_from_arrays(positions, faces);
    vertex_count_ = mesh.vertex_count();
    EditRegions regions;
    regions.fixed = vertex_list(fixed, "fixed");
    for (std::size_t h = 0; h < handles.size(); ++h)
      regions.handles.push_back(vertex_list(handles[h], "handles[" + std::to_string(h) + "]"));
    if (!region_of_interest.is_none()) regions.region_of_interest = vertex_list(region_of_interest, "region_of_interest");
    handle_count_ = static_cast<int>(regions.handles.size());
    SurfaceEditOptions options;
    options.rotation_clusters = rotation_clusters;
    options.refinement_steps = refinement_steps;
    options.frame_budget = frame_budget_seconds;
    options.check_orientation = check_orientation;
    options.solver = solver_options(backend, device);
    asked_for_device_ = asks_for_device(options.solver);
    {
      const py::gil_scoped_release released;
      editor_ = std::make_unique<SurfaceEditor>(mesh, regions, options);
    }
    raise_unless_ok(editor_->setup_report(), asked_for_device_);
  }

  py::dict setup_report() const { return report_dict(editor_->setup_report()); }
  py::array_t<double> handle_fields() const { return to_numpy<double>(editor_->handle_fields()); }
  int factorization_count() const { return editor_->factorization_count(); }
  int handle_count() const { return handle_count_; }

  // One frame: per handle a unit quaternion (w, x, y, z), a centre, a scale and a translation.
  py::tuple deform(const py::handle& rotations, const py::handle& centers, const py::handle& scales,
                   const py::handle& translations) {
    const Eigen::MatrixXd rotation = per_handle(rotations, "rotations", 4, 1.0, 0.0);
    const Eigen::MatrixXd center = per_handle(centers, "centers", 3, 0.0, 0.0);
    const Eigen::MatrixXd scale = per_handle(scales, "scales", 1, 1.0, 1.0);
    const Eigen::MatrixXd translation = per_handle(translations, "translations", 3, 0.0, 0.0);
    std::vector<SimilarityTransform> transforms(static_cast<std::size_t>(handle_count_));
    for (int h = 0; h < handle_count_; ++h) {
      SimilarityTransform& transform = transforms[static_cast<std::size_t>(h)];
      const Eigen::Quaterniond q(rotation(h, 0), rotation(h, 1), rotation(h, 2), rotation(h, 3));
      if (!(q.norm() > 0.0)) raise_invalid_input("rotations[" + std::to_string(h) + "] is zero: expected a quaternion (w, x, y, z)");
      if (!(scale(h, 0) > 0.0)) raise_invalid_input("scales[" + std::to_string(h) + "] is not positive");
      transform.rotation = q.normalized();
      transform.center = center.row(h).transpose();
      transform.scale = scale(h, 0);
      transform.translation = translation.row(h).transpose();
    }
    SurfaceEditResult result;
    {
      const py::gil_scoped_release released;
      const std::lock_guard lock(mutex_);
      result = editor_->deform(transforms);
    }
    return frame(result);
  }

  py::tuple drag(const py::handle& translations) {
    const Eigen::MatrixXd translation = per_handle(translations, "translations", 3, 0.0, 0.0);
    std::vector<Eigen::Vector3d> moves;
    for (int h = 0; h < handle_count_; ++h) moves.emplace_back(translation.row(h).transpose());
    SurfaceEditResult result;
    {
      const py::gil_scoped_release released;
      const std::lock_guard lock(mutex_);
      result = editor_->drag(moves);
    }
    return frame(result);
  }

 private:
  std::vector<int> vertex_list(const py::handle& values, const std::string& name) const {
    const py::array array = py::array::ensure(values);
    if (!array || array.ndim() > 1) raise_invalid_input(name + " is not a list of vertex indices");
    const py::object column = py::module_::import("numpy").attr("reshape")(array, py::make_tuple(-1, 1));
    const Eigen::MatrixXi indices = index_matrix(column, name, 1, vertex_count_);
    return std::vector<int>(indices.data(), indices.data() + indices.size());
  }

  // A #handles x `columns` argument; None gives every handle `fill` (the first column `first`).
  Eigen::MatrixXd per_handle(const py::handle& values, const std::string& name, int columns, double first,
                             double fill) const {
    if (values.is_none()) {
      Eigen::MatrixXd matrix = Eigen::MatrixXd::Constant(handle_count_, columns, fill);
      matrix.col(0).setConstant(first);
      return matrix;
    }
    const py::object shaped = py::module_::import("numpy").attr("reshape")(values, py::make_tuple(-1, columns));
    const Eigen::MatrixXd matrix = real_matrix(shaped, name, columns);
    if (matrix.rows() != handle_count_)
      raise_invalid_input(name + " has " + std::to_string(matrix.rows()) + " rows for " +
                          std::to_string(handle_count_) + " handles");
    return matrix;
  }

  py::tuple frame(const SurfaceEditResult& result) const {
    if (result.report.status != Status::flipped_triangles) raise_unless_ok(result.report, asked_for_device_);
    py::dict report = report_dict(result.report);
    report["degenerate_triangles"] = result.report.degenerate_triangles;
    report["refinement_steps"] = result.refinement_steps;
    report["frame_seconds"] = result.timing.total();
    return py::make_tuple(to_numpy<double>(result.positions), report);
  }

  std::unique_ptr<SurfaceEditor> editor_;
  std::mutex mutex_;
  int vertex_count_ = 0;
  int handle_count_ = 0;
  bool asked_for_device_ = false;
};

}  // namespace

void bind_editing(py::module_& module) {
  py::class_<PythonSurfaceEditor>(module, "SurfaceEditor")
      .def(py::init<const py::handle&, const py::handle&, const py::handle&, const py::list&, const py::object&, std::optional<int>,
                    int, double, bool, const std::string&, const py::object&>(),
           py::arg("positions"), py::arg("faces"), py::arg("fixed"), py::arg("handles"),
           py::arg("region_of_interest"), py::kw_only(), py::arg("rotation_clusters"), py::arg("refinement_steps"),
           py::arg("frame_budget_seconds"), py::arg("check_orientation"), py::arg("backend"), py::arg("device"))
      .def_property_readonly("setup_report", &PythonSurfaceEditor::setup_report)
      .def_property_readonly("handle_fields", &PythonSurfaceEditor::handle_fields)
      .def_property_readonly("factorization_count", &PythonSurfaceEditor::factorization_count)
      .def_property_readonly("handle_count", &PythonSurfaceEditor::handle_count)
      .def("deform", &PythonSurfaceEditor::deform, py::arg("rotations"), py::arg("centers"), py::arg("scales"),
           py::arg("translations"))
      .def("drag", &PythonSurfaceEditor::drag, py::arg("translations"));
}

}  // namespace harmonia::python
