// The texture atlas of a mesh (harmonia/texture_atlas.h): segmentation, charts made disks and
// flattened on a pool of threads (split in two where they are not disks or do not flatten within
// the limit), packing, and the atlas' figures.
#include "harmonia/texture_atlas.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include <Eigen/Geometry>

#include "atlas/atlas_metrics.h"
#include "atlas/chart_flattening.h"
#include "atlas/chart_mesh.h"
#include "atlas/chart_packing.h"
#include "atlas/chart_segmentation.h"
#include "atlas/face_geometry.h"
#include "fallback/single_threaded_blas.h"
#include "harmonia/topology.h"
#include "planar/map_pipeline.h"

namespace harmonia {

std::string_view to_string(ChartMethod method) {
  switch (method) {
    case ChartMethod::single_triangle: return "single_triangle";
    case ChartMethod::linear_abf: return "linear_abf";
    case ChartMethod::free_boundary: return "free_boundary";
    case ChartMethod::tutte: return "tutte";
    case ChartMethod::degenerate: return "degenerate";
  }
  return "unknown";
}

namespace {

constexpr double kDegree = M_PI / 180.0;

// A chart that is done: its faces (increasing), its copy of their vertices and their layout.
struct FinishedChart {
  detail::ChartMesh mesh;
  detail::FlattenedChart layout;
};

std::string option_problem(const TextureAtlasOptions& options) {
  if (options.resolution < 16 || options.resolution > 32768)
    return "resolution " + std::to_string(options.resolution) + " is outside [16, 32768]";
  if (options.padding < 0 || options.padding > 64)
    return "padding " + std::to_string(options.padding) + " is outside [0, 64]";
  if (2 * options.padding + 1 > options.resolution)
    return "padding " + std::to_string(options.padding) + " leaves no texel of a " +
           std::to_string(options.resolution) + " atlas";
  if (!(options.max_distortion > 1.0)) return "max_distortion must be greater than 1";
  if (!(options.max_normal_deviation_degrees >= 1.0 && options.max_normal_deviation_degrees <= 89.0))
    return "max_normal_deviation_degrees must lie in [1, 89]";
  if (options.threads < 0) return "threads must not be negative";
  return {};
}

// Makes every chart a disk and flattens it, on `threads` workers sharing one queue of face sets.
// A set that is not a disk, or that no method flattens within the limit, is split in two and
// both halves queued again. Each set's outcome depends only on the set, so the charts are the
// same whatever the threads' timing; they are sorted by their first face at the end.
class ChartWorkshop {
 public:
  ChartWorkshop(const Mesh& surface, const detail::FaceGeometry& geometry, double max_stretch,
                SolverOptions solver)
      : surface_(surface), geometry_(geometry), max_stretch_(max_stretch), solver_(std::move(solver)) {
    solver_.progress = nullptr;  // the atlas reports its own phases
  }

  std::vector<FinishedChart> run(std::vector<std::vector<int>> face_sets, int threads) {
    for (std::vector<int>& faces : face_sets) queue_.push_back(std::move(faces));
    pending_ = queue_.size();
    // Charts factorized side by side would queue for OpenBLAS's one pool and spin: its calls are
    // held to one thread meanwhile where the caller's policy allows (harmonia/blas_threads.h).
    std::optional<detail::SingleThreadedBlas> single_threaded_blas;
    if (threads > 1 && detail::SingleThreadedBlas::allowed()) single_threaded_blas.emplace();
    std::vector<std::thread> workers;
    for (int t = 1; t < threads; ++t) workers.emplace_back([this] { work(); });
    work();
    for (std::thread& worker : workers) worker.join();
    std::sort(finished_.begin(), finished_.end(), [](const FinishedChart& a, const FinishedChart& b) {
      return a.mesh.surface_face.front() < b.mesh.surface_face.front();
    });
    return std::move(finished_);
  }

 private:
  void work() {
    for (;;) {
      std::vector<int> faces;
      {
        std::unique_lock lock(mutex_);
        ready_.wait(lock, [this] { return !queue_.empty() || pending_ == 0; });
        if (queue_.empty()) return;
        faces = std::move(queue_.front());
        queue_.pop_front();
      }
      std::vector<std::vector<int>> halves;
      std::optional<FinishedChart> done = make_chart(faces, halves);
      std::lock_guard lock(mutex_);
      if (done) finished_.push_back(std::move(*done));
      for (std::vector<int>& half : halves) {
        queue_.push_back(std::move(half));
        ++pending_;
      }
      --pending_;
      ready_.notify_all();
    }
  }

  std::optional<FinishedChart> make_chart(const std::vector<int>& faces,
                                          std::vector<std::vector<int>>& halves) const {
    detail::ChartMesh mesh = detail::chart_mesh(surface_, geometry_, faces);
    if (!detail::is_disk(mesh))
      if (std::optional<detail::ChartMesh> opened = detail::cut_holes_open(surface_, geometry_, mesh))
        mesh = std::move(*opened);
    if (detail::is_disk(mesh)) {
      if (std::optional<detail::FlattenedChart> layout = detail::flatten_chart(mesh, max_stretch_, solver_))
        return FinishedChart{std::move(mesh), std::move(*layout)};
    }
    halves = detail::split_in_two(geometry_, faces);
    return std::nullopt;
  }

  const Mesh& surface_;
  const detail::FaceGeometry& geometry_;
  const double max_stretch_;
  SolverOptions solver_;
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<std::vector<int>> queue_;
  std::size_t pending_ = 0;  // queued or being worked on
  std::vector<FinishedChart> finished_;
};

struct NormalizedMesh {
  Mesh mesh;
  double size = 1.0;  // the model's largest bounding-box side
};

// The mesh moved to the corner of its bounding box at the origin and divided by its largest side.
NormalizedMesh normalized_to_size(const Mesh& input) {
  NormalizedMesh normalized{input, 1.0};
  if (input.vertices.rows() == 0) return normalized;
  const Eigen::RowVector3d lowest = input.vertices.colwise().minCoeff();
  const double size = (input.vertices.colwise().maxCoeff() - lowest).maxCoeff();
  if (!(size > 0.0) || !std::isfinite(size)) return normalized;
  normalized.mesh.vertices = (input.vertices.rowwise() - lowest) / size;
  normalized.size = size;
  return normalized;
}

int worker_count(int requested) {
  if (requested > 0) return requested;
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

// Every face the segmentation leaves out (FaceGeometry::degenerate) as a chart of its own: laid
// out exactly when it has an area, else drawn as a small valid triangle.
void add_degenerate_faces(const Mesh& surface, const detail::FaceGeometry& geometry, double max_stretch,
                          const SolverOptions& solver, std::vector<FinishedChart>& charts) {
  for (int f = 0; f < geometry.face_count(); ++f) {
    if (!geometry.degenerate[static_cast<std::size_t>(f)]) continue;
    FinishedChart chart;
    chart.mesh.surface_face = {f};
    chart.mesh.mesh.faces = Eigen::RowVector3i(0, 1, 2);
    chart.mesh.mesh.vertices.resize(3, 3);
    for (int k = 0; k < 3; ++k) {
      chart.mesh.surface_vertex.push_back(surface.faces(f, k));
      chart.mesh.mesh.vertices.row(k) = surface.vertices.row(surface.faces(f, k));
    }
    std::optional<detail::FlattenedChart> exact = detail::flatten_chart(chart.mesh, max_stretch, solver);
    chart.layout = exact ? std::move(*exact) : detail::degenerate_face_layout(surface, f);
    charts.push_back(std::move(chart));
  }
  std::sort(charts.begin(), charts.end(), [](const FinishedChart& a, const FinishedChart& b) {
    return a.mesh.surface_face.front() < b.mesh.surface_face.front();
  });
}

// Each chart's triangles, corner by corner, as the packer takes them.
std::vector<Eigen::MatrixX2d> chart_triangles(const std::vector<FinishedChart>& charts) {
  std::vector<Eigen::MatrixX2d> triangles;
  triangles.reserve(charts.size());
  for (const FinishedChart& chart : charts) {
    const Mesh& mesh = chart.mesh.mesh;
    Eigen::MatrixX2d corners(3 * mesh.faces.rows(), 2);
    for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
      for (int k = 0; k < 3; ++k) corners.row(3 * f + k) = chart.layout.uv.row(mesh.faces(f, k));
    triangles.push_back(std::move(corners));
  }
  return triangles;
}

// The atlas from the placed charts: per-face corner UVs in [0, 1] and each chart's record.
void place_charts(const std::vector<FinishedChart>& charts, const detail::ChartPacking& packing,
                  int resolution, int face_count, TextureAtlas& atlas) {
  atlas.resolution = resolution;
  atlas.corner_uv.resize(face_count, 6);
  atlas.chart_of_face.assign(static_cast<std::size_t>(face_count), -1);
  atlas.charts.resize(charts.size());
  for (std::size_t c = 0; c < charts.size(); ++c) {
    const FinishedChart& chart = charts[c];
    const detail::ChartPlacement& placement = packing.placements[c];
    const Eigen::Matrix2d turn = Eigen::Rotation2Dd(placement.angle).toRotationMatrix();
    AtlasChart& record = atlas.charts[c];
    record.faces = chart.mesh.surface_face;
    record.method = chart.layout.method;
    const Mesh& mesh = chart.mesh.mesh;
    for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
      const int face = chart.mesh.surface_face[static_cast<std::size_t>(f)];
      atlas.chart_of_face[static_cast<std::size_t>(face)] = static_cast<int>(c);
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector2d corner = chart.layout.uv.row(mesh.faces(f, k)).transpose();
        const Eigen::Vector2d texel = packing.texels_per_unit * (turn * corner) + placement.offset;
        record.texel_box.extend(texel);
        atlas.corner_uv.block<1, 2>(face, 2 * k) = texel.transpose() / resolution;
      }
    }
  }
}

}  // namespace

TextureAtlas texture_atlas(const Mesh& input, const TextureAtlasOptions& options) {
  TextureAtlas atlas;
  SolveReport& report = atlas.report;
  detail::PhaseClock clock(report, options.solver.progress);
  if (!clock.start("validation")) return atlas;
  std::string problem;
  if (check_indices_and_coordinates(input, &problem) != Status::ok || !(problem = option_problem(options)).empty()) {
    report.status = Status::invalid_input;
    report.message = "texture atlas: " + problem;
    return atlas;
  }
  if (input.faces.rows() == 0) {
    report.status = Status::invalid_input;
    report.message = "texture atlas: the mesh has no faces";
    return atlas;
  }
  // Computed on a copy normalized to its size (bounding box from the origin, largest side 1), so
  // that every figure is relative to the model: the same charts at any scale.
  const NormalizedMesh normalized = normalized_to_size(input);
  const Mesh& surface = normalized.mesh;
  if (!clock.start("segmentation")) return atlas;
  const detail::FaceGeometry geometry = detail::face_geometry(surface);
  detail::SegmentationOptions segmentation_options;
  segmentation_options.max_normal_deviation = options.max_normal_deviation_degrees * kDegree;
  const detail::Segmentation segmentation = detail::segment_into_charts(geometry, segmentation_options);
  std::vector<std::vector<int>> face_sets(static_cast<std::size_t>(segmentation.chart_count));
  for (int f = 0; f < geometry.face_count(); ++f)
    if (const int chart = segmentation.chart_of_face[static_cast<std::size_t>(f)]; chart >= 0)
      face_sets[static_cast<std::size_t>(chart)].push_back(f);
  if (!clock.start("flattening")) return atlas;
  SolverOptions solver = options.solver;
  if (solver.backend == BackendChoice::automatic) solver.backend = BackendChoice::cpu;  // small systems
  std::vector<FinishedChart> charts = ChartWorkshop(surface, geometry, options.max_distortion, solver)
                                          .run(std::move(face_sets), worker_count(options.threads));
  add_degenerate_faces(surface, geometry, options.max_distortion, solver, charts);
  if (!clock.start("packing")) return atlas;
  detail::PackingOptions packing_options;
  packing_options.resolution = options.resolution;
  packing_options.padding = options.padding;
  detail::ChartPacking packing;
  try {
    packing = detail::pack_charts(chart_triangles(charts), packing_options);
  } catch (const Error& error) {  // more charts than the resolution can hold with this padding
    report.status = error.status();
    report.message = std::string("texture atlas: ") + error.what() +
                     " (a larger resolution or a smaller padding leaves room for them)";
    return atlas;
  }
  place_charts(charts, packing, options.resolution, input.face_count(), atlas);
  if (!clock.start("metrics")) return atlas;
  // Chart layouts are in the normalized copy's lengths: per unit of the model, 1/size as many texels.
  // measure_atlas also gives each chart its figures, measured in the model's own units.
  atlas.metrics = detail::measure_atlas(input, atlas);
  atlas.metrics.texels_per_unit = packing.texels_per_unit / normalized.size;
  clock.stop();
  return atlas;
}

}  // namespace harmonia
