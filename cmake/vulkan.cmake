# The Vulkan compute backend (HARMONIA_WITH_VULKAN): Vulkan headers, glslangValidator, and the
# build-time compilation of shaders/*.comp into SPIR-V arrays embedded in the library.
#
# The library does not link the Vulkan loader: kernels/vulkan_functions.cpp opens libvulkan.so.1 at
# run time, so that a machine without a loader still runs the CPU backend. Only the headers are
# needed to build. Resolution order: an existing Vulkan::Headers target, then find_package(Vulkan)
# (CMake's FindVulkan, honouring VULKAN_SDK), then the system include path.

if(NOT TARGET Vulkan::Headers)
  find_package(Vulkan QUIET)
endif()
if(NOT TARGET Vulkan::Headers)
  find_path(HARMONIA_VULKAN_INCLUDE_DIR vulkan/vulkan_core.h)
  if(NOT HARMONIA_VULKAN_INCLUDE_DIR)
    message(FATAL_ERROR "harmonia: HARMONIA_WITH_VULKAN is ON but the Vulkan headers were not "
                        "found; install libvulkan-dev (Debian) or configure with "
                        "-DHARMONIA_WITH_VULKAN=OFF")
  endif()
  add_library(Vulkan::Headers INTERFACE IMPORTED)
  set_target_properties(Vulkan::Headers PROPERTIES
                        INTERFACE_INCLUDE_DIRECTORIES ${HARMONIA_VULKAN_INCLUDE_DIR})
endif()

find_program(HARMONIA_GLSLANG_VALIDATOR NAMES glslangValidator
             HINTS ${Vulkan_GLSLANG_VALIDATOR_EXECUTABLE} $ENV{VULKAN_SDK}/bin)
if(NOT HARMONIA_GLSLANG_VALIDATOR)
  message(FATAL_ERROR "harmonia: HARMONIA_WITH_VULKAN is ON but glslangValidator was not found; "
                      "install glslang-tools (Debian) or configure with -DHARMONIA_WITH_VULKAN=OFF")
endif()
message(STATUS "harmonia: Vulkan backend on (shaders compiled with ${HARMONIA_GLSLANG_VALIDATOR})")

# harmonia_embed_shaders(<target> <shader dir>)
# Two custom commands per <shader dir>/<name>.comp write <binary dir>/shaders/<name>.spv.h and
# <name>_fp64.spv.h, C arrays named <name>_spv and <name>_fp64_spv, each with a depfile so that
# editing an included shaders/common/*.glsl recompiles exactly the shaders that include it.
# kernels/<name>.cpp includes that header (one translation unit per shader). Nothing is generated
# into the source tree.
function(harmonia_embed_shaders target shader_dir)
  set(output_dir ${PROJECT_BINARY_DIR}/shaders)
  file(MAKE_DIRECTORY ${output_dir})
  file(GLOB shader_sources CONFIGURE_DEPENDS ${shader_dir}/*.comp)
  set(outputs)
  foreach(source ${shader_sources})
    get_filename_component(name ${source} NAME_WE)
    # Two variants per shader: fp32 (<name>_spv) and fp64 (<name>_fp64_spv, HARMONIA_FP64 defined;
    # shaders/common/real.glsl), chosen at pipeline creation (kernels/pipelines.h).
    foreach(variant IN ITEMS "" "_fp64")
      set(defines)
      if(variant STREQUAL "_fp64")
        set(defines -DHARMONIA_FP64)
      endif()
      set(output ${output_dir}/${name}${variant}.spv.h)
      add_custom_command(
        OUTPUT ${output}
        COMMAND ${HARMONIA_GLSLANG_VALIDATOR} --quiet --target-env vulkan1.1 ${defines}
                --vn ${name}${variant}_spv --depfile ${output_dir}/${name}${variant}.d
                -o ${output} ${source}
        MAIN_DEPENDENCY ${source}
        DEPFILE ${output_dir}/${name}${variant}.d
        COMMENT "Compiling shader ${name}.comp to SPIR-V${variant}"
        VERBATIM)
      list(APPEND outputs ${output})
    endforeach()
  endforeach()
  target_sources(${target} PRIVATE ${outputs})
  target_include_directories(${target} PRIVATE ${output_dir})
endfunction()
