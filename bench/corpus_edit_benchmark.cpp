// corpus_edit_benchmark: the surface editor (harmonia/surface_editor.h, CPU backend) in two parts.
//
// Quality: every edit case of ../shared/data/edit (homer-a/b/c, elephant-a/b/c) and of this
// project's tests/assets/edit (limbs turned about their joints on cheburashka, cow, spot, homer and
// elephant; references made alike by corpus_edit_reference), deformed by the
// editor with 0, 4 and 10 as-rigid-as-possible refinement steps and with a 5 ms frame budget,
// and the case's own files (the
// harmonic baseline, ARAP after 10 iterations), each measured against the converged ARAP reference
// (arap500) as the data's README measures: rms_rel = RMS vertex distance / bounding-box diagonal of
// the reference. The target depends on the case's class, derived from the edit (a handle
// rotates when its rotation is not the identity): every handle rotates, the harmonic baseline must
// be >= 2x as far from the reference as the editor; mixed, >= 1.33x; translation only, the editor
// no farther than the baseline (1x). Beside it: flipped triangles (the editor's report), the
// largest constraint error and deformation_metrics' similarity deviation.
//
// Speed: closed corpus meshes (default the bunny) at 1x, 16x and 64x their size (6,966 / 111,456
// / 445,824 faces, midpoint subdivision), with the geometric edit of bench/surface_edit_support.h
// on the whole mesh: the set-up's time against the floor of the same mesh cut open (cut_to_disk,
// automatic ends, as corpus_sphere_benchmark measures it; target set-up <= 2x floor), and the
// median of a frame over the edit played as --frames frames (partial(t)) with its split (target
// <= 10 ms near 100K faces, <= 50 ms near 400K faces), and the peak resident size.
//
// Every case and every measurement runs in its own forked process (corpus_child.h), so its peak
// resident size is its own and a crash ends only that row. Output: a markdown report (stdout and
// --out-md) and a JSON file (--out-json). See bench/README.md.

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/bench_support.h"
#include "bench/corpus_child.h"
#include "bench/corpus_methods.h"
#include "bench/corpus_report.h"
#include "bench/surface_edit_support.h"
#include "harmonia/blas_threads.h"
#include "harmonia/cut.h"
#include "harmonia/deformation_metrics.h"
#include "harmonia/edit_file.h"
#include "harmonia/io.h"
#include "harmonia/surface_editor.h"

namespace {

namespace fs = std::filesystem;
namespace bench = harmonia::bench;
using bench::Json;

// ---------------------------------------------------------------------------------------------
// Options

struct Options {
  // The public cases, then this project's own (tests/assets/edit): limbs turned about their joints
  // on every closed corpus mesh with legs or arms.
  std::vector<std::string> cases{"homer-a",       "homer-b",       "homer-c", "elephant-a", "elephant-b",
                                 "elephant-c",    "cheburashka-a", "cheburashka-b", "cow-a", "cow-b",
                                 "spot-a",        "spot-b",        "homer-d", "elephant-d", "elephant-e"};
  std::vector<std::string> speed_meshes{"bunny"};  // Closed corpus meshes of the speed part.
  std::vector<int> sizes{1, 16, 64};               // Their size factors (powers of 4).
  int frames = 20;                                 // Frames of the played edit per speed row.
  bool quality = true;
  bool speed = true;
  // repeat: set-ups and floors per speed row (the fastest counts); the child processes' limit,
  // the OpenBLAS policy and the outputs.
  bench::CorpusRunOptions run{.out_md = "edit-bench-results.md",
                              .out_json = "edit-bench-results.json"};
};

//! The editor's settings of the quality part: the default (rotation clusters) alone, then 4 and 10
//! as-rigid-as-possible steps on the same factorization, then as many as fit a frame budget of
//! 5 ms (SurfaceEditOptions::frame_budget; the frame is played twice and the second counts: the
//! first teaches the editor what a step costs, as an engine's first frame would).
struct EditorSetting {
  const char* key;  // the column's name: r<steps> or b<budget in ms>
  int refinement_steps = 0;
  double frame_budget_ms = 0.0;
  const char* what;
};
constexpr EditorSetting kEditorSettings[] = {{"r0", 0, 0.0, "the default: rotation clusters, no refinement"},
                                             {"r4", 4, 0.0, "4 as-rigid-as-possible steps"},
                                             {"r10", 10, 0.0, "10 as-rigid-as-possible steps"},
                                             {"b5", 0, 5.0, "as many steps as fit 5 ms a frame"}};
//! A ratio meets its target up to this relative rounding: on a translation-only edit the editor
//! gives the harmonic interpolation itself, which differs from the baseline file only by the two
//! solvers' rounding (a ratio of 1 - 3e-13 on homer-a).
constexpr double kRatioRounding = 1e-9;

// The speed targets: a frame's median near 100K and near 400K faces ("near": within a factor 2),
// and the set-up against the floor on the meshes of either size.
constexpr int kNear100KMinFaces = 50000;
constexpr int kNear400KMinFaces = 200000;
constexpr int kNear400KMaxFaces = 800000;
constexpr double kFrameTargetNear100KSeconds = 0.010;
constexpr double kFrameTargetNear400KSeconds = 0.050;
constexpr double kSetupTargetFloorMultiple = 2.0;

void print_usage() {
  std::cout
      << "usage: corpus_edit_benchmark [--cases a,b] [--speed-meshes a,b] [--sizes 1,16,64]\n"
         "                             [--frames N] [--repeat N] [--timeout S] [--quick]\n"
         "                             [--skip-quality] [--skip-speed] [--out-md FILE]\n"
         "                             [--out-json FILE] [--blas-threads hold|leave]\n"
         "Quality: the edit cases of ../shared/data/edit and tests/assets/edit against their ARAP reference (harmonic\n"
         "and arap10 files, the editor with 0, 4 and 10 refinement steps and a 5 ms frame\n"
         "budget). Speed: the speed\n"
         "meshes (closed corpus, default bunny) at each size, geometric edit on the whole mesh:\n"
         "set-up against the floor of the mesh cut open, median frame over --frames frames.\n"
         "--quick: speed at sizes 1,16 with 10 frames.\n";
}

//! The options of the command line; nothing after a message on stderr when it is not understood.
std::optional<Options> parse_options(int argc, char** argv) {
  Options options;
  const std::vector<std::string> arguments(argv + 1, argv + argc);
  for (std::size_t index = 0; index < arguments.size(); ++index) {
    const std::string& flag = arguments[index];
    if (flag == "--help" || flag == "-h") {
      print_usage();
      std::exit(0);
    } else if (flag == "--quick") {
      options.sizes = {1, 16};
      options.frames = 10;
    } else if (flag == "--skip-quality") {
      options.quality = false;
    } else if (flag == "--skip-speed") {
      options.speed = false;
    } else if (index + 1 == arguments.size()) {
      std::cerr << "corpus_edit_benchmark: " << flag << " needs a value (or is unknown)\n";
      return std::nullopt;
      // Every flag from here on takes the next argument as its value.
    } else if (const std::string& value = arguments[++index]; flag == "--cases") {
      options.cases = bench::comma_separated(value);
    } else if (flag == "--speed-meshes") {
      options.speed_meshes = bench::comma_separated(value);
    } else if (flag == "--sizes") {
      options.sizes.clear();
      for (const std::string& size : bench::comma_separated(value)) {
        options.sizes.push_back(std::stoi(size));
        if (bench::subdivision_steps(options.sizes.back()) < 0) {
          std::cerr << "corpus_edit_benchmark: size " << size << " is not a power of 4\n";
          return std::nullopt;
        }
      }
    } else if (flag == "--frames") {
      options.frames = std::max(1, std::stoi(value));
    } else if (!bench::parse_corpus_run_option(flag, value, &options.run)) {
      std::cerr << "corpus_edit_benchmark: unknown option " << flag << " " << value << "\n";
      return std::nullopt;
    }
  }
  return options;
}

// ---------------------------------------------------------------------------------------------
// Measures of a deformation

//! A row's status and message.
Json status_json(harmonia::Status status, const std::string& message) {
  return Json{{"status", std::string(harmonia::to_string(status))}, {"message", message}};
}

double bounding_box_diagonal(const Eigen::MatrixX3d& positions) {
  return (positions.colwise().maxCoeff() - positions.colwise().minCoeff()).norm();
}

//! The data's rms_rel: RMS distance between corresponding vertices over `diagonal`.
double relative_rms_distance(const Eigen::MatrixX3d& positions, const Eigen::MatrixX3d& reference,
                             double diagonal) {
  return std::sqrt((positions - reference).rowwise().squaredNorm().mean()) / diagonal;
}

//! The largest distance of a constrained vertex (fixed or on a handle) from its target, over
//! `diagonal`.
double max_constraint_error(const harmonia::Mesh& rest, const harmonia::EditDescription& edit,
                            const Eigen::MatrixX3d& positions, double diagonal) {
  double largest = 0.0;
  for (const int vertex : edit.regions.fixed) {
    largest = std::max(largest, (positions.row(vertex) - rest.vertices.row(vertex)).norm());
  }
  for (std::size_t handle = 0; handle < edit.regions.handles.size(); ++handle) {
    for (const int vertex : edit.regions.handles[handle]) {
      const Eigen::Vector3d target =
          edit.transforms[handle].apply(rest.vertices.row(vertex).transpose());
      largest = std::max(largest, (positions.row(vertex).transpose() - target).norm());
    }
  }
  return largest / diagonal;
}

//! The vertex positions of a deformation file of `rest`; throws when the vertex count differs.
Eigen::MatrixX3d deformed_positions(const fs::path& path, const harmonia::Mesh& rest) {
  harmonia::Mesh deformed = harmonia::read_mesh(path);
  if (deformed.vertex_count() != rest.vertex_count()) {
    throw std::runtime_error(path.string() + " has " + std::to_string(deformed.vertex_count()) +
                             " vertices, the rest mesh " + std::to_string(rest.vertex_count()));
  }
  return std::move(deformed.vertices);
}

// ---------------------------------------------------------------------------------------------
// Quality

//! The class of an edit and the target for it: how many times farther from the reference
//! the harmonic baseline must be than the editor.
struct EditClass {
  std::string name;
  double target_ratio = 1.0;
};

//! Every handle rotates, some do, or none (a translation-only edit, where the editor gives the
//! harmonic interpolation of the displacements by design and must only be no farther).
EditClass classify(const harmonia::EditDescription& edit) {
  std::size_t rotating = 0;
  for (const harmonia::SimilarityTransform& transform : edit.transforms) {
    // A unit quaternion is the identity exactly when its vector part is zero.
    if (transform.rotation.vec().norm() > 0.0) ++rotating;
  }
  if (rotating == edit.transforms.size()) return {"every handle rotates", 2.0};
  if (rotating > 0) return {"mixed", 1.33};
  return {"translation only", 1.0};
}

//! How far `positions` is from the reference, and how well it keeps the local shape.
Json deformation_entry(const harmonia::Mesh& rest, const harmonia::EditDescription& edit,
                       const Eigen::MatrixX3d& positions, const Eigen::MatrixX3d& reference) {
  const double diagonal = bounding_box_diagonal(reference);
  const harmonia::DeformationMetrics metrics = harmonia::deformation_metrics(rest, positions);
  return Json{{"rms_rel", relative_rms_distance(positions, reference, diagonal)},
              {"max_constraint_error", max_constraint_error(rest, edit, positions, diagonal)},
              {"similarity_deviation_mean", metrics.similarity_deviation_mean},
              {"similarity_deviation_max", metrics.similarity_deviation_max},
              {"turned_faces", metrics.turned_faces},
              {"degenerate_faces", metrics.degenerate_faces}};
}

//! The editor on one case with `setting`: set-up, one frame of the whole edit (with a budget, the
//! second of two).
Json editor_entry(const harmonia::Mesh& rest, const harmonia::EditDescription& edit,
                  const Eigen::MatrixX3d& reference, const EditorSetting& setting) {
  harmonia::SurfaceEditOptions options;
  options.refinement_steps = setting.refinement_steps;
  options.frame_budget = setting.frame_budget_ms / 1000.0;
  options.solver.backend = harmonia::BackendChoice::cpu;
  bench::Stopwatch setting_up;
  harmonia::SurfaceEditor editor(rest, edit.regions, options);
  const double setup_seconds = setting_up.seconds();
  if (setting.frame_budget_ms > 0.0) (void)editor.deform(edit.transforms);
  bench::Stopwatch deforming;
  const harmonia::SurfaceEditResult result = editor.deform(edit.transforms);
  const double frame_seconds = deforming.seconds();

  Json entry = status_json(result.report.status, result.report.message);
  entry.update(Json{{"refinement_steps", result.refinement_steps},
                    {"frame_budget_ms", setting.frame_budget_ms},
                    {"setup_seconds", setup_seconds},
                    {"frame_seconds", frame_seconds},
                    {"flipped_triangles", result.report.flipped_triangles},
                    {"degenerate_triangles", result.report.degenerate_triangles},
                    {"factorizations", editor.factorization_count()}});
  if (result.positions.rows() == rest.vertex_count()) {
    entry.update(deformation_entry(rest, edit, result.positions, reference));
  }
  return entry;
}

std::string editor_key(const EditorSetting& setting) {
  return std::string("harmonia-") + setting.key;
}

//! The folder of an edit case's files: the public cases' ../shared/data/edit, else this project's
//! own cases, tests/assets/edit (made by its make_cases.py and corpus_edit_reference).
fs::path case_folder(const std::string& case_name) {
  const fs::path public_cases = bench::shared_data_dir() / "edit";
  if (fs::exists(public_cases / (case_name + ".json"))) return public_cases;
  return fs::path(HARMONIA_SOURCE_DIR) / "tests" / "assets" / "edit";
}

//! Child body for one edit case: the rest mesh (../closed/ + the case's name up to its first
//! '-', as the data's README pairs them), the edit, the files, and the editor at each refinement.
Json measure_case_child(const std::string& case_name) {
  const fs::path edit_dir = case_folder(case_name);
  const std::string mesh_name = case_name.substr(0, case_name.find('-'));
  const harmonia::Mesh rest =
      harmonia::read_mesh(bench::shared_data_dir() / "closed" / (mesh_name + ".obj"));
  const harmonia::EditDescription edit =
      harmonia::read_edit_file(edit_dir / (case_name + ".json"), rest);
  const Eigen::MatrixX3d reference =
      deformed_positions(edit_dir / (case_name + ".arap500.obj"), rest);
  const EditClass edit_class = classify(edit);

  Json handle_vertices = Json::array();
  for (const std::vector<int>& handle : edit.regions.handles) {
    handle_vertices.push_back(handle.size());
  }
  Json row{{"status", "ok"},
           {"case", case_name},
           {"mesh", mesh_name},
           {"vertices", rest.vertex_count()},
           {"faces", rest.face_count()},
           {"fixed_vertices", edit.regions.fixed.size()},
           {"handle_vertices", handle_vertices},
           {"class", edit_class.name},
           {"target_ratio", edit_class.target_ratio}};

  Json deformations = Json::object();
  // The reference against itself: its rms_rel is 0, its similarity deviation the scale of the
  // others'.
  for (const char* file : {"harmonic", "arap10", "arap500"}) {
    const fs::path path = edit_dir / (case_name + "." + file + ".obj");
    deformations[file] = deformation_entry(rest, edit, deformed_positions(path, rest), reference);
  }
  const double baseline = deformations["harmonic"]["rms_rel"].get<double>();
  for (const EditorSetting& setting : kEditorSettings) {
    Json entry = editor_entry(rest, edit, reference, setting);
    if (entry.contains("rms_rel")) {
      const double ratio = baseline / entry["rms_rel"].get<double>();
      entry["baseline_ratio"] = ratio;
      entry["target_met"] = ratio >= edit_class.target_ratio * (1.0 - kRatioRounding);
    }
    deformations[editor_key(setting)] = std::move(entry);
  }
  row["deformations"] = std::move(deformations);
  return row;
}

// ---------------------------------------------------------------------------------------------
// Speed

struct SpeedMesh {
  std::string name;  // e.g. "bunny-x16".
  std::string base;  // e.g. "bunny".
  fs::path path;
  int factor = 1;
};

std::vector<SpeedMesh> speed_meshes(const Options& options) {
  std::vector<SpeedMesh> meshes;
  for (const std::string& base : options.speed_meshes) {
    for (const int factor : options.sizes) {
      std::string message;
      const auto path = bench::scaled_mesh(bench::shared_data_dir() / "closed" / (base + ".obj"),
                                           factor, &message);
      if (!path) {
        std::cerr << "corpus_edit_benchmark: " << message << "\n";
        continue;
      }
      meshes.push_back(
          {factor == 1 ? base : base + "-x" + std::to_string(factor), base, *path, factor});
    }
  }
  return meshes;
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  if (values.size() % 2 == 1) return *middle;
  return 0.5 * (*middle + *std::max_element(values.begin(), middle));
}

//! Child body: the closed mesh cut open (cut_to_disk, automatic ends) and written to `disk_path`,
//! where the floor's own child reads it.
Json cut_open_child(const fs::path& closed_path, const fs::path& disk_path) {
  const harmonia::CutResult cut = harmonia::cut_to_disk(harmonia::read_mesh(closed_path));
  if (cut.status != harmonia::Status::ok) {
    return status_json(cut.status, "cut_to_disk: " + cut.message);
  }
  harmonia::write_mesh(disk_path, cut.disk);
  return Json{{"status", "ok"}, {"seam_edges", cut.seam_edges}};
}

//! The floor of `mesh` cut open: cut in one child, measured in another
//! (bench::measure_floor_child).
Json cut_open_floor(const SpeedMesh& mesh, const fs::path& scratch, const Options& options) {
  const fs::path disk_path = scratch / (mesh.name + "-cut.obj");
  Json floor = bench::run_in_child([&] { return cut_open_child(mesh.path, disk_path); },
                                   options.run.timeout_seconds);
  if (floor.value("status", std::string()) == "ok") {
    floor.update(bench::run_in_child(
        [&] { return bench::measure_floor_child(disk_path, options.run.repeat); },
        options.run.timeout_seconds));
  }
  std::error_code error;
  fs::remove(disk_path, error);
  return floor;
}

//! The frame split's parts, as named in the JSON and the markdown.
const std::vector<std::string>& frame_parts() {
  static const std::vector<std::string> parts{"blending", "assembly", "solve", "check"};
  return parts;
}

//! Child body for one speed row: read the mesh, choose the geometric edit, set the editor up
//! `repeat` times (the fastest counts), play the edit as `frames` frames on the last editor, and
//! read the peak resident size of all that (the mesh included).
Json measure_editor_child(const fs::path& mesh_path, int frames, int repeat) {
  bench::Stopwatch reading;
  const harmonia::Mesh mesh = harmonia::read_mesh(mesh_path);
  const double read_seconds = reading.seconds();
  const harmonia::EditDescription edit = bench::geometric_edit(mesh);
  harmonia::SurfaceEditOptions options;
  options.solver.backend = harmonia::BackendChoice::cpu;

  const double resident_before = bench::process_status_megabytes("VmRSS");
  const bool peak_reset = bench::reset_peak_resident_size();
  std::optional<harmonia::SurfaceEditor> editor;
  double setup_seconds = std::numeric_limits<double>::infinity();
  for (int run = 0; run < repeat; ++run) {
    editor.reset();  // One editor at a time, so the peak is one editor's.
    bench::Stopwatch setting_up;
    editor.emplace(mesh, edit.regions, options);
    setup_seconds = std::min(setup_seconds, setting_up.seconds());
  }
  const harmonia::SolveReport& setup = editor->setup_report();
  Json row = status_json(setup.status, setup.message);
  row.update(Json{{"faces", mesh.face_count()},
                  {"vertices", mesh.vertex_count()},
                  {"fixed_vertices", edit.regions.fixed.size()},
                  {"handle_vertices", edit.regions.handles.front().size()},
                  {"solver", setup.solver},
                  {"read_seconds", read_seconds},
                  {"setup_seconds", setup_seconds},
                  {"setup_phases", bench::phases_json(setup)}});
  if (!setup.ok()) return row;

  std::vector<double> frame_seconds;
  std::vector<std::vector<double>> part_seconds(frame_parts().size());
  harmonia::SurfaceEditResult frame;
  for (int index = 1; index <= frames; ++index) {
    bench::Stopwatch deforming;
    frame = editor->deform(bench::frame_transforms(edit.transforms, index, frames));
    frame_seconds.push_back(deforming.seconds());
    if (!frame.report.ok()) break;
    const double parts[] = {frame.timing.blending, frame.timing.assembly, frame.timing.solve,
                            frame.timing.check};
    for (std::size_t part = 0; part < part_seconds.size(); ++part) {
      part_seconds[part].push_back(parts[part]);
    }
  }
  row["peak_MB"] = bench::process_status_megabytes("VmHWM");
  row["rss_before_MB"] = resident_before;
  row["peak_is_per_run"] = peak_reset;
  row.update(status_json(frame.report.status, frame.report.message));
  row["frames"] = frame_seconds.size();
  row["frame_seconds"] = frame_seconds;
  row["frame_median_seconds"] = median(frame_seconds);
  Json split = Json::object();
  for (std::size_t part = 0; part < part_seconds.size(); ++part) {
    split[frame_parts()[part]] = median(part_seconds[part]);
  }
  row["frame_split_median_seconds"] = split;
  row["flipped_triangles"] = frame.report.flipped_triangles;  // Of the last frame, the whole edit.
  row["degenerate_triangles"] = frame.report.degenerate_triangles;
  row["factorizations"] = editor->factorization_count();
  return row;
}

Json speed_row(const SpeedMesh& mesh, const fs::path& scratch, const Options& options) {
  Json row{{"mesh", mesh.name}, {"base", mesh.base}, {"factor", mesh.factor}};
  row.update(bench::run_in_child(
      [&] { return measure_editor_child(mesh.path, options.frames, options.run.repeat); },
      options.run.timeout_seconds));
  row["floor"] = cut_open_floor(mesh, scratch, options);
  const Json& floor = row["floor"];
  if (floor.value("status", std::string()) == "ok" && row.contains("setup_seconds")) {
    row["setup_x_floor"] = row["setup_seconds"].get<double>() / floor["seconds"].get<double>();
  }
  return row;
}

// ---------------------------------------------------------------------------------------------
// Targets

struct Target {
  std::string name;
  std::string measured;
  std::string limit;
  std::optional<bool> met;  // Nothing when the run has no row the target is about.
  std::string note;
};

Json to_json(const Target& target) {
  return Json{{"target", target.name},
              {"measured", target.measured},
              {"limit", target.limit},
              {"met", target.met ? Json(*target.met) : Json()},
              {"note", target.note}};
}

//! Quality: per refinement setting, the cases whose ratio meets their class's target.
void add_quality_targets(const Json& quality, std::vector<Target>& targets) {
  for (const EditorSetting& setting : kEditorSettings) {
    const std::string key = editor_key(setting);
    int met = 0;
    int measured = 0;
    std::string missed;
    for (const Json& row : quality) {
      if (!row.contains("deformations")) continue;
      const Json& entry = row["deformations"][key];
      ++measured;
      if (entry.value("target_met", false)) {
        ++met;
        continue;
      }
      if (!missed.empty()) missed += ", ";
      missed += row["case"].get<std::string>() + " " +
                bench::fixed(entry.value("baseline_ratio", Json()), 2) + "x";
    }
    if (measured == 0) continue;
    targets.push_back(
        {std::string("editor, ") + setting.what + ": harmonic rms_rel / ours",
         std::to_string(met) + " of " + std::to_string(measured) + " cases met" +
             (missed.empty() ? std::string() : "; missed: " + missed),
         ">= 2 (every handle rotates), 1.33 (mixed), 1 (translation only)", met == measured,
         setting.frame_budget_ms > 0.0 ? "steps made: see the details" : ""});
  }
}

//! Speed: the set-up <= 2x the floor on the meshes near 100K and 400K faces, and the frame's median
//! within its size's limit.
void add_speed_targets(const Json& speed, std::vector<Target>& targets) {
  for (const Json& row : speed) {
    const int faces = row.value("faces", 0);
    if (faces < kNear100KMinFaces || faces >= kNear400KMaxFaces) continue;
    const std::string mesh =
        row["mesh"].get<std::string>() + " (" + std::to_string(faces) + " faces)";
    const Json setup_multiple = row.value("setup_x_floor", Json());
    targets.push_back(
        {mesh + " set-up / floor", bench::fixed(setup_multiple, 2),
         "<= " + bench::fixed(Json(kSetupTargetFloorMultiple), 0),
         setup_multiple.is_number()
             ? std::optional<bool>(setup_multiple.get<double>() <= kSetupTargetFloorMultiple)
             : std::nullopt,
         setup_multiple.is_number() ? "" : "no floor: " + row["floor"].value("message", "")});
    const bool near_400k = faces >= kNear400KMinFaces;
    const double limit = near_400k ? kFrameTargetNear400KSeconds : kFrameTargetNear100KSeconds;
    const Json frame = row.value("frame_median_seconds", Json());
    targets.push_back(
        {mesh + " frame median (ms)",
         frame.is_number() ? bench::fixed(Json(1e3 * frame.get<double>()), 1) : "-",
         "<= " + bench::fixed(Json(1e3 * limit), 0) + (near_400k ? " (near 400K)" : " (near 100K)"),
         frame.is_number() ? std::optional<bool>(frame.get<double>() <= limit) : std::nullopt,
         row.value("status", std::string()) == "ok" ? "" : bench::status_text(row)});
  }
}

// ---------------------------------------------------------------------------------------------
// Markdown

std::string milliseconds(const Json& seconds, int decimals = 2) {
  return seconds.is_number() ? bench::fixed(Json(1e3 * seconds.get<double>()), decimals) : "-";
}

std::string yes_no(const Json& value) {
  if (!value.is_boolean()) return "-";
  return value.get<bool>() ? "yes" : "NO";
}

void quality_markdown(const Json& quality, std::ostringstream& md) {
  md << "## Quality: distance to the converged ARAP reference\n\n"
     << "rms_rel: RMS vertex distance to `<case>.arap500.obj` / its bounding-box diagonal. "
     << "harmonic, arap10: the case's files; r0, r4, r10: the editor (CPU) with 0, 4 and 10 "
     << "refinement steps, one frame of the whole edit; b5: as many steps as fit a 5 ms frame "
     << "(the second frame of two). ratio: harmonic rms_rel / the editor's "
     << "(higher is better). class: from the edit (a handle rotates when its rotation is not the "
     << "identity); target: the ratio the class asks for (translation only: no farther than the "
     << "baseline).\n\n"
     << "| case | class | harmonic | arap10 | r0 | r4 | r10 | b5 | ratio r0 | ratio r4 | "
        "ratio r10 | ratio b5 | target | met r0 / r4 / r10 / b5 |\n"
     << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
  for (const Json& row : quality) {
    if (!row.contains("deformations")) {
      md << "| " << row["case"].get<std::string>() << " | " << bench::status_text(row)
         << " | | | | | | | | | | | | |\n";
      continue;
    }
    const Json& deformations = row["deformations"];
    md << "| " << row["case"].get<std::string>() << " | " << row["class"].get<std::string>()
       << " | " << bench::fixed(deformations["harmonic"]["rms_rel"], 4) << " | "
       << bench::fixed(deformations["arap10"]["rms_rel"], 4);
    for (const EditorSetting& setting : kEditorSettings) {
      md << " | " << bench::fixed(deformations[editor_key(setting)].value("rms_rel", Json()), 4);
    }
    std::string met;
    for (const EditorSetting& setting : kEditorSettings) {
      const Json& entry = deformations[editor_key(setting)];
      md << " | " << bench::fixed(entry.value("baseline_ratio", Json()), 2);
      met += (met.empty() ? "" : " / ") + yes_no(entry.value("target_met", Json()));
    }
    md << " | " << bench::fixed(row["target_ratio"], 2) << " | " << met << " |\n";
  }

  md << "\n### Details\n\n"
     << "max constraint error: largest distance of a fixed or handle vertex from its target / the "
     << "reference's diagonal. similarity deviation: deformation_metrics' mean (and max) distance "
     << "of a triangle's deformation gradient from a similarity (0: only turned and scaled; the "
     << "arap500 row is the reference's own). turned: triangles whose normal turned more than 90 "
     << "degrees from the rest normal (deformation_metrics); flipped: the editor's report (turned "
     << "90 degrees or more from the triangle's own blended rotation). Times: the editor's set-up "
     << "and its one frame (wall clock); steps: the frame's refinement steps.\n\n"
     << "| case | deformation | rms_rel | max constraint error | similarity deviation mean (max) | "
        "turned | flipped | steps | set-up s | frame s | status |\n"
     << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
  for (const Json& row : quality) {
    if (!row.contains("deformations")) continue;
    for (const auto& [name, entry] : row["deformations"].items()) {
      const bool editor = entry.contains("refinement_steps");
      md << "| " << row["case"].get<std::string>() << " | " << name << " | "
         << bench::fixed(entry.value("rms_rel", Json()), 4) << " | "
         << bench::scientific(entry.value("max_constraint_error", Json())) << " | "
         << bench::fixed(entry.value("similarity_deviation_mean", Json()), 4) << " ("
         << bench::fixed(entry.value("similarity_deviation_max", Json()), 3) << ") | "
         << bench::integer(entry, "turned_faces") << " | "
         << (editor ? bench::integer(entry, "flipped_triangles") : "-") << " | "
         << (editor ? bench::integer(entry, "refinement_steps") : "-") << " | "
         << bench::fixed(entry.value("setup_seconds", Json()), 3) << " | "
         << bench::fixed(entry.value("frame_seconds", Json()), 3) << " | "
         << (editor ? bench::status_text(entry) : "file") << " |\n";
    }
  }
}

void speed_markdown(const Json& speed, int frames, std::ostringstream& md) {
  md << "\n## Speed: set-up and frames (CPU)\n\n"
     << "The geometric edit (bench/surface_edit_support.h): the lowest 10% of the height fixed, "
     << "the highest 10% one handle turned 45 degrees about x through its centroid and lifted by "
     << "5% of the height; region of interest: the whole mesh. set-up: the SurfaceEditor "
     << "constructor (wall clock). floor: CHOLMOD supernodal analyze + factorize + solve of the "
     << "cotangent Dirichlet system of the same mesh cut open (cut_to_disk, automatic ends), "
     << "assembly excluded. Frames: the edit played as " << frames << " frames (partial(t), t = k/"
     << frames
     << "); the median of each frame's wall clock and of each part of SurfaceEditResult::timing. "
     << "peak_MB: peak resident size of the process (mesh, editor and frames). flipped: the last "
     << "frame's report. fact.: factorizations after all frames (1 = never refactorized).\n\n"
     << "| mesh | faces | vertices | fixed / handle | set-up s | floor s | set-up / floor | "
        "frame ms | blending | assembly | solve | check | peak_MB | flipped | fact. | status |\n"
     << "|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
  for (const Json& row : speed) {
    const Json split = row.value("frame_split_median_seconds", Json::object());
    md << "| " << row["mesh"].get<std::string>() << " | " << row.value("faces", 0) << " | "
       << row.value("vertices", 0) << " | " << bench::integer(row, "fixed_vertices") << " / "
       << bench::integer(row, "handle_vertices") << " | "
       << bench::fixed(row.value("setup_seconds", Json()), 3) << " | "
       << bench::fixed(row["floor"].value("seconds", Json()), 3) << " | "
       << bench::fixed(row.value("setup_x_floor", Json()), 2) << " | "
       << milliseconds(row.value("frame_median_seconds", Json()));
    for (const std::string& part : frame_parts())
      md << " | " << milliseconds(split.value(part, Json()));
    md << " | " << bench::fixed(row.value("peak_MB", Json()), 0) << " | "
       << bench::integer(row, "flipped_triangles") << " | " << bench::integer(row, "factorizations")
       << " | " << bench::status_text(row) << " |\n";
  }

  md << "\n### Where the set-up goes (seconds)\n\n"
     << "| mesh | set-up phases | floor: analyze, factorize, solve | seam edges |\n"
     << "|---|---|---|---:|\n";
  for (const Json& row : speed) {
    std::string setup_phases;
    for (const Json& phase : row.value("setup_phases", Json::array())) {
      if (!setup_phases.empty()) setup_phases += ", ";
      setup_phases += phase["phase"].get<std::string>() + " " + bench::fixed(phase["seconds"], 3);
    }
    const Json& floor = row["floor"];
    md << "| " << row["mesh"].get<std::string>() << " | "
       << (setup_phases.empty() ? "-" : setup_phases) << " | "
       << (floor.contains("phases") ? bench::phases_text(floor) : bench::status_text(floor))
       << " | " << bench::integer(floor, "seam_edges") << " |\n";
  }
}

void targets_markdown(const std::vector<Target>& targets, std::ostringstream& md) {
  md << "\n## Targets\n\n| target | measured | limit | met | note |\n|---|---|---|---|---|\n";
  for (const Target& target : targets) {
    md << "| " << target.name << " | " << target.measured << " | " << target.limit << " | "
       << (target.met ? (*target.met ? "yes" : "NO") : "n/a") << " | " << target.note << " |\n";
  }
}

std::string markdown(const Json& results, const std::vector<Target>& targets) {
  std::ostringstream md;
  const Json& host = results["host"];
  md << "# harmonia surface-edit benchmark\n\n"
     << "Host: " << host["cpu"].get<std::string>() << ", " << host["cores"]
     << " cores; load average " << host["load_start"].get<std::string>() << " at start, "
     << host["load_end"].get<std::string>()
     << " at end. CPU backend; OpenBLAS threads: " << results["blas_threads"].get<std::string>()
     << ". Each case and measurement in its own "
     << "process, capped at " << results["timeout"] << " s.\n\n";
  if (!results["quality"].empty()) quality_markdown(results["quality"], md);
  if (!results["speed"].empty()) speed_markdown(results["speed"], results["frames"].get<int>(), md);
  targets_markdown(targets, md);
  return md.str();
}

}  // namespace

int main(int argc, char** argv) {
  const std::optional<Options> parsed = parse_options(argc, argv);
  if (!parsed) {
    print_usage();
    return 2;
  }
  const Options& options = *parsed;
  harmonia::set_blas_thread_policy(options.run.blas_threads);  // Inherited by every forked child.
  std::error_code error;
  if (!fs::is_directory(bench::shared_data_dir() / "closed", error)) {
    std::cerr << "corpus_edit_benchmark: corpus absent (" << bench::shared_data_dir() / "closed"
              << " does not exist)\n";
    return 1;
  }

  Json results{{"host", Json{{"cpu", bench::host_cpu_model()},
                             {"cores", static_cast<int>(::sysconf(_SC_NPROCESSORS_ONLN))},
                             {"load_start", bench::host_load_average()}}},
               {"blas_threads", bench::blas_policy_name(options.run.blas_threads)},
               {"frames", options.frames},
               {"repeat", options.run.repeat},
               {"timeout", options.run.timeout_seconds},
               {"quality", Json::array()},
               {"speed", Json::array()}};

  if (options.quality) {
    for (const std::string& case_name : options.cases) {
      std::cerr << "[" << case_name << "]" << std::flush;
      Json row{{"case", case_name}};
      row.update(bench::run_in_child([&] { return measure_case_child(case_name); },
                                     options.run.timeout_seconds));
      std::cerr << " " << bench::status_text(row) << "\n";
      results["quality"].push_back(std::move(row));
    }
  }
  if (options.speed) {
    // The cut-open disks of the floor are written here, one at a time, and removed at the end.
    const fs::path scratch =
        fs::temp_directory_path() / ("harmonia-edit-bench-" + std::to_string(::getpid()));
    fs::create_directories(scratch, error);
    for (const SpeedMesh& mesh : speed_meshes(options)) {
      std::cerr << "[" << mesh.name << "]" << std::flush;
      Json row = speed_row(mesh, scratch, options);
      std::cerr << " set-up " << bench::fixed(row.value("setup_seconds", Json()), 3) << " s, floor "
                << bench::fixed(row["floor"].value("seconds", Json()), 3) << " s, frame "
                << milliseconds(row.value("frame_median_seconds", Json())) << " ms\n";
      results["speed"].push_back(std::move(row));
    }
    fs::remove_all(scratch, error);
  }

  results["host"]["load_end"] = bench::host_load_average();
  std::vector<Target> targets;
  add_quality_targets(results["quality"], targets);
  add_speed_targets(results["speed"], targets);
  results["targets"] = Json::array();
  for (const Target& target : targets) results["targets"].push_back(to_json(target));

  const std::string report = markdown(results, targets);
  std::cout << report;
  std::ofstream(options.run.out_md) << report;
  std::ofstream(options.run.out_json) << results.dump(2) << "\n";
  return 0;
}
