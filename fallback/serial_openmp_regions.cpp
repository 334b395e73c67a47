#include "fallback/serial_openmp_regions.h"

#ifdef HARMONIA_HAVE_OPENMP
#include <omp.h>
#endif

namespace harmonia::detail {

#ifdef HARMONIA_HAVE_OPENMP
SerialOpenMpRegions::SerialOpenMpRegions() : previous_(omp_get_max_active_levels()) {
  omp_set_max_active_levels(0);
}
SerialOpenMpRegions::~SerialOpenMpRegions() { omp_set_max_active_levels(previous_); }
bool SerialOpenMpRegions::serial_now() { return omp_get_max_active_levels() == 0; }
#else
SerialOpenMpRegions::SerialOpenMpRegions() = default;
SerialOpenMpRegions::~SerialOpenMpRegions() = default;
bool SerialOpenMpRegions::serial_now() { return true; }
#endif

}  // namespace harmonia::detail
