#pragma once
//! \file report_output.h
//! \brief How reports look on stdout: aligned "name  value" text for people, JSON for programs.

#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "harmonia/metrics.h"
#include "harmonia/topology.h"
#include "harmonia/types.h"

namespace harmonia::cli {

//! Rows of "name  value" printed with the values lined up in one column.
class FieldTable {
 public:
  void add(std::string name, std::string value);
  void add(std::string name, long long value);
  void add_number(std::string name, double value);
  void add_yes_no(std::string name, bool value);
  void print(std::ostream& out) const;

 private:
  std::vector<std::pair<std::string, std::string>> rows_;
};

//! A number in the text output: 6 significant digits, "inf"/"nan" spelled out.
[[nodiscard]] std::string format_number(double value);

//! Every field of the topology report, plus is_disk, is_closed_manifold and disk_problem.
[[nodiscard]] nlohmann::json topology_json(const TopologyReport& report);

//! The text form of the topology report; index lists are cut after `list_limit` entries.
void add_topology_rows(FieldTable& table, const TopologyReport& report, std::size_t list_limit);

//! The scalar fields of the distortion metrics (the per-face arrays are left out).
[[nodiscard]] nlohmann::json metrics_json(const DistortionMetrics& metrics);
void add_metrics_rows(FieldTable& table, const DistortionMetrics& metrics);

//! Phase timings as {phase: seconds}; a phase recorded more than once (one per round) is summed.
[[nodiscard]] nlohmann::json timings_json(const std::vector<PhaseTiming>& timings);

}  // namespace harmonia::cli
