#include "fallback/dynamic_openmp_teams.h"

#ifdef HARMONIA_HAVE_OPENMP
#include <omp.h>
#endif

namespace harmonia::detail {

#ifdef HARMONIA_HAVE_OPENMP
DynamicOpenMpTeams::DynamicOpenMpTeams() : previous_(omp_get_dynamic()) { omp_set_dynamic(1); }
DynamicOpenMpTeams::~DynamicOpenMpTeams() { omp_set_dynamic(previous_); }
bool DynamicOpenMpTeams::dynamic_now() { return omp_get_dynamic() != 0; }
#else
DynamicOpenMpTeams::DynamicOpenMpTeams() = default;
DynamicOpenMpTeams::~DynamicOpenMpTeams() = default;
bool DynamicOpenMpTeams::dynamic_now() { return false; }
#endif

}  // namespace harmonia::detail
