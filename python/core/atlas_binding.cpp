// The texture atlas (harmonia/texture_atlas.h) for Python: the compiled half of harmonia.atlas()
// and harmonia.parametrize() (python/harmonia/atlas.py).

#include <cstdint>
#include <cstring>
#include <string>
#include <unordered_map>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "core/bindings.h"
#include "core/errors.h"
#include "core/numpy_arrays.h"
#include "core/released_call.h"
#include "core/solver_choice.h"
#include "harmonia/atlas_io.h"
#include "harmonia/atlas_picture.h"
#include "harmonia/texture_atlas.h"

namespace harmonia::python {

namespace {

// The atlas' phases and their usual shares of its time (cow x16 on the CPU: flattening about
// half, packing a third); the device path runs "batched linear abf" before its flattening.
const PhaseShares kAtlasPhases = {{"validation", 0.0},         {"segmentation", 0.1},
                                  {"device", 0.0},             {"batched linear abf", 0.2},
                                  {"flattening", 0.4},         {"degenerate faces", 0.0},
                                  {"packing", 0.25},           {"metrics", 0.05}};

// A finished atlas with the mesh it was made of (the picture and the OBJ need both).
struct AtlasOfMesh {
  Mesh mesh;
  TextureAtlas atlas;
};

// One vertex of the xatlas form: an input vertex at one UV (UVs compared bit for bit).
struct CornerKey {
  int vertex;
  std::uint64_t u, v;
  bool operator==(const CornerKey&) const = default;
};

struct CornerKeyHash {
  std::size_t operator()(const CornerKey& key) const noexcept {
    std::size_t hash = std::hash<int>{}(key.vertex);
    hash ^= std::hash<std::uint64_t>{}(key.u) + 0x9e3779b97f4a7c15ULL + (hash << 6) + (hash >> 2);
    hash ^= std::hash<std::uint64_t>{}(key.v) + 0x9e3779b97f4a7c15ULL + (hash << 6) + (hash >> 2);
    return hash;
  }
};

std::uint64_t bits_of(double value) {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

// xatlas-python's contract: one new vertex per input vertex and UV, in order of first use by the
// faces; vmapping (uint32, #new) the input vertex of each, indices (uint32, #F x 3) the faces
// over the new vertices, uvs (float32, #new x 2) in [0, 1].
py::tuple xatlas_form(const AtlasOfMesh& result) {
  const Mesh& mesh = result.mesh;
  const auto& corner_uv = result.atlas.corner_uv;
  std::unordered_map<CornerKey, std::uint32_t, CornerKeyHash> index_of;
  index_of.reserve(static_cast<std::size_t>(mesh.faces.rows()) * 2);
  std::vector<std::uint32_t> vmapping;
  std::vector<float> uvs;
  py::array_t<std::uint32_t> indices({static_cast<py::ssize_t>(mesh.faces.rows()), py::ssize_t{3}});
  auto faces_out = indices.mutable_unchecked<2>();
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const double u = corner_uv(f, 2 * k), v = corner_uv(f, 2 * k + 1);
      const CornerKey key{mesh.faces(f, k), bits_of(u), bits_of(v)};
      const auto [slot, inserted] = index_of.try_emplace(key, static_cast<std::uint32_t>(vmapping.size()));
      if (inserted) {
        vmapping.push_back(static_cast<std::uint32_t>(key.vertex));
        uvs.push_back(static_cast<float>(u));
        uvs.push_back(static_cast<float>(v));
      }
      faces_out(f, k) = slot->second;
    }
  py::array_t<float> uv_array({static_cast<py::ssize_t>(vmapping.size()), py::ssize_t{2}});
  std::memcpy(uv_array.mutable_data(), uvs.data(), uvs.size() * sizeof(float));
  return py::make_tuple(vector_to_numpy<std::uint32_t>(vmapping), indices, uv_array);
}

py::dict chart_dict(const AtlasChart& chart) {
  const Eigen::AlignedBox2d& box = chart.texel_box;
  py::dict dict;
  dict["faces"] = vector_to_numpy<std::int32_t>(chart.faces);
  dict["method"] = std::string(to_string(chart.method));
  dict["piece_of_a_cut"] = chart.piece_of_a_cut;
  dict["l2_stretch"] = chart.l2_stretch;
  dict["angle_distortion"] = chart.angle_distortion;
  dict["area_distortion"] = chart.area_distortion;
  dict["surface_area"] = chart.surface_area;
  dict["texel_box"] = py::make_tuple(box.min().x(), box.min().y(), box.max().x(), box.max().y());
  dict["page"] = chart.page;
  return dict;
}

py::dict metrics_dict(const AtlasMetrics& metrics) {
  py::dict dict;
  dict["charts"] = metrics.charts;
  dict["faces"] = metrics.faces;
  dict["coverage"] = metrics.coverage;
  dict["page_coverage"] = metrics.page_coverage;
  dict["texels_per_unit"] = metrics.texels_per_unit;
  dict["l2_stretch"] = metrics.l2_stretch;
  dict["angle_distortion"] = metrics.angle_distortion;
  dict["area_distortion"] = metrics.area_distortion;
  dict["flipped_triangles"] = metrics.flipped_triangles;
  dict["mirrored_charts"] = metrics.mirrored_charts;
  dict["overlapping_texels"] = metrics.overlapping_texels;
  dict["boundary_crossings"] = metrics.boundary_crossings;
  dict["dropped_faces"] = metrics.dropped_faces;
  return dict;
}

// #F x 3 x 2: the corner UVs of each face.
py::array_t<double> corner_uv_array(const TextureAtlas& atlas) {
  const auto faces = static_cast<py::ssize_t>(atlas.corner_uv.rows());
  py::array_t<double> array({faces, py::ssize_t{3}, py::ssize_t{2}});
  auto out = array.mutable_unchecked<3>();
  for (py::ssize_t f = 0; f < faces; ++f)
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 2; ++c) out(f, k, c) = atlas.corner_uv(f, 2 * k + c);
  return array;
}

AtlasOfMesh make_atlas(const py::handle& positions, const py::handle& faces, int resolution, int padding,
                       double max_distortion, double max_normal_deviation, bool keep_splits, int threads,
                       const std::string& backend, const py::object& device, const py::object& progress,
                       const py::object& cancel, double texels_per_unit, bool join_charts, int max_pages,
                       int height) {
  AtlasOfMesh result;
  result.mesh = mesh_from_arrays(positions, faces);
  TextureAtlasOptions options;
  options.resolution = resolution;
  options.padding = padding;
  options.max_distortion = max_distortion;
  options.max_normal_deviation_degrees = max_normal_deviation;
  options.keep_splits = keep_splits;
  options.join_charts = join_charts;
  options.threads = threads;
  options.texels_per_unit = texels_per_unit;
  options.max_pages = max_pages;
  options.height = height;
  options.solver = solver_options(backend, device);
  const PythonControl control = python_control(progress, cancel);
  run_released(control, kAtlasPhases, [&](const ProgressCallback& callback) {
    TextureAtlasOptions call = options;
    call.solver.progress = callback;
    result.atlas = texture_atlas(result.mesh, call);
    return result.atlas.report.ok();
  });
  raise_unless_ok(result.atlas.report, asks_for_device(options.solver));
  return result;
}

// repack_texture_atlas of the mesh and its UVs per corner (#F x 6), as make_atlas.
AtlasOfMesh make_repack(const py::handle& positions, const py::handle& faces, const py::handle& corner_uv,
                        int resolution, int padding, int threads, double texels_per_unit, int max_pages,
                        int height) {
  AtlasOfMesh result;
  result.mesh = mesh_from_arrays(positions, faces);
  const Eigen::Matrix<double, Eigen::Dynamic, 6> uv = real_matrix(corner_uv, "corner_uv", 6);
  TextureAtlasOptions options;
  options.resolution = resolution;
  options.padding = padding;
  options.threads = threads;
  options.texels_per_unit = texels_per_unit;
  options.max_pages = max_pages;
  options.height = height;
  const PythonControl control = python_control(py::none(), py::none());
  run_released(control, kAtlasPhases, [&](const ProgressCallback& callback) {
    TextureAtlasOptions call = options;
    call.solver.progress = callback;
    result.atlas = repack_texture_atlas(result.mesh, uv, call);
    return result.atlas.report.ok();
  });
  raise_unless_ok(result.atlas.report, false);
  return result;
}

}  // namespace

void bind_atlas(py::module_& module) {
  py::class_<AtlasOfMesh>(module, "AtlasOfMesh")
      .def_property_readonly("corner_uv", [](const AtlasOfMesh& r) { return corner_uv_array(r.atlas); })
      .def_property_readonly("chart_of_face",
                             [](const AtlasOfMesh& r) { return vector_to_numpy<std::int32_t>(r.atlas.chart_of_face); })
      .def_property_readonly("charts",
                             [](const AtlasOfMesh& r) {
                               py::list charts;
                               for (const AtlasChart& chart : r.atlas.charts) charts.append(chart_dict(chart));
                               return charts;
                             })
      .def_property_readonly("metrics", [](const AtlasOfMesh& r) { return metrics_dict(r.atlas.metrics); })
      .def_property_readonly("report", [](const AtlasOfMesh& r) { return report_dict(r.atlas.report); })
      .def_property_readonly("resolution", [](const AtlasOfMesh& r) { return r.atlas.resolution; })
      .def_property_readonly("height", [](const AtlasOfMesh& r) { return r.atlas.height_texels(); })
      .def_property_readonly("pages", [](const AtlasOfMesh& r) { return r.atlas.pages; })
      .def_property_readonly("page_of_face",
                             [](const AtlasOfMesh& r) {
                               std::vector<int> pages = page_of_face(r.atlas);
                               if (pages.empty()) {  // one page: 0 for every face in a chart
                                 pages.resize(r.atlas.chart_of_face.size());
                                 for (std::size_t f = 0; f < pages.size(); ++f) pages[f] = r.atlas.chart_of_face[f] < 0 ? -1 : 0;
                               }
                               return vector_to_numpy<std::int32_t>(pages);
                             })
      .def_property_readonly("welded_vertices", [](const AtlasOfMesh& r) { return r.atlas.welded_vertices; })
      .def("xatlas_form", &xatlas_form)
      .def(
          "write_obj",
          [](const AtlasOfMesh& r, const std::string& path) {
            const py::gil_scoped_release released;
            write_atlas_obj(path, r.mesh, r.atlas);
          },
          py::arg("path"))
      .def(
          "write_picture",
          [](const AtlasOfMesh& r, const std::string& path, int width, int height, const std::string& title) {
            AtlasPictureOptions options;
            options.width = width;
            options.height = height;
            options.title = title;
            const py::gil_scoped_release released;
            write_atlas_picture(path, r.mesh, r.atlas, options);
          },
          py::arg("path"), py::arg("width"), py::arg("height"), py::arg("title"));
  module.def("texture_atlas", &make_atlas, py::arg("positions"), py::arg("faces"), py::kw_only(),
             py::arg("resolution"), py::arg("padding"), py::arg("max_distortion"), py::arg("max_normal_deviation"),
             py::arg("keep_splits"), py::arg("threads"), py::arg("backend"), py::arg("device"),
             py::arg("progress"), py::arg("cancel"), py::arg("texels_per_unit") = 0.0,
             py::arg("join_charts") = false, py::arg("max_pages") = 0, py::arg("height") = 0);
  module.def("repack_atlas", &make_repack, py::arg("positions"), py::arg("faces"), py::arg("corner_uv"), py::kw_only(),
             py::arg("resolution"), py::arg("padding"), py::arg("threads"), py::arg("texels_per_unit"),
             py::arg("max_pages") = 0, py::arg("height") = 0);
}

}  // namespace harmonia::python
