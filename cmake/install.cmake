# Installation and the CMake package config, so that a consumer can write
#   find_package(harmonia REQUIRED)  target_link_libraries(app PRIVATE harmonia::harmonia)
include(CMakePackageConfigHelpers)

install(TARGETS harmonia EXPORT harmoniaTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# harmonia/vulkan_context.h is installed only with the Vulkan backend (it needs the Vulkan headers,
# which a consumer finds on the system include path).
set(HARMONIA_HEADER_EXCLUDES)
if(NOT HARMONIA_WITH_VULKAN)
  set(HARMONIA_HEADER_EXCLUDES PATTERN "vulkan_context.h" EXCLUDE)
endif()
install(DIRECTORY ${PROJECT_SOURCE_DIR}/host/harmonia DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.h" ${HARMONIA_HEADER_EXCLUDES})

set(HARMONIA_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/harmonia)
install(EXPORT harmoniaTargets NAMESPACE harmonia:: DESTINATION ${HARMONIA_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/harmoniaConfig.cmake.in
  ${PROJECT_BINARY_DIR}/harmoniaConfig.cmake INSTALL_DESTINATION ${HARMONIA_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/harmoniaConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/harmoniaConfig.cmake ${PROJECT_BINARY_DIR}/harmoniaConfigVersion.cmake
        DESTINATION ${HARMONIA_CMAKE_DIR})
