// Flattening a disk with any planar method (harmonia/flattening.h), measuring a layout
// (harmonia/metrics.h) and comparing layouts (harmonia/distortion_plot.h) for Python: the
// compiled half of harmonia.unwrap(), harmonia.evaluate() and harmonia.compare()
// (python/harmonia/planar.py). The option names and values are the program's (`harmonia unwrap`).

#include <optional>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "core/bindings.h"
#include "core/errors.h"
#include "core/numpy_arrays.h"
#include "core/released_call.h"
#include "core/solver_choice.h"
#include "harmonia/distortion_plot.h"
#include "harmonia/flattening.h"
#include "harmonia/metrics.h"

namespace harmonia::python {

namespace {

// A keyword's value among `names` (their values `values`), or InvalidInputError naming both.
template <typename Value>
Value one_of(const std::string& keyword, const std::string& given, std::initializer_list<const char*> names,
             std::initializer_list<Value> values) {
  auto value = values.begin();
  std::string expected;
  for (const char* name : names) {
    if (given == name) return *value;
    expected += (expected.empty() ? "\"" : ", \"") + std::string(name) + "\"";
    ++value;
  }
  raise_invalid_input(keyword + " is \"" + given + "\": expected one of " + expected);
}

py::tuple unwrap(const py::handle& positions, const py::handle& faces, const std::string& method,
                 std::optional<std::string> weights, const std::string& boundary, std::optional<int> rounds,
                 bool polish, const std::string& stop_after, double boundary_t, const std::string& solver,
                 bool underdetermined, const std::string& reconstruction, const std::string& normalize,
                 const std::string& backend, const py::object& device, const py::object& progress,
                 const py::object& cancel) {
  const Mesh mesh = mesh_from_arrays(positions, faces);
  FlatteningChoice choice;
  const std::optional<FlatteningMethod> kind = flattening_method_from_string(method);
  if (!kind)
    raise_invalid_input("method is \"" + method +
                        "\": expected one of \"conformal\", \"lscm\", \"qhm\", \"abf\", \"linabf\", \"free\"");
  choice.method = *kind;
  if (weights) {
    const std::optional<WeightScheme> scheme = weight_scheme_from_string(*weights);
    if (!scheme) raise_invalid_input("weights is \"" + *weights + "\": not a weight scheme (see harmonia unwrap --help)");
    choice.weights = *scheme;
  }
  if ((choice.method == FlatteningMethod::qhm || choice.method == FlatteningMethod::free) &&
      choice.weights != WeightScheme::cotangent && choice.weights != WeightScheme::mean_value)
    raise_invalid_input("method \"" + method + "\" takes weights \"cotangent\" or \"mean-value\", not \"" +
                        weights.value_or("") + "\"");
  choice.boundary = one_of("boundary", boundary, {"circle", "square"}, {BoundaryShape::circle, BoundaryShape::square});
  if (rounds) {
    if (*rounds < 1) raise_invalid_input("rounds is " + std::to_string(*rounds) + ": expected 1 or more");
    if (choice.method == FlatteningMethod::linabf) choice.linabf_rounds = *rounds;
    choice.rounds = *rounds;
  }
  choice.polish = polish;
  choice.stop_after_conformal = one_of("stop_after", stop_after, {"quasi-harmonic", "conformal"}, {false, true});
  choice.boundary_t = boundary_t;
  choice.abf_solver = one_of("solver", solver, {"auto", "schur-minres", "uzawa", "full-minres", "full-cgnr", "schur-direct"},
                             {AbfSolver::automatic, AbfSolver::schur_minres, AbfSolver::uzawa, AbfSolver::full_minres,
                              AbfSolver::full_cgnr, AbfSolver::schur_direct});
  choice.underdetermined = underdetermined;
  choice.reconstruction = one_of("reconstruction", reconstruction, {"lsq", "greedy"},
                                 {AngleReconstruction::least_squares, AngleReconstruction::greedy});
  choice.normalization = one_of("normalize", normalize, {"surface-area", "unit-square", "none"},
                                {UvNormalization::match_surface_area, UvNormalization::unit_square, UvNormalization::none});
  const SolverOptions solver_choice = solver_options(backend, device);
  MapResult result;
  AngleFigures figures;
  run_released(python_control(progress, cancel), {}, [&](const ProgressCallback& callback) {
    SolverOptions call = solver_choice;
    call.progress = callback;
    result = flatten_disk(mesh, choice, call, &figures);
    return result.report.ok() || result.report.status == Status::flipped_triangles;
  });
  // A map with flipped triangles is still a map (the report counts them), as the program writes it.
  if (result.report.status != Status::flipped_triangles) raise_unless_ok(result.report, asks_for_device(solver_choice));
  py::dict report = report_dict(result.report);
  report["degenerate_triangles"] = result.report.degenerate_triangles;
  report["boundary_self_intersections"] = result.report.boundary_self_intersections;
  report["constraint_residual"] = result.report.constraint_residual;
  if (choice.method == FlatteningMethod::abf || choice.method == FlatteningMethod::linabf) {
    report["abf_energy"] = figures.abf_energy;
    report["boundary_t"] = figures.boundary_t;
  }
  return py::make_tuple(to_numpy<double>(result.uv), report);
}

// A layout of `mesh`: its UVs and the UV row of each corner (the mesh's faces when uv has one
// row per vertex and uv_faces is None).
struct Layout {
  Eigen::MatrixX2d uv;
  Eigen::MatrixX3i uv_faces;
};

Layout layout_of(const Mesh& mesh, const py::handle& uv, const py::handle& uv_faces, const std::string& name) {
  Layout layout;
  layout.uv = real_matrix(uv, name, 2);
  if (uv_faces.is_none()) {
    if (layout.uv.rows() != mesh.vertices.rows())
      raise_invalid_input(name + " has " + std::to_string(layout.uv.rows()) + " rows for " +
                          std::to_string(mesh.vertices.rows()) + " positions: give uv_faces, or one uv per position");
    layout.uv_faces = mesh.faces;
  } else {
    layout.uv_faces = index_matrix(uv_faces, name + " faces", 3, layout.uv.rows(), "uv row");
    if (layout.uv_faces.rows() != mesh.faces.rows())
      raise_invalid_input(name + " faces has " + std::to_string(layout.uv_faces.rows()) + " rows for " +
                          std::to_string(mesh.faces.rows()) + " faces");
  }
  return layout;
}

py::dict metrics_dict(const DistortionMetrics& metrics) {
  py::dict dict;
  dict["faces"] = metrics.faces;
  dict["flipped_triangles"] = metrics.flipped_triangles;
  dict["zero_area_triangles"] = metrics.zero_area_triangles;
  dict["degenerate_input_triangles"] = metrics.degenerate_input_triangles;
  dict["boundary_self_intersections"] = metrics.boundary_self_intersections;
  dict["angle_error_mean_squared"] = metrics.angle_error_mean_squared;
  dict["abf_energy"] = metrics.abf_energy;
  dict["conformal_distortion_mean"] = metrics.conformal_distortion_mean;
  dict["conformal_distortion_max"] = metrics.conformal_distortion_max;
  dict["area_distortion_mean"] = metrics.area_distortion_mean;
  dict["area_distortion_max"] = metrics.area_distortion_max;
  dict["l2_stretch"] = metrics.l2_stretch;
  return dict;
}

py::dict evaluate(const py::handle& positions, const py::handle& faces, const py::handle& uv,
                  const py::object& uv_faces) {
  const Mesh mesh = mesh_from_arrays(positions, faces);
  const Layout layout = layout_of(mesh, uv, uv_faces, "uv");
  DistortionMetrics metrics;
  {
    const py::gil_scoped_release released;
    metrics = evaluate_map(mesh, layout.uv, layout.uv_faces);
  }
  return metrics_dict(metrics);
}

// Several layouts of one mesh: each one's figures (as evaluate) and, with `picture`, the plot of
// their sorted per-triangle angle distortion and log area ratio (`harmonia compare --picture`).
py::dict compare(const py::handle& positions, const py::handle& faces, const py::dict& layouts,
                 const std::string& picture, const std::string& title) {
  const Mesh mesh = mesh_from_arrays(positions, faces);
  if (layouts.empty()) raise_invalid_input("layouts is empty: expected {label: uv or (uv, uv_faces)}");
  std::vector<std::string> labels;
  std::vector<Layout> parsed;
  for (const auto& [key, value] : layouts) {
    const std::string label = py::str(key);
    const bool with_faces = py::isinstance<py::tuple>(value) && py::len(value) == 2;
    const py::handle uv = with_faces ? value.cast<py::tuple>()[0] : value;
    const py::object uv_faces = with_faces ? py::object(value.cast<py::tuple>()[1]) : py::none();
    labels.push_back(label);
    parsed.push_back(layout_of(mesh, uv, uv_faces, "layouts[" + label + "]"));
  }
  std::vector<DistortionMetrics> figures(parsed.size());
  std::vector<std::vector<double>> angle_distortions(parsed.size());
  {
    const py::gil_scoped_release released;
    std::vector<LayoutDistortion> curves;
    for (std::size_t k = 0; k < parsed.size(); ++k) {
      figures[k] = evaluate_map(mesh, parsed[k].uv, parsed[k].uv_faces);
      const Eigen::VectorXd angle = face_angle_distortion(mesh, parsed[k].uv, parsed[k].uv_faces);
      angle_distortions[k].assign(angle.data(), angle.data() + angle.size());
      curves.push_back(LayoutDistortion{labels[k], angle, figures[k].face_area_log_ratio});
    }
    if (!picture.empty()) {
      DistortionPlotOptions options;
      options.title = title;
      write_distortion_plot(picture, curves, options);
    }
  }
  py::dict table;
  for (std::size_t k = 0; k < parsed.size(); ++k) {
    py::dict row = metrics_dict(figures[k]);
    row["face_angle_distortion"] = vector_to_numpy<double>(angle_distortions[k]);
    table[py::str(labels[k])] = row;
  }
  return table;
}

}  // namespace

void bind_planar(py::module_& module) {
  module.def("unwrap", &unwrap, py::arg("positions"), py::arg("faces"), py::kw_only(), py::arg("method"),
             py::arg("weights"), py::arg("boundary"), py::arg("rounds"), py::arg("polish"), py::arg("stop_after"),
             py::arg("boundary_t"), py::arg("solver"), py::arg("underdetermined"), py::arg("reconstruction"),
             py::arg("normalize"), py::arg("backend"), py::arg("device"), py::arg("progress"), py::arg("cancel"));
  module.def("evaluate", &evaluate, py::arg("positions"), py::arg("faces"), py::arg("uv"), py::arg("uv_faces"));
  module.def("compare", &compare, py::arg("positions"), py::arg("faces"), py::arg("layouts"), py::arg("picture"),
             py::arg("title"));
}

}  // namespace harmonia::python
