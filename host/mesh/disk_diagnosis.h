#pragma once
// The disk check on an existing report, for callers that already analyzed the mesh (one analysis
// instead of two).

#include <string>

#include "harmonia/topology.h"

namespace harmonia::detail {

//! What check_disk returns for a mesh with this report (indices assumed valid); `message` gets
//! the report's disk_problem().
[[nodiscard]] Status disk_status(const TopologyReport& report, std::string* message);

}  // namespace harmonia::detail
