// corpus_transfer_benchmark: deformation transfer (harmonia/deformation_transfer.h, CPU backend)
// from the lion's poses onto the cat (../shared/data/deform), in three parts.
//
// lion -> cat: both methods (correspondence, 8.4; quaternion, 8.5) with the 55 marker pairs: the
// set-up (the constructor: marker fields, correspondence, factorization; wall clock and its
// SolveReport phases), matched and unmatched triangles, each of the 9 poses' transfer() (median
// and max over the poses), the distance to the known true target poses (cat-01 only) after the
// best rigid alignment, relative to the truth's bounding-box diagonal, and per pose the target
// triangles the transfer folds against those the source pose folds itself.
//
// Growth with marker count: the correspondence method with a deterministic subset of the pairs
// (--marker-counts, default 15, 30, 55; --marker-subset spread: every (55/n)-th pair, so that the
// subset covers the whole body, or first: the first n pairs of the file).
//
// Growth with mesh size: both meshes, the poses and the truth subdivided 1 -> 4 (--sizes, default
// 1, 4; midpoint subdivision by subdivide.py, cached as bench_support.h's scaled_mesh does). The
// subdivision keeps the original vertices first, so the marker indices stay valid, and it makes
// the same new vertices for every file with the same faces, so a subdivided pose keeps the
// connectivity of the subdivided rest mesh (checked before measuring).
//
// Timings are the fastest of --repeat runs (default 3): a set-up is built --repeat times, and
// every pose transferred --repeat times on the last one. The targets (2 cores, 1x, 55
// markers): set-up <= 1 s, each pose <= 20 ms, the error to the true pose <= 2 % (median over the
// poses with a truth), no pose folding more target triangles than the source pose folds.
//
// Every row runs in its own forked process (corpus_child.h), so a crash ends only that row.
// Output: a markdown report (stdout and --out-md) and a JSON file (--out-json). See
// bench/README.md.

#include <unistd.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "bench/bench_support.h"
#include "bench/corpus_child.h"
#include "bench/corpus_methods.h"
#include "bench/corpus_report.h"
#include "harmonia/blas_threads.h"
#include "harmonia/deformation_transfer.h"
#include "harmonia/io.h"
#include "harmonia/marker_file.h"

namespace {

namespace fs = std::filesystem;
namespace bench = harmonia::bench;
using bench::Json;
using harmonia::TransferMethod;

// ---------------------------------------------------------------------------------------------
// Options

enum class MarkerSubset {
  spread,  // Pairs floor(i * total / n), i = 0..n-1: spread over the file's order (the body).
  first,   // The first n pairs of the file (which lists the paws and legs first).
};

struct Options {
  std::vector<int> marker_counts{15, 30, 55};  // Pairs of the marker-count growth rows.
  MarkerSubset marker_subset = MarkerSubset::spread;
  std::vector<int> sizes{1, 4};  // Size factors of the mesh-size growth rows (powers of 4).
  bool marker_growth = true;
  bool size_growth = true;
  // repeat: set-ups and transfers of each pose per row (the fastest counts); the child
  // processes' limit, the OpenBLAS policy and the outputs.
  bench::CorpusRunOptions run{.repeat = 3,
                              .out_md = "transfer-bench-results.md",
                              .out_json = "transfer-bench-results.json"};
};

// The targets, on the lion -> cat rows at 1x with every marker pair.
constexpr double kSetupTargetSeconds = 1.0;
constexpr double kPoseTargetSeconds = 0.020;
constexpr double kErrorTargetRelative = 0.02;

// The corpus' names: the source's rest pose and poses are lion-*.obj, the target's cat-*.obj;
// cat-NN.obj is the true pose NN of the cat where it exists.
constexpr const char* kSourceName = "lion";
constexpr const char* kTargetName = "cat";
constexpr const char* kRestSuffix = "reference";
constexpr const char* kMarkerFile = "markers-lion-cat.txt";

void print_usage() {
  std::cout
      << "usage: corpus_transfer_benchmark [--marker-counts 15,30,55] [--marker-subset "
         "spread|first]\n"
         "                                 [--sizes 1,4] [--repeat N] [--timeout S]\n"
         "                                 [--skip-marker-growth] [--skip-size-growth]\n"
         "                                 [--out-md FILE] [--out-json FILE]\n"
         "                                 [--blas-threads hold|leave]\n"
         "Deformation transfer lion -> cat (../shared/data/deform), CPU backend: both methods\n"
         "with every marker pair; the correspondence method with fewer pairs; both meshes\n"
         "subdivided. Timings: fastest of --repeat (default 3) runs.\n";
}

//! The comma-separated positive integers of `value`; nothing after a message when one is not.
std::optional<std::vector<int>> positive_integers(const std::string& flag,
                                                  const std::string& value) {
  std::vector<int> numbers;
  for (const std::string& item : bench::comma_separated(value)) {
    const int number = std::atoi(item.c_str());
    if (number <= 0) {
      std::cerr << "corpus_transfer_benchmark: " << flag << ": " << item
                << " is not a positive integer\n";
      return std::nullopt;
    }
    numbers.push_back(number);
  }
  return numbers;
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
    } else if (flag == "--skip-marker-growth") {
      options.marker_growth = false;
    } else if (flag == "--skip-size-growth") {
      options.size_growth = false;
    } else if (index + 1 == arguments.size()) {
      std::cerr << "corpus_transfer_benchmark: " << flag << " needs a value (or is unknown)\n";
      return std::nullopt;
      // Every flag from here on takes the next argument as its value.
    } else if (const std::string& value = arguments[++index]; flag == "--marker-counts") {
      const auto counts = positive_integers(flag, value);
      if (!counts) return std::nullopt;
      options.marker_counts = *counts;
    } else if (flag == "--marker-subset" && (value == "spread" || value == "first")) {
      options.marker_subset = value == "spread" ? MarkerSubset::spread : MarkerSubset::first;
    } else if (flag == "--sizes") {
      const auto sizes = positive_integers(flag, value);
      if (!sizes) return std::nullopt;
      for (const int size : *sizes) {
        if (bench::subdivision_steps(size) < 0) {
          std::cerr << "corpus_transfer_benchmark: size " << size << " is not a power of 4\n";
          return std::nullopt;
        }
      }
      options.sizes = *sizes;
    } else if (!bench::parse_corpus_run_option(flag, value, &options.run)) {
      std::cerr << "corpus_transfer_benchmark: unknown option " << flag << " " << value << "\n";
      return std::nullopt;
    }
  }
  return options;
}

const char* method_name(TransferMethod method) {
  return method == TransferMethod::correspondence ? "correspondence" : "quaternion";
}

const char* subset_name(MarkerSubset subset) {
  return subset == MarkerSubset::spread ? "spread" : "first";
}

// ---------------------------------------------------------------------------------------------
// The corpus at one size

//! The files of one size factor: the rest poses, the source's poses and the true target poses
//! (one per source pose that has one), all subdivided alike.
struct TransferCorpus {
  int factor = 1;
  fs::path source_rest;
  fs::path target_rest;
  fs::path markers;
  std::vector<std::string> pose_names;          // "01", "02", ...
  std::vector<fs::path> source_poses;           // lion-NN, one per name.
  std::vector<std::optional<fs::path>> truths;  // cat-NN where the corpus has it.
};

//! The corpus at `factor` (subdivided files made once into bench::mesh_cache_dir()); nothing,
//! with the reason in `message`, when a file is missing or cannot be subdivided.
std::optional<TransferCorpus> transfer_corpus(int factor, std::string* message) {
  const fs::path folder = bench::shared_data_dir() / "deform";
  const auto scaled = [&](const std::string& stem) {
    return bench::scaled_mesh(folder / (stem + ".obj"), factor, message);
  };
  TransferCorpus corpus;
  corpus.factor = factor;
  corpus.markers = folder / kMarkerFile;
  const auto source_rest = scaled(std::string(kSourceName) + "-" + kRestSuffix);
  const auto target_rest = scaled(std::string(kTargetName) + "-" + kRestSuffix);
  if (!source_rest || !target_rest) return std::nullopt;
  corpus.source_rest = *source_rest;
  corpus.target_rest = *target_rest;

  // The source's poses: lion-NAME.obj for every NAME but the rest pose, in name order.
  const std::string prefix = std::string(kSourceName) + "-";
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(folder, error)) {
    const std::string stem = entry.path().stem().string();
    if (entry.path().extension() == ".obj" && stem.starts_with(prefix) &&
        stem != prefix + kRestSuffix) {
      corpus.pose_names.push_back(stem.substr(prefix.size()));
    }
  }
  std::sort(corpus.pose_names.begin(), corpus.pose_names.end());
  if (corpus.pose_names.empty()) {
    *message = "corpus absent: no " + prefix + "*.obj poses in " + folder.string();
    return std::nullopt;
  }
  for (const std::string& name : corpus.pose_names) {
    const auto pose = scaled(prefix + name);
    if (!pose) return std::nullopt;
    corpus.source_poses.push_back(*pose);
    const std::string truth = std::string(kTargetName) + "-" + name;
    if (!fs::exists(folder / (truth + ".obj"), error)) {
      corpus.truths.emplace_back();
      continue;
    }
    const auto truth_path = scaled(truth);
    if (!truth_path) return std::nullopt;
    corpus.truths.push_back(*truth_path);
  }
  return corpus;
}

//! The vertex positions of `path`, a pose of `rest`; throws unless it has the rest mesh's faces
//! (a subdivided pose must have the subdivided rest mesh's connectivity, or the comparison and
//! the transfer would be wrong without any error).
Eigen::MatrixX3d pose_positions(const fs::path& path, const harmonia::Mesh& rest) {
  harmonia::Mesh pose = harmonia::read_mesh(path);
  if (pose.vertex_count() != rest.vertex_count() || pose.face_count() != rest.face_count() ||
      pose.faces != rest.faces) {
    throw std::runtime_error(path.string() + " does not have the faces of its rest mesh");
  }
  return std::move(pose.vertices);
}

//! `count` of the pairs: see MarkerSubset. All of them when `count` is not smaller.
std::vector<harmonia::MarkerPair> marker_subset(const std::vector<harmonia::MarkerPair>& pairs,
                                                int count, MarkerSubset subset) {
  const std::size_t total = pairs.size();
  const std::size_t wanted = std::min(total, static_cast<std::size_t>(count));
  std::vector<harmonia::MarkerPair> chosen;
  for (std::size_t k = 0; k < wanted; ++k) {
    chosen.push_back(pairs[subset == MarkerSubset::spread ? k * total / wanted : k]);
  }
  return chosen;
}

// ---------------------------------------------------------------------------------------------
// One row: a set-up and every pose

//! RMS distance between `positions` moved by the best rigid motion onto `truth` (Kabsch) and
//! `truth`, over the truth's bounding-box diagonal: the transfer fixes the shape, not where the
//! result stands, so only the shape is compared.
double aligned_relative_rms(const Eigen::MatrixX3d& positions, const Eigen::MatrixX3d& truth) {
  const Eigen::MatrixX3d centred = positions.rowwise() - positions.colwise().mean();
  const Eigen::MatrixX3d truth_centred = truth.rowwise() - truth.colwise().mean();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(centred.transpose() * truth_centred,
                                              Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d no_reflection = Eigen::Matrix3d::Identity();
  if ((svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0) no_reflection(2, 2) = -1.0;
  const Eigen::Matrix3d rotation = svd.matrixV() * no_reflection * svd.matrixU().transpose();
  const Eigen::MatrixX3d aligned = centred * rotation.transpose();
  const double diagonal = (truth.colwise().maxCoeff() - truth.colwise().minCoeff()).norm();
  return std::sqrt((aligned - truth_centred).rowwise().squaredNorm().mean()) / diagonal;
}

double median(std::vector<double> values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  if (values.size() % 2 == 1) return *middle;
  return 0.5 * (*middle + *std::max_element(values.begin(), middle));
}

//! What a row measures.
struct RowSpec {
  TransferMethod method = TransferMethod::correspondence;
  int factor = 1;
  int marker_count = 0;  // Pairs used (at most the file's).
  auto key() const { return std::tuple(static_cast<int>(method), factor, marker_count); }
};

//! Child body for one row: read the meshes, build the transfer `repeat` times (the fastest
//! counts), transfer every pose `repeat` times on the last one (the fastest of each counts) and
//! measure each result against its truth.
Json measure_transfer_child(const TransferCorpus& corpus, const RowSpec& spec, MarkerSubset subset,
                            int repeat) {
  const harmonia::Mesh source = harmonia::read_mesh(corpus.source_rest);
  const harmonia::Mesh target = harmonia::read_mesh(corpus.target_rest);
  std::vector<Eigen::MatrixX3d> poses;
  std::vector<std::optional<Eigen::MatrixX3d>> truths;
  for (std::size_t k = 0; k < corpus.source_poses.size(); ++k) {
    poses.push_back(pose_positions(corpus.source_poses[k], source));
    truths.push_back(corpus.truths[k] ? std::optional(pose_positions(*corpus.truths[k], target))
                                      : std::nullopt);
  }
  const std::vector<harmonia::MarkerPair> markers = marker_subset(
      harmonia::read_marker_file(corpus.markers, source.vertex_count(), target.vertex_count()),
      spec.marker_count, subset);

  harmonia::DeformationTransferOptions options;
  options.method = spec.method;
  options.solver.backend = harmonia::BackendChoice::cpu;
  std::optional<harmonia::DeformationTransfer> transfer;
  double setup_seconds = std::numeric_limits<double>::infinity();
  Json setup_phases;
  for (int run = 0; run < repeat; ++run) {
    transfer.reset();  // One set-up in memory at a time.
    bench::Stopwatch setting_up;
    transfer.emplace(source, target, markers, options);
    const double seconds = setting_up.seconds();
    if (seconds < setup_seconds) {
      setup_seconds = seconds;
      setup_phases = bench::phases_json(transfer->setup_report());
    }
  }
  const harmonia::SolveReport& setup = transfer->setup_report();
  Json row{{"status", std::string(harmonia::to_string(setup.status))},
           {"message", setup.message},
           {"source_faces", source.face_count()},
           {"target_faces", target.face_count()},
           {"target_vertices", target.vertex_count()},
           {"markers", markers.size()},
           {"solver", setup.solver},
           {"setup_seconds", setup_seconds},
           {"setup_phases", setup_phases},
           {"matched_triangles", transfer->matched_triangles()},
           {"unmatched_triangles", transfer->unmatched_triangles()}};
  if (!setup.ok()) return row;

  // Pose-major inside each repetition, so that a burst of noise on the machine spreads over
  // several poses' runs instead of all runs of one pose.
  std::vector<double> pose_seconds(poses.size(), std::numeric_limits<double>::infinity());
  std::vector<harmonia::TransferResult> results(poses.size());
  for (int run = 0; run < repeat; ++run) {
    for (std::size_t k = 0; k < poses.size(); ++k) {
      bench::Stopwatch transferring;
      harmonia::TransferResult result = transfer->transfer(poses[k]);
      const double seconds = transferring.seconds();
      if (seconds < pose_seconds[k]) {
        pose_seconds[k] = seconds;
        results[k] = std::move(result);
      }
    }
  }

  Json pose_rows = Json::array();
  std::vector<double> errors;
  int poses_folding_more = 0;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const harmonia::TransferResult& result = results[k];
    Json pose{{"pose", corpus.pose_names[k]},
              {"status", std::string(harmonia::to_string(result.report.status))},
              {"message", result.report.message},
              {"seconds", pose_seconds[k]},
              {"phases", bench::phases_json(result.report)},
              {"flipped_triangles", result.report.flipped_triangles},
              {"source_folded_triangles", result.source_folded_triangles},
              {"degenerate_triangles", result.report.degenerate_triangles}};
    if (result.report.ok() && result.report.flipped_triangles > result.source_folded_triangles) {
      ++poses_folding_more;
    }
    if (result.report.ok() && truths[k]) {
      errors.push_back(aligned_relative_rms(result.positions, *truths[k]));
      pose["error"] = errors.back();
    }
    if (!result.report.ok() && row["status"] == "ok") {
      row["status"] = pose["status"];
      row["message"] = "pose " + corpus.pose_names[k] + ": " + result.report.message;
    }
    pose_rows.push_back(std::move(pose));
  }
  row["pose_median_seconds"] = median(pose_seconds);
  row["pose_max_seconds"] = *std::max_element(pose_seconds.begin(), pose_seconds.end());
  row["truths"] = errors.size();
  if (!errors.empty()) row["error_median"] = median(errors);
  row["poses_folding_more"] = poses_folding_more;
  row["poses"] = std::move(pose_rows);
  return row;
}

//! Rows measured once each and shared by the tables that show them (the correspondence method
//! at 1x with every pair is in all three).
class RowCache {
 public:
  RowCache(const Options& options, std::map<int, TransferCorpus> corpora, int all_markers)
      : options_(options), corpora_(std::move(corpora)), all_markers_(all_markers) {}

  //! The row of `spec` (marker_count clamped to the file's pairs), measured on first use.
  const Json& row(RowSpec spec) {
    spec.marker_count = std::min(spec.marker_count, all_markers_);
    const auto found = rows_.find(spec.key());
    if (found != rows_.end()) return found->second;
    Json row{{"method", method_name(spec.method)},
             {"factor", spec.factor},
             {"marker_count", spec.marker_count}};
    std::cerr << "[" << method_name(spec.method) << ", x" << spec.factor << ", "
              << spec.marker_count << " markers]" << std::flush;
    const auto corpus = corpora_.find(spec.factor);
    if (corpus == corpora_.end()) {
      row.update(Json{{"status", "absent"}, {"message", "no corpus at this size"}});
    } else {
      row.update(bench::run_in_child(
          [&] {
            return measure_transfer_child(corpus->second, spec, options_.marker_subset,
                                          options_.run.repeat);
          },
          options_.run.timeout_seconds));
    }
    std::cerr << " set-up " << bench::fixed(row.value("setup_seconds", Json()), 3)
              << " s, pose median "
              << bench::fixed(Json(1e3 * row.value("pose_median_seconds", 0.0)), 2) << " ms, "
              << bench::status_text(row) << "\n";
    return rows_.emplace(spec.key(), std::move(row)).first->second;
  }

  [[nodiscard]] int all_markers() const { return all_markers_; }

 private:
  const Options& options_;
  std::map<int, TransferCorpus> corpora_;
  int all_markers_;
  std::map<std::tuple<int, int, int>, Json> rows_;
};

// ---------------------------------------------------------------------------------------------
// Targets

//! The targets on the rows at 1x with every pair: speed for both methods, the error for
//! the correspondence method (the quaternion variant's is reported beside it), folds for both.
Json targets(const Json& main_rows) {
  Json list = Json::array();
  const auto add = [&](const std::string& name, const Json& measured, const std::string& limit,
                       const std::optional<bool>& met) {
    list.push_back(Json{{"target", name},
                        {"measured", measured},
                        {"limit", limit},
                        {"met", met ? Json(*met) : Json()}});
  };
  for (const Json& row : main_rows) {
    const std::string method = row["method"].get<std::string>();
    if (row["status"] != "ok") {
      add(method + ": the row", bench::status_text(row), "ok", false);
      continue;
    }
    const double setup = row["setup_seconds"].get<double>();
    add(method + ": set-up (s)", bench::fixed(Json(setup), 3),
        "<= " + bench::fixed(Json(kSetupTargetSeconds), 0), setup <= kSetupTargetSeconds);
    const double slowest_pose = row["pose_max_seconds"].get<double>();
    add(method + ": slowest pose (ms)", bench::fixed(Json(1e3 * slowest_pose), 2),
        "<= " + bench::fixed(Json(1e3 * kPoseTargetSeconds), 0),
        slowest_pose <= kPoseTargetSeconds);
    if (row.contains("error_median")) {
      const double error = row["error_median"].get<double>();
      const bool counted = method == "correspondence";
      add(method + ": error to the true poses, median of " +
              std::to_string(row["truths"].get<int>()) + " (% of diagonal)",
          bench::fixed(Json(100.0 * error), 2),
          counted ? "<= " + bench::fixed(Json(100.0 * kErrorTargetRelative), 0)
                  : "reported beside the correspondence method",
          counted ? std::optional<bool>(error <= kErrorTargetRelative) : std::nullopt);
    }
    add(method + ": poses folding more target triangles than the source pose folds",
        std::to_string(row["poses_folding_more"].get<int>()) + " of " +
            std::to_string(row["poses"].size()),
        "0", row["poses_folding_more"].get<int>() == 0);
  }
  return list;
}

// ---------------------------------------------------------------------------------------------
// Markdown

std::string milliseconds(const Json& seconds) {
  return seconds.is_number() ? bench::fixed(Json(1e3 * seconds.get<double>()), 2) : "-";
}

std::string percent(const Json& relative) {
  return relative.is_number() ? bench::fixed(Json(100.0 * relative.get<double>()), 2) : "-";
}

//! The seconds of set-up phase `phase` ("-" when the row has no such phase).
std::string setup_phase(const Json& row, const std::string& phase) {
  for (const Json& timing : row.value("setup_phases", Json::array())) {
    if (timing["phase"] == phase) return bench::fixed(timing["seconds"], 3);
  }
  return "-";
}

//! The median over the poses of transfer phase `phase`, in milliseconds.
std::string pose_phase_median(const Json& row, const std::string& phase) {
  std::vector<double> seconds;
  for (const Json& pose : row.value("poses", Json::array())) {
    for (const Json& timing : pose["phases"]) {
      if (timing["phase"] == phase) seconds.push_back(timing["seconds"].get<double>());
    }
  }
  return seconds.empty() ? "-" : milliseconds(Json(median(seconds)));
}

std::string matched_text(const Json& row) {
  if (row["method"] != "correspondence") return "-";
  return bench::integer(row, "matched_triangles") + " / " +
         bench::integer(row, "unmatched_triangles");
}

std::string folds_text(const Json& row) {
  if (!row.contains("poses_folding_more")) return "-";
  return std::to_string(row["poses_folding_more"].get<int>()) + " of " +
         std::to_string(row["poses"].size());
}

//! Each pose's "flipped/source-folded", e.g. "20/46, 2/11": the folds behind folds_text.
std::string per_pose_folds_text(const Json& row) {
  std::ostringstream text;
  for (const Json& pose : row.value("poses", Json::array())) {
    if (text.tellp() > 0) text << ", ";
    text << bench::integer(pose, "flipped_triangles") << "/"
         << bench::integer(pose, "source_folded_triangles");
  }
  return text.tellp() > 0 ? text.str() : "-";
}

//! The columns every table shares: set-up and its phases, matches, the poses, error, folds.
std::string shared_columns(const Json& row) {
  std::ostringstream columns;
  columns << bench::fixed(row.value("setup_seconds", Json()), 3) << " | "
          << setup_phase(row, "fields") << " | " << setup_phase(row, "correspondence") << " | "
          << setup_phase(row, "factorization") << " | " << matched_text(row) << " | "
          << milliseconds(row.value("pose_median_seconds", Json())) << " | "
          << milliseconds(row.value("pose_max_seconds", Json())) << " | "
          << percent(row.value("error_median", Json())) << " | " << folds_text(row) << " | "
          << bench::status_text(row);
  return columns.str();
}

constexpr const char* kSharedHeader =
    "set-up s | fields | correspondence | factorization | matched / unmatched | pose ms median | "
    "pose ms max | cat-01 error % | poses folding more | status |";
constexpr const char* kSharedAlignment = "---:|---:|---:|---:|---|---:|---:|---:|---|---|";

void main_markdown(const Json& main_rows, std::ostringstream& md) {
  md << "## lion -> cat\n\n"
     << "Every marker pair, 1x (lion " << main_rows[0].value("source_faces", 0) << " faces, cat "
     << main_rows[0].value("target_faces", 0) << " faces). set-up: the DeformationTransfer "
     << "constructor (wall clock, fastest of --repeat) and its SolveReport phases (s; fields also "
     << "holds the deformation-gradient and load set-up, validation is not shown). pose ms: "
     << "transfer() per pose (fastest of --repeat), median and max over the poses; split: the "
     << "medians of its phases (deformations, assembly, solve with placement and fold counts). "
     << "cat-01 error: RMS vertex distance to the true cat-01 after the best rigid alignment, % "
     << "of its bounding-box diagonal (median over the poses with a truth: cat-01 only). poses "
     << "folding more: poses whose result folds more target triangles "
     << "(report.flipped_triangles) than the source pose folds of the lion "
     << "(source_folded_triangles).\n\n"
     << "| method | " << kSharedHeader << " pose split ms |\n|---|" << kSharedAlignment << "---|\n";
  for (const Json& row : main_rows) {
    md << "| " << row["method"].get<std::string>() << " | " << shared_columns(row) << " | "
       << pose_phase_median(row, "deformations") << ", " << pose_phase_median(row, "assembly")
       << ", " << pose_phase_median(row, "solve") << " |\n";
  }

  md << "\n### Per pose\n\nms: transfer(), fastest of --repeat. folds target / source: "
     << "report.flipped_triangles / source_folded_triangles. error: as above, where the pose "
     << "has a truth.\n\n| pose |";
  for (const Json& row : main_rows) {
    const std::string method = row["method"].get<std::string>();
    md << " " << method << " ms | " << method << " folds target / source | " << method
       << " error % |";
  }
  md << "\n|---|";
  for (std::size_t k = 0; k < main_rows.size(); ++k) md << "---:|---:|---:|";
  md << "\n";
  std::size_t pose_count = 0;
  for (const Json& row : main_rows)
    pose_count = std::max(pose_count, row.value("poses", Json::array()).size());
  for (std::size_t k = 0; k < pose_count; ++k) {
    std::string name;
    std::ostringstream cells;
    for (const Json& row : main_rows) {
      const Json poses = row.value("poses", Json::array());
      if (k >= poses.size()) {
        cells << " - | - | - |";
        continue;
      }
      const Json& pose = poses[k];
      name = pose["pose"].get<std::string>();
      const bool more =
          pose["flipped_triangles"].get<int>() > pose["source_folded_triangles"].get<int>();
      cells << " " << milliseconds(pose["seconds"]) << " | "
            << bench::integer(pose, "flipped_triangles") << " / "
            << bench::integer(pose, "source_folded_triangles") << (more ? " (MORE)" : "") << " | "
            << percent(pose.value("error", Json())) << " |";
    }
    md << "| " << name << " |" << cells.str() << "\n";
  }
}

void marker_growth_markdown(const Json& rows, const std::string& subset, int all_pairs,
                            std::ostringstream& md) {
  md << "\n## Growth with marker count\n\n"
     << "Correspondence method, 1x. Pairs: "
     << (subset == "spread" ? "pair floor(i * " + std::to_string(all_pairs) +
                                  " / n) of the file for i = 0..n-1 (spread over the body; the "
                                  "file lists paws and legs first)"
                            : std::string("the first n of the file"))
     << ". Columns as above; folds per pose: flipped / source-folded triangles of each pose.\n\n"
     << "| markers | " << kSharedHeader << " folds per pose |\n|---:|" << kSharedAlignment
     << "---|\n";
  for (const Json& row : rows) {
    md << "| " << row.value("markers", row["marker_count"].get<int>()) << " | "
       << shared_columns(row) << " | " << per_pose_folds_text(row) << " |\n";
  }
}

void size_growth_markdown(const Json& rows, std::ostringstream& md) {
  md << "\n## Growth with mesh size\n\n"
     << "Correspondence method, every marker pair; both meshes, the lion's poses and cat-01 "
     << "subdivided 1 -> 4 per step (midpoint subdivision, subdivide.py; the marker vertices "
     << "keep their indices). Columns as above; folds per pose: flipped / source-folded "
     << "triangles of each pose.\n\n"
     << "| size | lion faces | cat faces | " << kSharedHeader
     << " folds per pose |\n|---|---:|---:|" << kSharedAlignment << "---|\n";
  for (const Json& row : rows) {
    md << "| x" << row["factor"].get<int>() << " | " << bench::integer(row, "source_faces") << " | "
       << bench::integer(row, "target_faces") << " | " << shared_columns(row) << " | "
       << per_pose_folds_text(row) << " |\n";
  }
}

void targets_markdown(const Json& targets, std::ostringstream& md) {
  md << "\n## Targets (1x, every marker pair)\n\n| target | measured | limit | met |\n"
     << "|---|---:|---|---|\n";
  for (const Json& target : targets) {
    const Json& met = target["met"];
    md << "| " << target["target"].get<std::string>() << " | "
       << target["measured"].get<std::string>() << " | " << target["limit"].get<std::string>()
       << " | " << (met.is_boolean() ? (met.get<bool>() ? "yes" : "NO") : "n/a") << " |\n";
  }
}

std::string markdown(const Json& results) {
  std::ostringstream md;
  const Json& host = results["host"];
  md << "# harmonia deformation-transfer benchmark\n\n"
     << "Host: " << host["cpu"].get<std::string>() << ", " << host["cores"]
     << " cores; load average " << host["load_start"].get<std::string>() << " at start, "
     << host["load_end"].get<std::string>()
     << " at end. CPU backend; OpenBLAS threads: " << results["blas_threads"].get<std::string>()
     << ". Timings: fastest of " << results["repeat"]
     << " run(s). Each row in its own process, capped at " << results["timeout"] << " s.\n\n";
  main_markdown(results["lion_cat"], md);
  if (!results["marker_growth"].empty()) {
    marker_growth_markdown(results["marker_growth"], results["marker_subset"].get<std::string>(),
                           results["marker_pairs"].get<int>(), md);
  }
  if (!results["size_growth"].empty()) size_growth_markdown(results["size_growth"], md);
  targets_markdown(results["targets"], md);
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

  // Every size's files first (subdividing takes seconds and is no part of any row's time).
  std::vector<int> sizes{1};
  if (options.size_growth) {
    for (const int size : options.sizes) {
      if (std::find(sizes.begin(), sizes.end(), size) == sizes.end()) sizes.push_back(size);
    }
  }
  std::map<int, TransferCorpus> corpora;
  for (const int size : sizes) {
    std::string message;
    if (auto corpus = transfer_corpus(size, &message)) {
      corpora.emplace(size, std::move(*corpus));
    } else if (size == 1) {
      std::cerr << "corpus_transfer_benchmark: " << message << "\n";
      return 1;
    } else {
      std::cerr << "corpus_transfer_benchmark: x" << size << ": " << message << "\n";
    }
  }
  int all_markers = 0;
  try {
    // Parsed here only to count the pairs; each child reads the file with its meshes' sizes.
    const TransferCorpus& corpus = corpora.at(1);
    all_markers =
        static_cast<int>(harmonia::read_marker_file(corpus.markers, std::numeric_limits<int>::max(),
                                                    std::numeric_limits<int>::max())
                             .size());
  } catch (const std::exception& error) {
    std::cerr << "corpus_transfer_benchmark: " << error.what() << "\n";
    return 1;
  }

  Json results{{"host", Json{{"cpu", bench::host_cpu_model()},
                             {"cores", static_cast<int>(::sysconf(_SC_NPROCESSORS_ONLN))},
                             {"load_start", bench::host_load_average()}}},
               {"blas_threads", bench::blas_policy_name(options.run.blas_threads)},
               {"repeat", options.run.repeat},
               {"timeout", options.run.timeout_seconds},
               {"marker_pairs", all_markers},
               {"marker_subset", subset_name(options.marker_subset)},
               {"lion_cat", Json::array()},
               {"marker_growth", Json::array()},
               {"size_growth", Json::array()}};
  RowCache rows(options, std::move(corpora), all_markers);
  for (const TransferMethod method : {TransferMethod::correspondence, TransferMethod::quaternion}) {
    results["lion_cat"].push_back(rows.row({method, 1, all_markers}));
  }
  if (options.marker_growth) {
    for (const int count : options.marker_counts) {
      results["marker_growth"].push_back(rows.row({TransferMethod::correspondence, 1, count}));
    }
  }
  if (options.size_growth) {
    for (const int size : options.sizes) {
      results["size_growth"].push_back(
          rows.row({TransferMethod::correspondence, size, all_markers}));
    }
  }

  results["host"]["load_end"] = bench::host_load_average();
  results["targets"] = targets(results["lion_cat"]);

  const std::string report = markdown(results);
  std::cout << report;
  std::ofstream(options.run.out_md) << report;
  std::ofstream(options.run.out_json) << results.dump(2) << "\n";
  return 0;
}
