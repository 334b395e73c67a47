// The texture atlas of a mesh (harmonia/texture_atlas.h): segmentation, charts made disks and
// flattened on a pool of threads (split in two where they are not disks or do not flatten within
// the limit), packing, and the atlas' figures. When the solver options give a device (Vulkan, or
// automatic with a hardware GPU), the segmentation's charts that are disks first get linear
// ABF's first round solved together, a few hundred reduced angle systems per block-diagonal PCG
// (abf/linear_abf_batch.h); the pool then judges those results as it judges its own. On the CPU
// each chart's system is factorized directly, which no batch beats, and nothing is batched.
#include "harmonia/texture_atlas.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>

#include <Eigen/Geometry>

#include "abf/linear_abf_batch.h"
#include "atlas/atlas_metrics.h"
#include "atlas/chart_flattening.h"
#include "atlas/chart_mesh.h"
#include "atlas/chart_packing.h"
#include "atlas/chart_segmentation.h"
#include "atlas/flat_fold_merge.h"
#include "atlas/input_charts.h"
#include "atlas/face_geometry.h"
#include "atlas/long_chart_cut.h"
#include "atlas/stretch_bounded_join.h"
#include "atlas/zero_area_faces.h"
#include "fallback/single_threaded_blas.h"
#include "harmonia/topology.h"
#include "mesh/coincident_vertices.h"
#include "mesh/for_each_index.h"
#include "mesh/helper_tasks.h"
#include "planar/boundary_crossings.h"
#include "planar/map_pipeline.h"
#include "solve/backend_selection.h"

namespace harmonia {

std::string_view to_string(ChartMethod method) {
  switch (method) {
    case ChartMethod::single_triangle: return "single_triangle";
    case ChartMethod::linear_abf: return "linear_abf";
    case ChartMethod::relaxed_linear_abf: return "relaxed_linear_abf";
    case ChartMethod::free_boundary: return "free_boundary";
    case ChartMethod::tutte: return "tutte";
    case ChartMethod::degenerate: return "degenerate";
    case ChartMethod::input_layout: return "input_layout";
    case ChartMethod::projection: return "projection";
  }
  return "unknown";
}

namespace {

constexpr double kDegree = M_PI / 180.0;


// A face set for the workshop, with what was computed for it already: its chart mesh (made a
// disk where it could be) and its linear ABF result (the batched first round on a device).
struct ChartJob {
  std::vector<int> faces;
  std::optional<detail::ChartMesh> mesh;
  std::optional<AngleMapResult> linear_abf;
};


std::string option_problem(const TextureAtlasOptions& options) {
  if (options.resolution < 16 || options.resolution > 32768)
    return "resolution " + std::to_string(options.resolution) + " is outside [16, 32768]";
  if (options.height != 0 && (options.height < 16 || options.height > 32768))
    return "height " + std::to_string(options.height) + " is outside [16, 32768] (0: a square atlas)";
  const int height = options.height > 0 ? options.height : options.resolution;
  if (options.padding < 0 || options.padding > 64)
    return "padding " + std::to_string(options.padding) + " is outside [0, 64]";
  if (2 * detail::atlas_edge_margin(options.padding) + 1 > std::min(options.resolution, height))
    return "padding " + std::to_string(options.padding) + " leaves no texel of a " +
           std::to_string(options.resolution) + " x " + std::to_string(height) + " atlas";
  if (!(options.max_distortion > 1.0)) return "max_distortion must be greater than 1";
  if (!(options.max_normal_deviation_degrees >= 1.0 && options.max_normal_deviation_degrees <= 89.0))
    return "max_normal_deviation_degrees must lie in [1, 89]";
  if (options.threads < 0) return "threads must not be negative";
  if (!(options.texels_per_unit >= 0.0) || !std::isfinite(options.texels_per_unit))
    return "texels_per_unit must be finite and not negative";
  if (options.max_pages < 0) return "max_pages must not be negative";
  return {};
}

// Makes every chart a disk and flattens it, on `threads` workers sharing one queue of face sets.
// A set that is not a disk, or that no method flattens within the limit, is split in two and
// both halves queued again (or handed back, for the device's next batch). Each set's outcome
// depends only on the set, so the charts are the same whatever the threads' timing; they are
// sorted by their first face at the end.
class ChartWorkshop {
 public:
  // `solver.progress` (if any) hears, after each chart, how many of the surface's faces lie in
  // finished charts (stage "flattening"), and may cancel: the workers then take no new chart.
  ChartWorkshop(const Mesh& surface, const detail::FaceGeometry& geometry, double max_stretch,
                SolverOptions solver)
      : surface_(surface), geometry_(geometry), max_stretch_(max_stretch), solver_(std::move(solver)) {
    progress_ = std::move(solver_.progress);
    // A chart's own solves report no phases of their own (the atlas reports its phases), but
    // they ask whether to go on, so that a cancel stops a large chart's solve too.
    if (progress_) solver_.progress = [this](const Progress&) { return report_progress(); };
  }

  // Works through `jobs` and the halves of every one that is split, on `threads` threads; with
  // `split_off`, the halves are handed back there (in any order) instead. Returns false when the
  // progress callback cancelled (the charts finished so far are kept, the rest dropped).
  [[nodiscard]] bool run(std::vector<ChartJob> jobs, int threads,
                         std::vector<std::vector<int>>* split_off = nullptr) {
    if (cancelled_) return false;
    for (ChartJob& job : jobs) queue_.emplace(job.faces.size(), std::move(job));
    pending_ = queue_.size();
    split_off_ = split_off;
    // Charts factorized side by side would queue for OpenBLAS's one pool and spin: its calls are
    // held to one thread meanwhile where the caller's policy allows (harmonia/blas_threads.h).
    std::optional<detail::SingleThreadedBlas> single_threaded_blas;
    if (threads > 1 && detail::SingleThreadedBlas::allowed()) single_threaded_blas.emplace();
    std::vector<std::thread> workers;
    for (int t = 1; t < threads; ++t) workers.emplace_back([this] { work(); });
    work();
    for (std::thread& worker : workers) worker.join();
    return !cancelled_;
  }

  // The charts finished so far, sorted by their first face.
  std::vector<detail::FinishedChart> finished() {
    std::sort(finished_.begin(), finished_.end(), [](const detail::FinishedChart& a, const detail::FinishedChart& b) {
      return a.mesh.surface_face.front() < b.mesh.surface_face.front();
    });
    return std::move(finished_);
  }

 private:
  // Each chart's solves start helper tasks (an ordering beside the assembly, ...): run on the
  // worker itself, as the workers are the atlas' parallelism (and with one worker, the caller
  // asked for one thread).
  void work() {
    const detail::HelperTasksOnThisThread helper_tasks_here;
    for (;;) {
      ChartJob job;
      {
        std::unique_lock lock(mutex_);
        ready_.wait(lock, [this] { return !queue_.empty() || pending_ == 0 || cancelled_; });
        if (queue_.empty() || cancelled_) return;
        job = std::move(queue_.begin()->second);
        queue_.erase(queue_.begin());
      }
      std::vector<detail::FinishedChart> done;
      std::vector<ChartJob> pieces;
      make_chart(std::move(job), done, pieces);
      std::lock_guard lock(mutex_);
      for (detail::FinishedChart& chart : done) {
        finished_faces_ += chart.mesh.surface_face.size();
        finished_.push_back(std::move(chart));
      }
      report_progress_locked();
      for (ChartJob& piece : pieces) {
        if (split_off_ != nullptr) {
          split_off_->push_back(std::move(piece.faces));
          continue;
        }
        const std::size_t size = piece.faces.size();
        queue_.emplace(size, std::move(piece));
        ++pending_;
      }
      --pending_;
      ready_.notify_all();
    }
  }

  // Tells the progress callback how many faces lie in finished charts; false once it cancelled.
  // Under the lock, so that the callback is never called by two workers at once.
  bool report_progress() {
    const std::lock_guard lock(mutex_);
    return report_progress_locked();
  }
  bool report_progress_locked() {
    if (progress_ && !cancelled_ &&
        !progress_(Progress{"flattening", static_cast<int>(finished_faces_), static_cast<int>(surface_.faces.rows())}))
      cancelled_ = true;
    return !cancelled_;
  }

  // The chart of a job when it is a disk that flattens within the limit; else its pieces: the
  // two halves of a split, or, where linear ABF's layout crossed the chart's boundary, the
  // pieces of a cut between the crossing edges, each finished with its part of that layout when
  // that part is valid and within the limit, else to be flattened on its own.
  void make_chart(ChartJob job, std::vector<detail::FinishedChart>& done, std::vector<ChartJob>& pieces) const {
    // A chart with holes over a plane is laid out as it lies, not cut open (projected_layout).
    detail::ChartMesh plain = detail::chart_mesh(surface_, geometry_, job.faces);
    const bool plain_disk = detail::is_disk(plain);
    if (!plain_disk) {
      if (std::optional<detail::FlattenedChart> layout = detail::projected_layout(plain, max_stretch_)) {
        done.push_back(detail::FinishedChart{std::move(plain), std::move(*layout)});
        return;
      }
    }
    // Else the chart opened_chart makes (its holes cut open), unless the device's batch made it.
    if (!job.mesh && !plain_disk)
      if (std::optional<detail::ChartMesh> opened = detail::cut_holes_open(surface_, geometry_, plain))
        job.mesh = std::move(*opened);
    detail::ChartMesh mesh = job.mesh ? std::move(*job.mesh) : std::move(plain);
    if (!detail::is_disk(mesh)) {
      for (std::vector<int>& half : detail::split_in_two(geometry_, job.faces))
        pieces.push_back(ChartJob{std::move(half), std::nullopt, std::nullopt});
      return;
    }
    detail::ChartFlattening flattening =
        job.linear_abf ? detail::flatten_chart(mesh, max_stretch_, solver_, *job.linear_abf)
                       : detail::flatten_chart(mesh, max_stretch_, solver_);
    if (flattening.chart) {
      done.push_back(detail::FinishedChart{std::move(mesh), std::move(*flattening.chart)});
      return;
    }
    if (!flattening.crossing) {
      for (std::vector<int>& half : detail::split_in_two(geometry_, job.faces))
        pieces.push_back(ChartJob{std::move(half), std::nullopt, std::nullopt});
      return;
    }
    // Cut between the crossing edges; a piece whose part of the layout still crosses its boundary
    // is cut again, with no new solve, until its pieces are valid or fail otherwise.
    struct Cut {
      detail::ChartMesh mesh;
      detail::CrossingLayout crossing;
    };
    std::vector<Cut> to_cut;
    to_cut.push_back(Cut{std::move(mesh), std::move(*flattening.crossing)});
    while (!to_cut.empty()) {
      const Cut cut = std::move(to_cut.back());
      to_cut.pop_back();
      const std::vector<int>& faces = cut.mesh.surface_face;
      for (std::vector<int>& half : detail::split_between(geometry_, faces, faces[static_cast<std::size_t>(cut.crossing.faces[0])],
                                                          faces[static_cast<std::size_t>(cut.crossing.faces[1])])) {
        detail::ChartMesh piece = detail::opened_chart(surface_, geometry_, half);
        if (detail::is_disk(piece)) {
          detail::ChartFlattening restricted =
              detail::restricted_layout(cut.mesh, cut.crossing.uv, piece, ChartMethod::linear_abf, max_stretch_, &solver_);
          if (restricted.chart) {
            done.push_back(detail::FinishedChart{std::move(piece), std::move(*restricted.chart)});
            continue;
          }
          if (restricted.crossing) {
            to_cut.push_back(Cut{std::move(piece), std::move(*restricted.crossing)});
            continue;
          }
        }
        pieces.push_back(ChartJob{std::move(half), std::move(piece), std::nullopt});
      }
    }
  }

  const Mesh& surface_;
  const detail::FaceGeometry& geometry_;
  const double max_stretch_;
  SolverOptions solver_;
  std::mutex mutex_;
  std::condition_variable ready_;
  // Jobs waiting, largest face set first: the longest flattenings (and the halves of a large set
  // that was split) start early, so that the workers finish together. The charts do not depend on
  // the order.
  std::multimap<std::size_t, ChartJob, std::greater<>> queue_;
  std::size_t pending_ = 0;  // queued or being worked on
  std::vector<std::vector<int>>* split_off_ = nullptr;
  std::vector<detail::FinishedChart> finished_;
  ProgressCallback progress_;
  std::size_t finished_faces_ = 0;
  bool cancelled_ = false;  // guarded by mutex_
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

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The faces of `mesh` (normalized to its size) on one vertex per point: each vertex within
// kCoincidentVertexTolerance of an earlier one replaced by the earliest (the positions and the face
// order stay; the replaced vertices are left unused). Returns how many were replaced.
int weld_coincident_vertices(Mesh& mesh) {
  const std::vector<int> representative =
      detail::coincident_vertex_representatives(mesh.vertices, kCoincidentVertexTolerance);
  int welded = 0;
  for (std::size_t v = 0; v < representative.size(); ++v) welded += representative[v] != static_cast<int>(v);
  if (welded == 0) return 0;
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) mesh.faces(f, k) = representative[static_cast<std::size_t>(mesh.faces(f, k))];
  return welded;
}

int worker_count(int requested) {
  if (requested > 0) return requested;
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

// Rounds of splitting the charts whose boundary crosses itself once placed, and packing again: a
// safety net under the flattening's clearance (each round halves such charts).
constexpr int kPlacementRepairRounds = 8;

// The device pass' batches: at most this many charts, and about this many rows of reduced angle
// systems (two per interior vertex, counted as two per chart vertex), per solve.
constexpr std::size_t kBatchCharts = 256;
constexpr std::size_t kBatchRows = std::size_t{1} << 20;

// The backend of the device pass: `solver`'s choice (automatic: a hardware GPU), or nothing where
// that is the CPU (which factorizes each chart's system directly, faster than any batch). Where
// no backend can be made, `notice` says why: for an explicit device choice the atlas is then
// refused (the caller asked for the device), for `automatic` it runs on the CPU and reports why.
// Whether the atlas of a mesh of `faces` faces looks for a device (kSmallestAtlasForDevice).
bool looks_for_device(const SolverOptions& solver, Eigen::Index faces) {
  return solver.backend == BackendChoice::vulkan ||
         (solver.backend == BackendChoice::automatic && faces >= kSmallestAtlasForDevice);
}

std::unique_ptr<detail::Backend> device_backend(const SolverOptions& solver, Eigen::Index faces,
                                                std::string& notice) {
  if (solver.backend == BackendChoice::cpu) return nullptr;
  if (!looks_for_device(solver, faces)) {
    notice = "cpu: " + std::to_string(faces) + " faces, fewer than the " + std::to_string(kSmallestAtlasForDevice) +
             " at which the atlas looks for a device (finding and starting one would take longer than the atlas)";
    return nullptr;
  }
  std::unique_ptr<detail::Backend> backend = detail::make_backend(solver, &notice);
  if (backend && backend->kind() == BackendKind::cpu) backend.reset();
  return backend;
}

struct BatchedFirstRounds {
  std::vector<ChartJob> jobs;
  int charts = 0;        // Charts whose first round was solved in a batch.
  int final_rounds = 0;  // Of them, those whose batched round is their linear ABF result.
  int batches = 0;
  std::string failure;   // Why a batch was given up (a device error), if one was.
  bool cancelled = false;
};

// The face sets as workshop jobs, each with its chart mesh, and every disk of two faces or more
// with its linear ABF result where the batched first round is final (abf/linear_abf_batch.h): the
// charts' reduced angle systems solved together on `device`, a batch at a time. The workshop
// judges those results as flatten_chart judges its own and computes the others as it would
// without a device (linear ABF on `solver`'s backend, then the rest of the chain, or a split).
// `progress` (if any) hears of each batch (stage "batched linear abf", charts done) and may
// cancel between batches.
BatchedFirstRounds batch_first_rounds(const Mesh& surface, const detail::FaceGeometry& geometry,
                                      std::vector<std::vector<int>> face_sets,
                                      const SolverOptions& solver, detail::Backend& device,
                                      int threads, const ProgressCallback& progress) {
  BatchedFirstRounds batched;
  batched.jobs.resize(face_sets.size());
  detail::for_each_index(face_sets.size(), threads, [&](std::size_t i) {
    ChartJob& job = batched.jobs[i];
    job.faces = std::move(face_sets[i]);
    job.mesh = detail::opened_chart(surface, geometry, job.faces);
  });
  std::vector<std::size_t> candidates;
  for (std::size_t i = 0; i < batched.jobs.size(); ++i)
    if (const detail::ChartMesh& mesh = *batched.jobs[i].mesh;
        mesh.mesh.faces.rows() > 1 && detail::is_disk(mesh))
      candidates.push_back(i);
  // flatten_chart's, so that the results are judged alike
  LinearAbfOptions options = detail::chart_linear_abf_options(solver);
  options.solver_options.progress = nullptr;
  for (std::size_t first = 0; first < candidates.size();) {
    if (progress && !progress(Progress{"batched linear abf", batched.charts,
                                       static_cast<int>(candidates.size())})) {
      batched.cancelled = true;
      break;
    }
    std::vector<const Mesh*> meshes;
    std::size_t rows = 0, last = first;
    for (; last < candidates.size() && meshes.size() < kBatchCharts; ++last) {
      const Mesh& mesh = batched.jobs[candidates[last]].mesh->mesh;
      const auto chart_rows = static_cast<std::size_t>(2 * mesh.vertices.rows());
      if (!meshes.empty() && rows + chart_rows > kBatchRows) break;
      meshes.push_back(&mesh);
      rows += chart_rows;
    }
    std::vector<std::optional<AngleMapResult>> results;
    try {
      results = detail::linear_abf_first_rounds(meshes, options, device, threads);
    } catch (const Error& error) {  // a device lost or out of memory: the charts go one by one
      batched.failure = error.what();
      break;
    }
    for (std::size_t k = 0; k < meshes.size(); ++k) {
      if (!results[k]) continue;
      batched.jobs[candidates[first + k]].linear_abf = std::move(*results[k]);
      ++batched.final_rounds;
    }
    batched.charts += static_cast<int>(meshes.size());
    ++batched.batches;
    first = last;
  }
  return batched;
}

// Every face the segmentation leaves out (FaceGeometry::degenerate) that touches no face of area
// (`host_of_face` -1; the others are drawn inside their host's chart, zero_area_faces.h) as a
// chart of its own: laid out exactly when it has an area, else drawn as a small valid triangle.
void add_degenerate_faces(const Mesh& surface, const detail::FaceGeometry& geometry,
                          const std::vector<int>& host_of_face, double max_stretch, const SolverOptions& solver,
                          std::vector<detail::FinishedChart>& charts) {
  for (int f = 0; f < geometry.face_count(); ++f) {
    if (!geometry.degenerate[static_cast<std::size_t>(f)] || host_of_face[static_cast<std::size_t>(f)] >= 0) continue;
    detail::FinishedChart chart;
    chart.mesh.surface_face = {f};
    chart.mesh.mesh.faces = Eigen::RowVector3i(0, 1, 2);
    chart.mesh.mesh.vertices.resize(3, 3);
    for (int k = 0; k < 3; ++k) {
      chart.mesh.surface_vertex.push_back(surface.faces(f, k));
      chart.mesh.mesh.vertices.row(k) = surface.vertices.row(surface.faces(f, k));
    }
    detail::ChartFlattening flattening = detail::flatten_chart(chart.mesh, max_stretch, solver);
    if (flattening.chart)
      chart.layout = std::move(*flattening.chart);
    else
      chart.layout = detail::degenerate_face_layout(surface, f);
    charts.push_back(std::move(chart));
  }
  std::sort(charts.begin(), charts.end(), [](const detail::FinishedChart& a, const detail::FinishedChart& b) {
    return a.mesh.surface_face.front() < b.mesh.surface_face.front();
  });
}

// Each chart's triangles, corner by corner, as the packer takes them.
std::vector<Eigen::MatrixX2d> chart_triangles(const std::vector<detail::FinishedChart>& charts) {
  std::vector<Eigen::MatrixX2d> triangles;
  triangles.reserve(charts.size());
  for (const detail::FinishedChart& chart : charts) {
    const Mesh& mesh = chart.mesh.mesh;
    Eigen::MatrixX2d corners(3 * mesh.faces.rows(), 2);
    for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
      for (int k = 0; k < 3; ++k) corners.row(3 * f + k) = chart.layout.uv.row(mesh.faces(f, k));
    triangles.push_back(std::move(corners));
  }
  return triangles;
}

// The atlas from the placed charts: per-face corner UVs in [0, 1] and each chart's record.
// A chart's vertices where the atlas puts them, in texels: its layout turned, scaled and shifted.
Eigen::MatrixX2d placed_texels(const detail::FinishedChart& chart, const detail::ChartPlacement& placement,
                               double texels_per_unit) {
  const Eigen::Matrix2d turn = Eigen::Rotation2Dd(placement.angle).toRotationMatrix();
  Eigen::MatrixX2d texels(chart.layout.uv.rows(), 2);
  for (Eigen::Index v = 0; v < texels.rows(); ++v) {
    const Eigen::Vector2d corner = chart.layout.uv.row(v).transpose();
    texels.row(v) = (texels_per_unit * (turn * corner) + placement.offset).transpose();
  }
  return texels;
}

// The same over the atlas' sides, in [0, 1]: the UVs the atlas gives the chart's corners.
Eigen::MatrixX2d placed_layout(const detail::FinishedChart& chart, const detail::ChartPlacement& placement,
                               double texels_per_unit, const Eigen::Array2d& size) {
  return (placed_texels(chart, placement, texels_per_unit).array().rowwise() / size.transpose()).matrix();
}

// The atlas' width and height in texels.
Eigen::Array2d atlas_size(const TextureAtlasOptions& options) {
  return {static_cast<double>(options.resolution), static_cast<double>(options.height > 0 ? options.height : options.resolution)};
}

// The charts whose boundary, as placed in the atlas, crosses or touches itself. The flattening
// keeps every boundary clear of itself by far more than rounding (chart_flattening.cpp); this is
// the check that the placement's rounding kept it so, whatever the chart.
std::vector<std::size_t> charts_crossing_once_placed(const std::vector<detail::FinishedChart>& charts,
                                                     const detail::ChartPacking& packing, const Eigen::Array2d& size) {
  std::vector<std::size_t> crossing;
  for (std::size_t c = 0; c < charts.size(); ++c)
    if (detail::first_boundary_crossing(
            placed_layout(charts[c], packing.placements[c], packing.texels_per_unit, size),
            charts[c].mesh.mesh.faces))
      crossing.push_back(c);
  return crossing;
}

void place_charts(const std::vector<detail::FinishedChart>& charts, const detail::ChartPacking& packing,
                  const Eigen::Array2d& size, int face_count, TextureAtlas& atlas) {
  atlas.resolution = static_cast<int>(size.x());
  atlas.height = static_cast<int>(size.y());
  atlas.pages = packing.pages;
  atlas.corner_uv.resize(face_count, 6);
  atlas.chart_of_face.assign(static_cast<std::size_t>(face_count), -1);
  atlas.charts.resize(charts.size());
  for (std::size_t c = 0; c < charts.size(); ++c) {
    const detail::FinishedChart& chart = charts[c];
    const Eigen::MatrixX2d texels = placed_texels(chart, packing.placements[c], packing.texels_per_unit);
    AtlasChart& record = atlas.charts[c];
    record.faces = chart.mesh.surface_face;
    record.method = chart.layout.method;
    record.piece_of_a_cut = chart.layout.piece_of_a_cut;
    record.page = packing.placements[c].page;
    const Mesh& mesh = chart.mesh.mesh;
    for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
      const int face = chart.mesh.surface_face[static_cast<std::size_t>(f)];
      atlas.chart_of_face[static_cast<std::size_t>(face)] = static_cast<int>(c);
      for (int k = 0; k < 3; ++k) {
        const Eigen::RowVector2d texel = texels.row(mesh.faces(f, k));
        record.texel_box.extend(texel.transpose());
        atlas.corner_uv.block<1, 2>(face, 2 * k) = (texel.array() / size.transpose()).matrix();
      }
    }
  }
}

// `atlas` emptied and marked cancelled at `phase` (nothing of a cancelled atlas is kept).
TextureAtlas& cancelled(TextureAtlas& atlas, std::string_view phase) {
  SolveReport report = std::move(atlas.report);
  atlas = TextureAtlas{};
  atlas.report = std::move(report);
  atlas.report.status = Status::cancelled;
  atlas.report.message = "cancelled by the progress callback at \"" + std::string(phase) + "\"";
  return atlas;
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
  NormalizedMesh normalized = normalized_to_size(input);
  if (!options.keep_splits) atlas.welded_vertices = weld_coincident_vertices(normalized.mesh);
  const Mesh& surface = normalized.mesh;
  if (!clock.start("segmentation")) return atlas;
  // Not const: the joining of charts below cuts some edges (across them no chart grows).
  detail::FaceGeometry geometry = detail::face_geometry(surface, worker_count(options.threads));
  detail::SegmentationOptions segmentation_options;
  segmentation_options.max_normal_deviation = options.max_normal_deviation_degrees * kDegree;
  segmentation_options.progress = options.solver.progress;
  detail::Segmentation segmentation = detail::segment_into_charts(geometry, segmentation_options);
  if (segmentation.cancelled) return cancelled(atlas, "segmentation");
  detail::merge_across_flat_folds(surface, geometry, detail::joining_cone(segmentation_options), segmentation);
  std::vector<std::vector<int>> face_sets(static_cast<std::size_t>(segmentation.chart_count));
  for (int f = 0; f < geometry.face_count(); ++f)
    if (const int chart = segmentation.chart_of_face[static_cast<std::size_t>(f)]; chart >= 0)
      face_sets[static_cast<std::size_t>(chart)].push_back(f);
  SolverOptions solver = options.solver;
  if (solver.backend == BackendChoice::automatic) solver.backend = BackendChoice::cpu;  // small systems
  const int threads = worker_count(options.threads);
  std::string backend_notice;
  if (looks_for_device(options.solver, surface.faces.rows()) && !clock.start("device")) return atlas;
  std::unique_ptr<detail::Backend> device = device_backend(options.solver, surface.faces.rows(), backend_notice);
  if (!device && options.solver.backend == BackendChoice::vulkan) {
    report.status = Status::unsupported;
    report.message = "texture atlas: " + backend_notice;
    return atlas;
  }
  report.backend_notice = backend_notice;  // e.g. why `automatic` ran on the CPU
  ChartWorkshop workshop(surface, geometry, options.max_distortion, solver);
  if (device) {
    // On a device, the first linear ABF rounds of all charts that are disks are solved together,
    // a few hundred charts per block-diagonal solve, in waves: the segmentation's charts, then
    // the halves of those the workshop split, and so on. The workshop judges each wave's results
    // and flattens one by one what a batch did not finish.
    clock.stop();
    const ProgressCallback& progress = options.solver.progress;
    double batch_seconds = 0.0, workshop_seconds = 0.0;
    int charts = 0, final_rounds = 0, batches = 0, waves = 0;
    std::vector<std::vector<int>> wave = std::move(face_sets);
    bool batching = true;
    while (!wave.empty()) {
      if (!batching) {  // a batch failed on the device: the rest goes one by one
        std::vector<ChartJob> jobs;
        for (std::vector<int>& faces : wave)
          jobs.push_back(ChartJob{std::move(faces), std::nullopt, std::nullopt});
        wave.clear();
        const auto started = std::chrono::steady_clock::now();
        const bool finished = workshop.run(std::move(jobs), threads);
        workshop_seconds += seconds_since(started);
        if (!finished) return cancelled(atlas, "flattening");
        break;
      }
      const auto started = std::chrono::steady_clock::now();
      BatchedFirstRounds batched = batch_first_rounds(surface, geometry, std::move(wave), solver,
                                                      *device, threads, progress);
      wave.clear();
      const auto batched_at = std::chrono::steady_clock::now();
      batch_seconds += seconds_since(started);
      if (batched.cancelled) return cancelled(atlas, "batched linear abf");
      charts += batched.charts;
      final_rounds += batched.final_rounds;
      batches += batched.batches;
      ++waves;
      if (!batched.failure.empty()) {
        batching = false;
        report.fallbacks.push_back("a batched device solve failed (" + batched.failure +
                                   "): the remaining charts were flattened one by one");
      }
      if (!workshop.run(std::move(batched.jobs), threads, &wave)) return cancelled(atlas, "flattening");
      // The halves come back in the threads' order; the next wave's batches must not depend on it.
      std::sort(wave.begin(), wave.end(), [](const std::vector<int>& a, const std::vector<int>& b) {
        return *std::min_element(a.begin(), a.end()) < *std::min_element(b.begin(), b.end());
      });
      workshop_seconds += seconds_since(batched_at);
    }
    report.backend = device->kind();
    report.device = device->description();
    if (device->kind() == BackendKind::vulkan) report.precision = "float (refined in double)";
    report.solver = "linear abf first rounds by block-pcg-jacobi (reduced) on the device: " +
                    std::to_string(charts) + " charts in " + std::to_string(batches) +
                    " batch(es) over " + std::to_string(waves) + " wave(s) of splits, " +
                    std::to_string(final_rounds) + " final";
    report.timings.push_back(PhaseTiming{"batched linear abf", batch_seconds});
    report.timings.push_back(PhaseTiming{"flattening", workshop_seconds});
    if (!clock.start("degenerate faces")) return atlas;
  } else {
    if (!clock.start("flattening")) return atlas;
    std::vector<ChartJob> jobs;
    jobs.reserve(face_sets.size());
    for (std::vector<int>& faces : face_sets)
      jobs.push_back(ChartJob{std::move(faces), std::nullopt, std::nullopt});
    if (!workshop.run(std::move(jobs), threads)) return cancelled(atlas, "flattening");
  }
  std::vector<detail::FinishedChart> charts = workshop.finished();
  if (options.join_charts) {
    // Neighbours whose union flattens within the limit become one chart (stretch_bounded_join.h).
    if (!clock.start("joining")) return atlas;
    if (!detail::join_within_stretch(surface, geometry, detail::joining_cone(segmentation_options),
                                     options.max_distortion, solver, threads, charts))
      return cancelled(atlas, "joining");
  }
  const std::vector<int> host_of_face = detail::zero_area_hosts(surface, geometry);
  add_degenerate_faces(surface, geometry, host_of_face, options.max_distortion, solver, charts);
  if (!clock.start("packing")) return atlas;
  detail::PackingOptions packing_options;
  packing_options.resolution = options.resolution;
  packing_options.height = options.height;
  packing_options.padding = options.padding;
  packing_options.threads = threads;
  // The charts are in the normalized copy's lengths: a unit of the model is 1/size of them.
  packing_options.fixed_scale = options.texels_per_unit * normalized.size;
  packing_options.max_pages = options.max_pages;
  // The charts at `indices` (increasing) split in two and flattened again, the charts kept in
  // the order of their first face. False when cancelled.
  const auto split_again = [&](const std::vector<std::size_t>& indices) {
    std::vector<ChartJob> jobs;
    std::vector<detail::FinishedChart> kept;
    for (std::size_t c = 0, next = 0; c < charts.size(); ++c) {
      if (next < indices.size() && indices[next] == c) {
        ++next;
        for (std::vector<int>& half : detail::split_in_two(geometry, charts[c].mesh.surface_face))
          jobs.push_back(ChartJob{std::move(half), std::nullopt, std::nullopt});
      } else {
        kept.push_back(std::move(charts[c]));
      }
    }
    if (!workshop.run(std::move(jobs), threads)) return false;
    for (detail::FinishedChart& chart : workshop.finished()) kept.push_back(std::move(chart));
    std::sort(kept.begin(), kept.end(), [](const detail::FinishedChart& a, const detail::FinishedChart& b) {
      return a.mesh.surface_face.front() < b.mesh.surface_face.front();
    });
    charts = std::move(kept);
    return true;
  };
  if (packing_options.fixed_scale > 0.0) {
    // At a density asked for, a chart larger than a page is halved until its pieces fit one (a
    // single face larger than a page is refused by the packing).
    for (;;) {
      std::vector<std::size_t> too_large;
      const std::vector<Eigen::MatrixX2d> triangles = chart_triangles(charts);
      for (std::size_t c = 0; c < charts.size(); ++c)
        if (charts[c].mesh.surface_face.size() > 1 && !detail::fits_one_page(triangles[c], packing_options))
          too_large.push_back(c);
      if (too_large.empty()) break;
      if (!split_again(too_large)) return cancelled(atlas, "packing");
    }
  }
  detail::ChartPacking packing;
  try {
    packing = detail::pack_charts(chart_triangles(charts), packing_options);
    if (std::optional<std::vector<detail::FinishedChart>> cut = detail::long_charts_split(
            surface, geometry, options.max_distortion, options.resolution,
            static_cast<int>(atlas_size(options).y()), options.padding, charts)) {
      detail::ChartPacking cut_packing = detail::pack_charts(chart_triangles(*cut), packing_options);
      if (detail::cut_worth_its_charts(charts.size(), packing.coverage, cut->size(), cut_packing.coverage)) {
        charts = std::move(*cut);
        packing = std::move(cut_packing);
      }
    }
    // A chart whose placed boundary crosses itself is split in two and flattened again, and the
    // atlas packed anew: the promise of no crossing holds for any chart (a single face cannot
    // cross itself, so the halving ends).
    for (int round = 0; round < kPlacementRepairRounds; ++round) {
      const std::vector<std::size_t> crossing = charts_crossing_once_placed(charts, packing, atlas_size(options));
      if (crossing.empty()) break;
      if (!split_again(crossing)) return cancelled(atlas, "packing");
      packing = detail::pack_charts(chart_triangles(charts), packing_options);
    }
  } catch (const Error& error) {  // more charts than the resolution can hold with this padding
    report.status = error.status();
    report.message = std::string("texture atlas: ") + error.what() +
                     (options.texels_per_unit > 0.0
                          ? (options.max_pages > 0 ? " (a larger resolution, a smaller density or more pages leave room for them)"
                                                   : " (a larger resolution or a smaller density leaves room for them)")
                          : " (a larger resolution or a smaller padding leaves room for them)");
    return atlas;
  }
  // The faces of zero area with a face of area beside them, inside that face: the packing stays.
  detail::draw_inside_hosts(surface, geometry, host_of_face, charts);
  place_charts(charts, packing, atlas_size(options), input.face_count(), atlas);
  if (!clock.start("metrics")) return atlas;
  // Chart layouts are in the normalized copy's lengths: per unit of the model, 1/size as many texels.
  // measure_atlas also gives each chart its figures, measured in the model's own units.
  atlas.metrics = detail::measure_atlas(input, atlas);
  atlas.metrics.texels_per_unit = packing.texels_per_unit / normalized.size;
  clock.stop();
  return atlas;
}

}  // namespace harmonia

namespace harmonia {

std::vector<int> page_of_face(const TextureAtlas& atlas) {
  if (atlas.pages <= 1) return {};
  std::vector<int> pages(atlas.chart_of_face.size(), -1);
  for (std::size_t f = 0; f < pages.size(); ++f)
    if (const int chart = atlas.chart_of_face[f]; chart >= 0) pages[f] = atlas.charts[static_cast<std::size_t>(chart)].page;
  return pages;
}

TextureAtlas repack_texture_atlas(const Mesh& input, const Eigen::Matrix<double, Eigen::Dynamic, 6>& corner_uv,
                                  const TextureAtlasOptions& options) {
  TextureAtlas atlas;
  SolveReport& report = atlas.report;
  detail::PhaseClock clock(report, options.solver.progress);
  if (!clock.start("validation")) return atlas;
  std::string problem;
  if (check_indices_and_coordinates(input, &problem) == Status::ok && (problem = option_problem(options)).empty()) {
    if (corner_uv.rows() != input.faces.rows()) {
      problem = "corner_uv has " + std::to_string(corner_uv.rows()) + " rows for " +
                std::to_string(input.faces.rows()) + " faces";
    } else {
      for (Eigen::Index f = 0; f < corner_uv.rows() && problem.empty(); ++f)
        if (!corner_uv.row(f).allFinite()) problem = "face " + std::to_string(f) + " has a texture coordinate that is not finite";
    }
  }
  if (problem.empty() && input.faces.rows() == 0) problem = "the mesh has no faces";
  if (!problem.empty()) {
    report.status = Status::invalid_input;
    report.message = "repack: " + problem;
    return atlas;
  }
  if (!clock.start("segmentation")) return atlas;
  const std::vector<detail::FinishedChart> charts = detail::input_charts(input, corner_uv);
  if (!clock.start("packing")) return atlas;
  detail::PackingOptions packing_options;
  packing_options.resolution = options.resolution;
  packing_options.height = options.height;
  packing_options.padding = options.padding;
  packing_options.threads = worker_count(options.threads);
  packing_options.fixed_scale = options.texels_per_unit;  // the charts are in the model's lengths
  packing_options.max_pages = options.max_pages;
  packing_options.quarter_turns_only = true;
  detail::ChartPacking packing;
  try {
    packing = detail::pack_charts(chart_triangles(charts), packing_options);
  } catch (const Error& error) {
    report.status = error.status();
    report.message = std::string("repack: ") + error.what() +
                     (options.texels_per_unit > 0.0 ? " (a larger resolution or a smaller density leaves room for them)"
                                                    : " (a larger resolution or a smaller padding leaves room for them)");
    return atlas;
  }
  place_charts(charts, packing, atlas_size(options), input.face_count(), atlas);
  if (!clock.start("metrics")) return atlas;
  atlas.metrics = detail::measure_atlas(input, atlas);
  atlas.metrics.texels_per_unit = packing.texels_per_unit;
  clock.stop();
  return atlas;
}

}  // namespace harmonia
