#include "cli/unwrap.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/gltf_output.h"
#include "cli/methods.h"
#include "cli/progress_line.h"
#include "cli/report_output.h"
#include "harmonia/cleanup.h"
#include "harmonia/cut.h"
#include "harmonia/gltf.h"
#include "harmonia/io.h"
#include "harmonia/laplacian.h"
#include "harmonia/metrics.h"
#include "harmonia/picture.h"
#include "harmonia/view_page.h"
#include "harmonia/topology.h"

namespace harmonia::cli {

namespace {

// The CLI spellings of every weight scheme, for validating --weights.
std::vector<std::string> weight_names() {
  std::vector<std::string> names;
  for (const WeightScheme scheme : all_weight_schemes()) names.emplace_back(to_string(scheme));
  return names;
}

}  // namespace

CLI::App* add_unwrap_command(CLI::App& app, UnwrapOptions& options) {
  CLI::App* command = app.add_subcommand(
      "unwrap", "Flatten a disk-shaped mesh; write an OBJ with one vt per vertex");
  command->add_option("IN", options.input, "Input mesh, a disk (.obj, .off, .ply, .stl)")
      ->required();
  command->add_option("OUT", options.output, "Output OBJ with texture coordinates; or glTF (.glb, .gltf): the input document (or a new one) with the map in a new texture-coordinate set of each primitive")->required();
  add_texcoord_options(*command, options.gltf);
  command->add_flag("--in-place", options.in_place,
                    "Allow OUT to be IN: the input file is replaced by the result");
  command
      ->add_option("--method", options.method,
                   "conformal (fixed boundary, chapter 4), lscm (free boundary, 6.2.2), "
                   "qhm (quasi-harmonic, chapter 5), abf (angle based flattening, chapter 2), "
                   "linabf (linear ABF, chapter 3) or free (free-boundary quasi-harmonic, "
                   "chapter 6); default conformal")
      ->check(CLI::IsMember({"conformal", "lscm", "qhm", "abf", "linabf", "free"}));
  command
      ->add_option("--weights", options.weights,
                   "Laplacian weights for conformal (default cotangent); qhm takes cotangent "
                   "(default) or mean-value; free takes cotangent (default, mean-value where it "
                   "folds) or mean-value for its start map and its polish")
      ->check(CLI::IsMember(weight_names()));
  command->add_flag("--polish", options.polish,
                    "free: add the fixed-boundary quasi-harmonic polish P3 with P2's boundary");
  command
      ->add_option("--stop-after", options.stop_after,
                   "free: conformal (P1, the boundary-free conformal map) or quasi-harmonic "
                   "(P2, default)")
      ->check(CLI::IsMember({"conformal", "quasi-harmonic"}));
  command
      ->add_option("--boundary", options.boundary,
                   "Boundary shape for conformal and qhm: circle (default) or square")
      ->check(CLI::IsMember({"circle", "square"}));
  command
      ->add_option("--rounds", options.rounds,
                   "qhm: most rounds (default 5); linabf: linearization rounds (default: one, "
                   "and a second when the first leaves invalid angles or flips)")
      ->check(CLI::Range(1, 100));
  command->add_option("--boundary-t", options.boundary_t,
                      "abf: boundary control t, sum of the angles at a boundary vertex <= t pi "
                      "(default 2: classic ABF; 1: convex boundary; 1-2/n < t < 1: concave)");
  command
      ->add_option("--solver", options.solver,
                   "abf: linear solver of each Newton step: auto (default), schur-minres, "
                   "uzawa, full-minres, full-cgnr, schur-direct (cpu only)")
      ->check(CLI::IsMember(
          {"auto", "schur-minres", "uzawa", "full-minres", "full-cgnr", "schur-direct"}));
  command
      ->add_option("--reconstruction", options.reconstruction,
                   "abf and linabf: angles to UVs by lsq (least squares, default) or greedy")
      ->check(CLI::IsMember({"lsq", "greedy"}));
  command->add_flag("--underdetermined", options.underdetermined,
                    "abf: no objective, just the feasible angles nearest the 3D ones (2.4.3)");
  command
      ->add_option("--backend", options.backend,
                   "cpu, vulkan, or auto (default: Vulkan where a device exists, else cpu)")
      ->check(CLI::IsMember({"auto", "cpu", "vulkan"}));
  command->add_option("--preconditioner", options.preconditioner, preconditioner_help)
      ->check(CLI::IsMember({"multilevel", "jacobi"}));
  command
      ->add_option("--normalize", options.normalize,
                   "UV scale: surface-area (default, UV area = 3D area), unit-square, none")
      ->check(CLI::IsMember({"surface-area", "unit-square", "none"}));
  command
      ->add_option("--cleanup", options.cleanup,
                   "strict (default: refuse dirty input and say why) or repair (merge "
                   "duplicates, drop degenerate faces, fix orientation)")
      ->check(CLI::IsMember({"strict", "repair"}));
  command->add_option("--picture", options.picture,
                      "Also draw the layout coloured by conformal distortion (.svg or .png)");
  command->add_option("--view", options.view,
                      "Also write a page to look at the layout in a browser (.html; see `harmonia view`)");
  command->add_flag("--cut", options.cut,
                    "Cut a mesh that is not a disk (closed, several holes, higher genus) with "
                    "`harmonia cut`'s method first; the OBJ then has one vt per disk vertex and "
                    "faces f a/ta b/tb c/tc (seams get several vt)");
  command->add_flag("--json", options.json, "Print the report as one JSON object");
  return command;
}

namespace {

// Turns the option strings into a method choice, refusing combinations that mean nothing
// (e.g. a boundary shape for LSCM, whose boundary is free).
MethodChoice method_choice(const UnwrapOptions& options) {
  MethodChoice choice;
  if (options.method == "lscm") {
    choice.method = MethodKind::lscm;
    if (options.weights || options.boundary) {
      throw CliFailure(ExitCode::usage,
                       "--weights and --boundary do not apply to --method lscm (free boundary)");
    }
  } else if (options.method == "qhm") {
    choice.method = MethodKind::qhm;
  } else if (options.method == "abf") {
    choice.method = MethodKind::abf;
  } else if (options.method == "linabf") {
    choice.method = MethodKind::linabf;
  } else if (options.method == "free") {
    choice.method = MethodKind::free;
    if (options.boundary)
      throw CliFailure(ExitCode::usage, "--boundary does not apply to --method free (free boundary)");
  }
  if ((options.polish || options.stop_after) && choice.method != MethodKind::free)
    throw CliFailure(ExitCode::usage, "--polish and --stop-after apply to --method free only");
  if (options.polish && options.stop_after == "conformal")
    throw CliFailure(ExitCode::usage,
                     "--polish needs --stop-after quasi-harmonic (P3 starts from P2)");
  choice.polish = options.polish;
  choice.stop_after_conformal = options.stop_after == "conformal";
  const bool angle_based =
      choice.method == MethodKind::abf || choice.method == MethodKind::linabf;
  if (angle_based && (options.weights || options.boundary)) {
    throw CliFailure(ExitCode::usage, "--weights and --boundary do not apply to --method " +
                                          options.method + " (free boundary)");
  }
  if (options.rounds && choice.method != MethodKind::qhm && choice.method != MethodKind::linabf) {
    throw CliFailure(ExitCode::usage, "--rounds applies to --method qhm and linabf only");
  }
  if ((options.boundary_t || options.solver || options.underdetermined) &&
      choice.method != MethodKind::abf) {
    throw CliFailure(ExitCode::usage,
                     "--boundary-t, --solver and --underdetermined apply to --method abf only");
  }
  if (options.reconstruction && !angle_based) {
    throw CliFailure(ExitCode::usage, "--reconstruction applies to --method abf and linabf only");
  }
  if (options.boundary_t) choice.boundary_t = *options.boundary_t;
  if (options.solver) {
    const std::string& name = *options.solver;
    if (name == "schur-minres") choice.abf_solver = AbfSolver::schur_minres;
    if (name == "uzawa") choice.abf_solver = AbfSolver::uzawa;
    if (name == "full-minres") choice.abf_solver = AbfSolver::full_minres;
    if (name == "full-cgnr") choice.abf_solver = AbfSolver::full_cgnr;
    if (name == "schur-direct") choice.abf_solver = AbfSolver::schur_direct;
  }
  choice.underdetermined = options.underdetermined;
  if (options.reconstruction == "greedy") choice.reconstruction = AngleReconstruction::greedy;
  if (options.rounds && choice.method == MethodKind::linabf) choice.linabf_rounds = *options.rounds;
  if (options.weights) choice.weights = *weight_scheme_from_string(*options.weights);
  if ((choice.method == MethodKind::qhm || choice.method == MethodKind::free) &&
      choice.weights != WeightScheme::cotangent && choice.weights != WeightScheme::mean_value) {
    throw CliFailure(ExitCode::usage, "--method " + options.method +
                                          " takes --weights cotangent or mean-value (the tensor "
                                          "forms of chapter 5), not " +
                                          *options.weights);
  }
  if (options.boundary == "square") choice.boundary = BoundaryShape::square;
  if (options.rounds) choice.rounds = *options.rounds;
  choice.backend = backend_choice(options.backend);
  choice.preconditioner = preconditioner_choice(options.preconditioner);
  if (options.normalize == "unit-square") choice.normalization = UvNormalization::unit_square;
  if (options.normalize == "none") choice.normalization = UvNormalization::none;
  return choice;
}

// The mesh the method runs on (a disk), and how its vertices relate to the input's.
struct PreparedMesh {
  Mesh surface;  // The input after cleanup (equal to the input in strict mode).
  Mesh mesh;     // The disk that is mapped: `surface`, or `surface` cut open along seams.
  bool was_cut = false;
  Eigen::VectorXi cut_original_vertex;  // Disk vertex -> surface vertex (only when was_cut).
  int seam_edges = 0;
  bool repaired = false;
  Eigen::VectorXi vertex_map;       // Input vertex -> prepared vertex, or -1 (repair only).
  Eigen::VectorXi original_vertex;  // Prepared vertex -> input vertex (repair only).
  Eigen::VectorXi original_face;    // Prepared face -> input face (repair only).
  std::vector<std::string> changes;
};

PreparedMesh prepare_mesh(const Mesh& input, const UnwrapOptions& options) {
  const bool repair = options.cleanup == "repair";
  CleanupOptions cleanup_options;
  cleanup_options.mode = repair ? CleanupMode::repair : CleanupMode::strict;
  CleanupResult cleaned = cleanup(input, cleanup_options);
  if (cleaned.status != Status::ok) {
    std::string reason = options.input + ": " + cleaned.message;
    // Point at the CLI spelling only where the library says repair mode can fix it.
    if (!repair && cleaned.message.find("repair mode") != std::string::npos) {
      reason += " (`--cleanup repair`)";
    }
    throw CliFailure(ExitCode::input, reason);
  }
  PreparedMesh prepared;
  prepared.repaired = repair;
  prepared.changes = cleaned.changes;
  if (repair) {
    prepared.vertex_map = std::move(cleaned.vertex_map);
    prepared.original_vertex = std::move(cleaned.original_vertex);
    prepared.original_face = std::move(cleaned.original_face);
    prepared.surface = std::move(cleaned.mesh);
  } else {
    prepared.surface = input;
  }
  prepared.mesh = prepared.surface;

  std::string problem;
  const Status disk = check_disk(prepared.mesh, &problem);
  if (disk == Status::not_a_disk && options.cut) {
    CutResult cut = cut_to_disk(prepared.surface);
    if (cut.status != Status::ok) {
      throw CliFailure(ExitCode::input, options.input + ": cannot cut into a disk: " + cut.message);
    }
    prepared.mesh = std::move(cut.disk);
    prepared.cut_original_vertex = std::move(cut.original_vertex);
    prepared.seam_edges = cut.seam_edges;
    prepared.was_cut = true;
    return prepared;
  }
  if (disk != Status::ok) {
    std::string reason = options.input + " is not a disk: " + problem;
    if (disk == Status::not_a_disk && problem.find("harmonia cut") == std::string::npos) {
      reason += "; run `harmonia cut` first";
    }
    if (disk == Status::not_a_disk) reason += " (or pass --cut)";
    if (disk != Status::not_a_disk && !repair) reason += "; `--cleanup repair` may fix it";
    throw CliFailure(ExitCode::input, reason);
  }
  return prepared;
}

// The written file keeps the input's vertices in the input's order. After a repair, faces are the
// repaired faces renumbered back to input vertices. Without a cut each input vertex takes the UV of
// the vertex it became (a removed, unreferenced vertex gets (0, 0)) and uv_faces equal the faces;
// after a cut the UVs are the disk's, one per disk vertex, addressed per corner by the disk faces
// (whose order is the surface's face order).
TexturedMesh layout_for_input(const Mesh& input, const PreparedMesh& prepared,
                              const Eigen::MatrixX2d& uv) {
  TexturedMesh layout;
  layout.mesh.vertices = input.vertices;
  layout.mesh.faces = prepared.surface.faces;
  if (prepared.repaired) {
    for (int face = 0; face < prepared.surface.face_count(); ++face) {
      for (int corner = 0; corner < 3; ++corner) {
        layout.mesh.faces(face, corner) =
            prepared.original_vertex(prepared.surface.faces(face, corner));
      }
    }
  }
  if (prepared.was_cut) {
    layout.uv = uv;
    layout.uv_faces = prepared.mesh.faces;
    return layout;
  }
  if (!prepared.repaired) {
    layout.uv = uv;
  } else {
    layout.uv = Eigen::MatrixX2d::Zero(input.vertex_count(), 2);
    for (int vertex = 0; vertex < input.vertex_count(); ++vertex) {
      const int target = prepared.vertex_map(vertex);
      if (target >= 0) layout.uv.row(vertex) = uv.row(target);
    }
  }
  layout.uv_faces = layout.mesh.faces;
  return layout;
}

bool is_angle_based(const MethodChoice& choice) {
  return choice.method == MethodKind::abf || choice.method == MethodKind::linabf;
}

// The angle figures are reported for the angle-based methods only (null for the others).
nlohmann::json report_json(const UnwrapOptions& options, const MethodChoice& choice,
                           const SolveReport& report, std::vector<PhaseTiming> timings,
                           const AngleFigures& angle_figures) {
  const bool has_weights = choice.method == MethodKind::conformal ||
                           choice.method == MethodKind::qhm || choice.method == MethodKind::free;
  const bool has_boundary_shape =
      choice.method == MethodKind::conformal || choice.method == MethodKind::qhm;
  std::vector<PhaseTiming> all_timings = report.timings;
  all_timings.insert(all_timings.end(), timings.begin(), timings.end());
  return {
      {"status", std::string(to_string(report.status))},
      {"message", report.message},
      {"input", options.input},
      {"output", options.output},
      {"method", std::string(to_string(choice.method))},
      {"weights", has_weights ? nlohmann::json(std::string(to_string(choice.weights))) : nullptr},
      {"boundary",
       has_boundary_shape ? nlohmann::json(options.boundary.value_or("circle")) : nullptr},
      {"normalize", options.normalize},
      {"cleanup", options.cleanup},
      {"backend", std::string(to_string(report.backend))},
      {"solver", report.solver},
      {"device", report.device},
      {"backend_notice", report.backend_notice},
      {"precision", report.precision},
      {"iterations", report.iterations},
      {"residual", report.residual},
      {"rounds", report.rounds},
      {"abf_energy",
       is_angle_based(choice) ? nlohmann::json(angle_figures.abf_energy) : nullptr},
      {"boundary_t",
       is_angle_based(choice) ? nlohmann::json(angle_figures.boundary_t) : nullptr},
      {"constraint_residual",
       is_angle_based(choice) ? nlohmann::json(report.constraint_residual) : nullptr},
      {"flipped_triangles", report.flipped_triangles},
      {"degenerate_triangles", report.degenerate_triangles},
      {"boundary_self_intersections", report.boundary_self_intersections},
      {"timings", timings_json(all_timings)},
      {"fallbacks", report.fallbacks},
  };
}

// The method as a picture's title names it: "free (cotangent)", "lscm".
std::string method_title(const MethodChoice& choice) {
  const bool has_weights = choice.method == MethodKind::conformal ||
                           choice.method == MethodKind::qhm || choice.method == MethodKind::free;
  return std::string(to_string(choice.method)) +
         (has_weights ? " (" + std::string(to_string(choice.weights)) + ")" : std::string());
}

std::string method_description(const UnwrapOptions& options, const MethodChoice& choice) {
  if (choice.method == MethodKind::lscm) return "lscm (free boundary)";
  if (is_angle_based(choice)) {
    const std::string reconstruction = options.reconstruction.value_or("lsq");
    if (choice.method == MethodKind::linabf)
      return "linabf (free boundary, " + reconstruction + " reconstruction)";
    char t[32];
    std::snprintf(t, sizeof t, "%g", choice.boundary_t);
    return "abf (t = " + std::string(t) + ", solver " + options.solver.value_or("auto") + ", " +
           reconstruction + " reconstruction" +
           (choice.underdetermined ? ", underdetermined" : "") + ")";
  }
  if (choice.method == MethodKind::free) {
    const std::string steps =
        choice.stop_after_conformal ? "P0-P1" : (choice.polish ? "P0-P3" : "P0-P2");
    return "free (free boundary, " + std::string(to_string(choice.weights)) + " weights, " +
           steps + ")";
  }
  std::string text = std::string(to_string(choice.method)) + " (" + std::string(to_string(choice.weights)) +
                     " weights, " + options.boundary.value_or("circle") + " boundary";
  if (choice.method == MethodKind::qhm)
    text += ", " + std::to_string(choice.rounds) + " rounds max";
  return text + ")";
}

}  // namespace

ExitCode run_unwrap(const UnwrapOptions& options, const GlobalOptions& global) {
  // Refuse a bad command line before any expensive work.
  require_extension(options.output, {".obj", ".gltf", ".glb"}, "output");
  if (!options.picture.empty()) require_extension(options.picture, {".svg", ".png"}, "picture");
  const MethodChoice choice = method_choice(options);
  check_output(options.input, options.output, options.in_place, "OUT");
  if (!options.picture.empty()) check_output(options.input, options.picture, false, "--picture");
  if (!options.view.empty()) {
    require_extension(options.view, {".html"}, "view");
    check_output(options.input, options.view, false, "--view");
  }

  ProgressLine progress(global, options.json);
  std::vector<PhaseTiming> timings;
  auto start = Clock::now();
  progress.show("reading " + options.input);
  const Mesh input = load_mesh(options.input);
  timings.push_back({"read", seconds_since(start)});

  start = Clock::now();
  const PreparedMesh prepared = prepare_mesh(input, options);
  timings.push_back({"cleanup", seconds_since(start)});
  progress.clear();
  for (const std::string& change : prepared.changes) note(global, "cleanup: " + change);
  if (prepared.was_cut) {
    note(global, "cut: " + options.input + " cut open along " +
                     std::to_string(prepared.seam_edges) + " seam edges");
  }

  progress.show(std::string(to_string(choice.method)));
  AngleFigures angle_figures;
  const MapResult result = run_method(prepared.mesh, choice, progress.callback(), &angle_figures);
  progress.clear();
  const SolveReport& report = result.report;
  // A method that stops short of convergence with a map (abf: its best Newton iterate) still
  // writes it, as a map with flipped triangles is written: the exit code says what it is.
  const bool have_map = report.status == Status::ok || report.status == Status::flipped_triangles ||
                        (report.status == Status::not_converged &&
                         result.uv.rows() == prepared.mesh.vertex_count() && result.uv.allFinite());
  if (!have_map) {
    if (options.json)
      std::cout << report_json(options, choice, report, timings, angle_figures).dump(2) << '\n';
    throw CliFailure(exit_code_for(report.status),
                     options.input + ": " + std::string(to_string(choice.method)) + " failed (" +
                         std::string(to_string(report.status)) + "): " + report.message);
  }

  start = Clock::now();
  const DistortionMetrics metrics = evaluate_map(prepared.mesh, result.uv, prepared.mesh.faces);
  timings.push_back({"metrics", seconds_since(start)});

  start = Clock::now();
  progress.show("writing " + options.output);
  const TexturedMesh layout = layout_for_input(input, prepared, result.uv);
  if (is_gltf_path(options.output)) {
    write_layout_gltf(options.input, options.output, layout, options.gltf);
  } else if (const std::optional<ObjAsset> asset = kept_obj_asset(options.input); asset) {
    write_output([&] { write_obj(options.output, layout, *asset, prepared.original_face); });
  } else {
    write_output([&] { write_obj(options.output, layout); });
  }
  timings.push_back({"write", seconds_since(start)});
  if (!options.picture.empty()) {
    start = Clock::now();
    progress.show("drawing " + options.picture);
    PictureOptions picture;
    picture.title = std::filesystem::path(options.input).filename().string() + " - " +
                    method_title(choice) + " - " + picture_headline(metrics);
    write_output([&] {
      write_picture(options.picture, prepared.mesh, result.uv, prepared.mesh.faces, picture);
    });
    timings.push_back({"picture", seconds_since(start)});
  }
  if (!options.view.empty()) {
    start = Clock::now();
    progress.show("writing " + options.view);
    ViewPageOptions page;
    page.title = std::filesystem::path(options.input).filename().string() + " - " + method_title(choice);
    write_output([&] {
      write_view_page(options.view, {{std::filesystem::path(options.output).filename().string(), method_title(choice),
                                      prepared.mesh, result.uv, prepared.mesh.faces}}, page);
    });
    timings.push_back({"view", seconds_since(start)});
  }
  progress.clear();

  if (options.json) {
    nlohmann::json output = report_json(options, choice, report, timings, angle_figures);
    output["metrics"] = metrics_json(metrics);
    output["vertices"] = layout.mesh.vertex_count();
    output["faces"] = layout.mesh.face_count();
    output["uv_vertices"] = layout.uv.rows();
    output["seam_edges"] = prepared.seam_edges;
    output["cleanup_changes"] = prepared.changes;
    if (!options.picture.empty()) output["picture"] = options.picture;
    if (!options.view.empty()) output["view"] = options.view;
    std::cout << output.dump(2) << '\n';
  } else {
    double total = 0.0;
    for (const PhaseTiming& timing : report.timings) total += timing.seconds;
    for (const PhaseTiming& timing : timings) total += timing.seconds;
    FieldTable table;
    table.add("output", options.output);
    table.add("method", method_description(options, choice));
    table.add("backend", std::string(to_string(report.backend)) + " (" + report.solver + ")");
    table.add("device", report.device);
    if (!report.backend_notice.empty()) table.add("backend notice", report.backend_notice);
    if (report.ok() && !report.message.empty()) table.add("note", report.message);
    if (choice.method == MethodKind::qhm) table.add("rounds", report.rounds);
    for (const std::string& fallback : report.fallbacks) table.add("fallback", fallback);
    if (is_angle_based(choice)) {
      table.add("rounds", report.rounds);
      table.add_number("abf energy", angle_figures.abf_energy);
      table.add_number("constraint residual", report.constraint_residual);
      if (angle_figures.boundary_t > 0.0) table.add_number("boundary t", angle_figures.boundary_t);
    }
    table.add("vertices", layout.mesh.vertex_count());
    if (prepared.was_cut) table.add("seam edges", prepared.seam_edges);
    add_metrics_rows(table, metrics);
    table.add_number("seconds", total);
    table.print(std::cout);
  }

  if (report.status == Status::not_converged) {
    throw CliFailure(ExitCode::numerical, options.input + ": " + std::string(to_string(choice.method)) +
                                              " did not converge (" + report.message + "); " +
                                              options.output +
                                              " was written with its last iterate");
  }
  // The status is the library's verdict; the metrics re-count on the result as written. Either
  // finding flips makes the result invalid.
  if (report.status == Status::flipped_triangles || metrics.flipped_triangles > 0) {
    throw CliFailure(ExitCode::invalid_result,
                     "the map has " + std::to_string(metrics.flipped_triangles) +
                         " flipped triangles; " + options.output + " was written anyway");
  }
  return ExitCode::ok;
}

}  // namespace harmonia::cli
