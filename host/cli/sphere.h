#pragma once
//! \file sphere.h
//! \brief `harmonia sphere IN OUT [--poles N S] [--weights cotangent|mean-value] [--rounds K]
//! [--relax-rings R] [--relax-steps S] [--method curvilinear|relaxation] [--uv]
//! [--picture FILE.png] [--json]`: map a closed genus-0 mesh onto the unit sphere (thesis
//! chapter 7).

#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include <nlohmann/json.hpp>

#include "cli/common.h"
#include "cli/report_output.h"
#include "harmonia/gltf.h"
#include "harmonia/spherical_metrics.h"

namespace harmonia::cli {

struct SphereOptions {
  std::string input;
  std::string output;
  bool in_place = false;
  std::vector<int> poles;              //!< Empty or two vertex indices (north, south).
  std::string weights = "cotangent";  //!< cotangent or mean-value.
  std::optional<int> rounds;
  std::optional<int> relax_rings;
  std::optional<int> relax_steps;
  std::string method = "curvilinear";  //!< curvilinear or relaxation.
  std::string backend = "auto";
  std::string preconditioner = "multilevel";  //!< multilevel or jacobi (device solves).
  bool uv = false;      //!< Also write longitude/latitude vt per corner.
  bool positions = false;  //!< glTF output: the sphere points as positions, not a texcoord set.
  GltfWriteOptions gltf;   //!< glTF output: --texcoord and --overwrite.
  std::string picture;  //!< Also draw the map (PNG); empty: no picture.
  bool json = false;
};

CLI::App* add_sphere_command(CLI::App& app, SphereOptions& options);

//! The scalar fields of spherical metrics (also `harmonia eval --sphere`).
[[nodiscard]] nlohmann::json spherical_metrics_json(const SphericalMetrics& metrics);
void add_spherical_metrics_rows(FieldTable& table, const SphericalMetrics& metrics);
//! Writes OUT (OBJ: v = unit-sphere points in the input's order, the input's faces), the picture
//! if asked (also of a map with flipped triangles), and prints the report. ok; invalid_result when
//! the map has triangles turned over on the sphere (OUT and the picture are still written); input
//! for a mesh that is not a closed genus-0 surface.
[[nodiscard]] ExitCode run_sphere(const SphereOptions& options, const GlobalOptions& global);

}  // namespace harmonia::cli
