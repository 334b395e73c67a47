// Deformation transfer (harmonia/deformation_transfer.h) for Python: the compiled half of
// harmonia.DeformationTransfer (python/harmonia/editing.py). Built once, then one call a pose.

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "core/bindings.h"
#include "core/errors.h"
#include "core/numpy_arrays.h"
#include "core/solver_choice.h"
#include "harmonia/deformation_transfer.h"

namespace harmonia::python {

namespace {

class PythonDeformationTransfer {
 public:
  PythonDeformationTransfer(const py::handle& source_positions, const py::handle& source_faces,
                            const py::handle& target_positions, const py::handle& target_faces,
                            const py::handle& markers, const std::string& method, int components,
                            double max_match_distance, int smoothing_passes, int fold_repair_rounds,
                            const std::string& backend, const py::object& device) {
    const Mesh source = mesh_from_arrays(source_positions, source_faces);
    const Mesh target = mesh_from_arrays(target_positions, target_faces);
    source_vertex_count_ = source.vertex_count();
    // Marker pairs: column 0 a source vertex, column 1 a target vertex (each checked against its
    // own mesh by the library, which names the pair).
    const Eigen::MatrixXi pairs =
        index_matrix(markers, "markers", 2, std::max<long long>(source.vertices.rows(), target.vertices.rows()));
    std::vector<MarkerPair> marker_pairs;
    for (Eigen::Index k = 0; k < pairs.rows(); ++k) marker_pairs.push_back(MarkerPair{pairs(k, 0), pairs(k, 1)});
    DeformationTransferOptions options;
    if (method == "correspondence") {
      options.method = TransferMethod::correspondence;
    } else if (method == "quaternion") {
      options.method = TransferMethod::quaternion;
    } else {
      raise_invalid_input("method is \"" + method + "\": expected \"correspondence\" or \"quaternion\"");
    }
    options.components = components;
    options.max_match_distance = max_match_distance;
    options.smoothing_passes = smoothing_passes;
    options.fold_repair_rounds = fold_repair_rounds;
    options.solver = solver_options(backend, device);
    asked_for_device_ = asks_for_device(options.solver);
    {
      const py::gil_scoped_release released;
      transfer_ = std::make_unique<DeformationTransfer>(source, target, marker_pairs, options);
    }
    raise_unless_ok(transfer_->setup_report(), asked_for_device_);
  }

  py::dict setup_report() const { return report_dict(transfer_->setup_report()); }
  int matched_triangles() const { return transfer_->matched_triangles(); }
  int unmatched_triangles() const { return transfer_->unmatched_triangles(); }

  py::tuple transfer(const py::handle& source_pose) {
    const Eigen::MatrixX3d pose = real_matrix(source_pose, "source_pose", 3);
    if (pose.rows() != source_vertex_count_)
      raise_invalid_input("source_pose has " + std::to_string(pose.rows()) + " rows for the source's " +
                          std::to_string(source_vertex_count_) + " vertices");
    TransferResult result;
    {
      const py::gil_scoped_release released;
      const std::lock_guard lock(mutex_);
      result = transfer_->transfer(pose);
    }
    if (result.report.status != Status::flipped_triangles) raise_unless_ok(result.report, asked_for_device_);
    py::dict report = report_dict(result.report);
    report["folded_triangles"] = result.folded_triangles;
    report["source_folded_triangles"] = result.source_folded_triangles;
    report["turned_over_triangles"] = result.turned_over_triangles;
    return py::make_tuple(to_numpy<double>(result.positions), report);
  }

 private:
  std::unique_ptr<DeformationTransfer> transfer_;
  std::mutex mutex_;
  long long source_vertex_count_ = 0;
  bool asked_for_device_ = false;
};

}  // namespace

void bind_transfer(py::module_& module) {
  py::class_<PythonDeformationTransfer>(module, "DeformationTransfer")
      .def(py::init<const py::handle&, const py::handle&, const py::handle&, const py::handle&, const py::handle&,
                    const std::string&, int, double, int, int, const std::string&, const py::object&>(),
           py::arg("source_positions"), py::arg("source_faces"), py::arg("target_positions"), py::arg("target_faces"),
           py::arg("markers"), py::kw_only(), py::arg("method"), py::arg("components"), py::arg("max_match_distance"),
           py::arg("smoothing_passes"), py::arg("fold_repair_rounds"), py::arg("backend"), py::arg("device"))
      .def_property_readonly("setup_report", &PythonDeformationTransfer::setup_report)
      .def_property_readonly("matched_triangles", &PythonDeformationTransfer::matched_triangles)
      .def_property_readonly("unmatched_triangles", &PythonDeformationTransfer::unmatched_triangles)
      .def("transfer", &PythonDeformationTransfer::transfer, py::arg("source_pose"));
}

}  // namespace harmonia::python
