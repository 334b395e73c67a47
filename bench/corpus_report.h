#pragma once
// corpus_benchmark's output: the targets met or missed, and the markdown tables (the JSON holds
// the same rows with every field).

#include <cstdio>
#include <limits>
#include <sstream>
#include <string>

#include "bench/corpus_child.h"

namespace harmonia::bench {

inline std::string fixed(const Json& value, int decimals) {
  if (!value.is_number()) return "-";
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value.get<double>());
  return text;
}

inline std::string scientific(const Json& value) {
  if (!value.is_number()) return "-";
  char text[64];
  std::snprintf(text, sizeof text, "%.6g", value.get<double>());
  return text;
}

inline std::string integer(const Json& row, const char* field) {
  return row.contains(field) && row[field].is_number() ? std::to_string(row[field].get<int>())
                                                       : std::string("-");
}

inline std::string phases_text(const Json& row) {
  if (!row.contains("phases") || row["phases"].empty()) return "-";
  std::string text;
  double accounted = 0.0;
  for (const Json& phase : row["phases"]) {
    if (!text.empty()) text += ", ";
    text += phase["phase"].get<std::string>() + " " + fixed(phase["seconds"], 3);
    // ABF reports the reconstruction's own phases as "uv ..." inside its "angles to uv".
    const bool nested = phase["phase"].get<std::string>().rfind("uv ", 0) == 0;
    if (!nested) accounted += phase["seconds"].get<double>();
  }
  if (row["seconds"].is_number()) {
    text += ", (untimed " + fixed(row["seconds"].get<double>() - accounted, 3) + ")";
  }
  return text;
}

//! The backend column: "cpu", or "vulkan", marked when the device is a software one.
inline std::string backend_text(const Json& row, const Json& results) {
  const std::string choice = row.value("backend_choice", std::string("cpu"));
  if (choice != "vulkan") return choice;
  // The device's name is in the header above the table.
  return results["vulkan"].value("software", false) ? "vulkan (software)" : "vulkan";
}

inline std::string solver_text(const Json& row) {
  const std::string solver = row.value("solver", std::string());
  return solver.empty() ? "-" : solver;
}

inline void add_target(Json& list, const std::string& name, const Json& measured, double limit,
                       const std::string& note = {}) {
  const bool met = measured.is_number() && measured.get<double>() <= limit;
  list.push_back(Json{
      {"target", name}, {"measured", measured}, {"limit", limit}, {"met", met}, {"note", note}});
}

//! The CPU row of `key` on `mesh` with a map, or nullptr.
inline const Json* map_row(const Json& runs, const Json& mesh, const std::string& key) {
  for (const Json& row : runs) {
    if (row["mesh"] == mesh && row["key"] == key && row.value("backend_choice", "cpu") == "cpu" &&
        row.contains("area_distortion_mean"))
      return &row;
  }
  return nullptr;
}

//! Issue 17's quality targets of the free-boundary map on every mesh where it ran: its area
//! distortion below LSCM's, linear ABF's and the fixed-circle cotangent map's, and its angle
//! distortion (the ABF measure of the UV angles) below the circle map's (ratios < 1).
inline void add_free_map_quality_targets(const Json& runs, Json& list) {
  for (const Json& row : runs) {
    if (row["key"] != "free" || row.value("backend_choice", "cpu") != "cpu" ||
        !row.contains("area_distortion_mean"))
      continue;
    const std::string mesh = row["mesh"].get<std::string>();
    const double area = row["area_distortion_mean"].get<double>();
    for (const char* other : {"lscm", "linabf", "conformal-cotangent"}) {
      const Json* compared = map_row(runs, row["mesh"], other);
      if (compared == nullptr) continue;
      add_target(list, mesh + " free area distortion / " + other + "'s",
                 area / (*compared)["area_distortion_mean"].get<double>(), 1.0);
    }
    const Json* circle = map_row(runs, row["mesh"], "conformal-cotangent");
    if (circle != nullptr && circle->contains("uv_abf_energy") && row.contains("uv_abf_energy")) {
      add_target(list, mesh + " free uv ABF energy / conformal-cotangent's",
                 row["uv_abf_energy"].get<double>() / (*circle)["uv_abf_energy"].get<double>(),
                 1.0);
    }
  }
}

//! The report's targets, on the CPU rows of the largest scaled mesh: fixed-boundary conformal
//! <= 1.3x floor, quasi-harmonic <= 5x floor, linear ABF <= 4x floor and < 2 GB peak, the
//! free-boundary map <= 3x floor and <= 1.5 GB peak (and its quality on every mesh), and ABF
//! with its best solver <= 10x linear ABF's time at an ABF energy no higher (the best solver: the
//! fastest ABF row whose energy is no higher than linear ABF's, else the fastest ABF row, then
//! marked not met); read_mesh <= 1 s for every timed file.
inline Json targets(const Json& runs, const Json& reading, const std::string& largest_mesh) {
  Json list = Json::array();
  const Json* linear_abf_row = nullptr;
  for (const Json& row : runs) {
    if (row["mesh"] != largest_mesh || row.value("backend_choice", "cpu") != "cpu") continue;
    if (row["key"] == "linabf" && row["status"] == "ok") linear_abf_row = &row;
    if (!row.contains("x_floor")) continue;
    const std::string key = row["key"].get<std::string>();
    const double limit = key == "conformal-cotangent" ? 1.3
                         : key == "qhm"               ? 5.0
                         : key == "linabf"            ? 4.0
                         : key == "free"              ? 3.0
                                                      : 0.0;
    if (limit == 0.0) continue;
    add_target(list, largest_mesh + " " + key + " (x floor)", row["x_floor"], limit,
               row["status"].get<std::string>());
    if (key == "linabf") {
      add_target(list, largest_mesh + " linabf peak (MB)", row.value("peak_MB", Json()), 2048.0);
    }
    if (key == "free") {
      add_target(list, largest_mesh + " free peak (MB)", row.value("peak_MB", Json()), 1536.0);
    }
  }
  add_free_map_quality_targets(runs, list);
  if (linear_abf_row != nullptr && linear_abf_row->contains("abf_energy")) {
    const double linear_seconds = (*linear_abf_row)["seconds"].get<double>();
    const double linear_energy = (*linear_abf_row)["abf_energy"].get<double>();
    const Json* fastest = nullptr;
    const Json* fastest_no_higher = nullptr;
    for (const Json& row : runs) {
      if (row["mesh"] != largest_mesh || row.value("backend_choice", "cpu") != "cpu" ||
          row["method"] != "abf" || row["status"] != "ok" || !row.contains("abf_energy")) {
        continue;
      }
      const auto faster = [&](const Json* than) {
        return than == nullptr || row["seconds"].get<double>() < (*than)["seconds"].get<double>();
      };
      if (faster(fastest)) fastest = &row;
      // "No higher" up to rounding of the energy sum.
      const bool no_higher = row["abf_energy"].get<double>() <= linear_energy * (1.0 + 1e-12);
      if (no_higher && faster(fastest_no_higher)) fastest_no_higher = &row;
    }
    const Json* best = fastest_no_higher != nullptr ? fastest_no_higher : fastest;
    if (best != nullptr) {
      const std::string name = (*best)["key"].get<std::string>();
      add_target(list, largest_mesh + " " + name + " (x linabf time)",
                 (*best)["seconds"].get<double>() / linear_seconds, 10.0);
      add_target(list, largest_mesh + " " + name + " (ABF energy / linabf's)",
                 (*best)["abf_energy"].get<double>() / linear_energy, 1.0 + 1e-12);
    } else {
      add_target(list, largest_mesh + " abf best solver (x linabf time)", Json(), 10.0,
                 "no ABF row finished on this mesh");
    }
  }
  for (const Json& row : reading) {
    if (row["status"] != "ok") continue;
    add_target(list, "read_mesh " + row["file"].get<std::string>() + " (s)", row["seconds"], 1.0);
  }
  return list;
}

inline std::string status_text(const Json& row) {
  const std::string message = row.value("message", std::string());
  return row["status"].get<std::string>() + (message.empty() ? "" : ": " + message);
}

inline std::string markdown(const Json& results) {
  std::ostringstream md;
  md << "# harmonia corpus benchmark\n\n"
     << "Host: " << results["cpu"].get<std::string>() << ", " << results["cores"]
     << " cores; load average " << results["load_start"].get<std::string>() << " at start, "
     << results["load_end"].get<std::string>()
     << " at end. Vulkan: " << results["vulkan"].value("device", std::string("-"))
     << (results["vulkan"].value("software", false)
             ? " (a SOFTWARE device: its times say nothing about a GPU)"
             : "")
     << ". Wall-clock seconds, fastest of " << results["repeat"]
     << " run(s); each (mesh, method, backend) in its own process, capped at " << results["timeout"]
     << " s (--timeout). Slow ABF solvers (" << results["slow_solvers"].get<std::string>()
     << ") run only on meshes up to " << results["slow_max_faces"]
     << " faces (--slow-max-faces); Vulkan rows on a software device only up to "
     << results["software_max_faces"] << " faces (--software-max-faces). x_floor = seconds / "
     << "floor (CHOLMOD supernodal analyze + factorize + solve of the same mesh's cotangent "
     << "Dirichlet system, assembly excluded). peak_MB: peak resident size of that process during "
     << "the method (mesh included). abf_energy: the ABF objective (2.8) of the method's angles. "
     << "uv_abf: the same measure of the layout's UV angles (every method; metrics.h). "
     << "newton: Newton steps (abf), linearization rounds (linabf), rounds (qhm). bnd_x: "
     << "boundary self-intersections.\n\n";
  md << "| mesh | faces | method | variant | backend | solver | seconds | x_floor | peak_MB | "
        "flips | bnd_x | abf_energy | uv_abf | newton | conformal_mean | area_distortion_mean | status |\n"
     << "|---|---:|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
  for (const Json& row : results["runs"]) {
    md << "| " << row["mesh"].get<std::string>() << " | " << row.value("faces", 0) << " | "
       << row["method"].get<std::string>() << " | " << row["variant"].get<std::string>() << " | "
       << backend_text(row, results) << " | " << solver_text(row) << " | "
       << fixed(row.value("seconds", Json()), 3) << " | " << fixed(row.value("x_floor", Json()), 2)
       << " | " << fixed(row.value("peak_MB", Json()), 0) << " | " << integer(row, "flips") << " | "
       << integer(row, "boundary_self_intersections") << " | "
       << scientific(row.value("abf_energy", Json())) << " | "
       << scientific(row.value("uv_abf_energy", Json())) << " | "
       << (row["key"] == "floor" ? std::string("-") : integer(row, "rounds")) << " | "
       << fixed(row.value("conformal_mean", Json()), 4) << " | "
       << fixed(row.value("area_distortion_mean", Json()), 4) << " | " << status_text(row)
       << " |\n";
  }
  md << "\n## Where the time goes (SolveReport phases, seconds)\n\n"
     << "| mesh | method | variant | backend | seconds | phases |\n|---|---|---|---|---:|---|\n";
  for (const Json& row : results["runs"]) {
    if (!row.contains("seconds")) continue;
    md << "| " << row["mesh"].get<std::string>() << " | " << row["method"].get<std::string>()
       << " | " << row["variant"].get<std::string>() << " | "
       << row.value("backend_choice", std::string("cpu")) << " | "
       << fixed(row.value("seconds", Json()), 3) << " | " << phases_text(row) << " |\n";
  }
  if (!results["reading"].empty()) {
    md << "\n## read_mesh (target <= 1 s)\n\n| file | faces | file_MB | seconds | MB/s |\n"
       << "|---|---:|---:|---:|---:|\n";
    for (const Json& row : results["reading"]) {
      if (row["status"] != "ok") {
        md << "| " << row.value("file", std::string("?")) << " | - | - | " << status_text(row)
           << " | - |\n";
        continue;
      }
      md << "| " << row["file"].get<std::string>() << " | " << row["faces"] << " | "
         << fixed(row["file_MB"], 1) << " | " << fixed(row["seconds"], 3) << " | "
         << fixed(row["file_MB"].get<double>() / row["seconds"].get<double>(), 0) << " |\n";
    }
  }
  if (!results["targets"].empty()) {
    md << "\n## Targets (CPU rows)\n\n| target | measured | limit | met | note |\n"
       << "|---|---:|---:|---|---|\n";
    for (const Json& target : results["targets"]) {
      md << "| " << target["target"].get<std::string>() << " | " << fixed(target["measured"], 3)
         << " | " << fixed(target["limit"], 2) << " | "
         << (target["met"].get<bool>() ? "yes" : "NO") << " | "
         << target.value("note", std::string()) << " |\n";
    }
  }
  return md.str();
}

}  // namespace harmonia::bench
