# Every dependency comes from Debian's packages; see README.md ("Dependencies") for why each is here.
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json 3 REQUIRED)

# stb (stb_image_write encodes PNG pictures, stb_truetype draws their text): header-only,
# Debian's libstb-dev.
find_path(HARMONIA_STB_INCLUDE_DIR stb_image_write.h PATH_SUFFIXES stb REQUIRED)
if(NOT EXISTS ${HARMONIA_STB_INCLUDE_DIR}/stb_truetype.h)
  message(FATAL_ERROR "harmonia: stb_truetype.h is not beside ${HARMONIA_STB_INCLUDE_DIR}/"
                      "stb_image_write.h; install libstb-dev (Debian)")
endif()

# DejaVu Sans (Debian's fonts-dejavu-core): the text of PNG pictures, embedded in the library at
# build time (cmake/embed_file.cmake), so that no font file is needed at run time.
find_file(HARMONIA_FONT_FILE DejaVuSans.ttf
          PATHS /usr/share/fonts/truetype/dejavu /usr/share/fonts/dejavu
          PATH_SUFFIXES truetype/dejavu dejavu)
if(NOT HARMONIA_FONT_FILE)
  message(FATAL_ERROR "harmonia: DejaVuSans.ttf was not found; install fonts-dejavu-core (Debian) "
                      "or pass -DHARMONIA_FONT_FILE=/path/to/DejaVuSans.ttf")
endif()

# three.js (Debian's libjs-three): the 3D views of the pages `harmonia view` writes
# (host/picture/view_page.cpp), embedded in the library at build time with its orbit controls, so
# that a page needs no network and the program no file at run time.
find_path(HARMONIA_THREE_JS_DIR three.min.js PATHS /usr/share/javascript/three NO_DEFAULT_PATH)
if(NOT HARMONIA_THREE_JS_DIR OR NOT EXISTS ${HARMONIA_THREE_JS_DIR}/examples/js/controls/OrbitControls.js)
  message(FATAL_ERROR "harmonia: three.js was not found in /usr/share/javascript/three; install "
                      "libjs-three (Debian) or pass -DHARMONIA_THREE_JS_DIR=/path/to/three (the folder "
                      "of three.min.js and examples/js/controls/OrbitControls.js)")
endif()

add_library(harmonia_private_deps INTERFACE)
target_include_directories(harmonia_private_deps INTERFACE ${HARMONIA_STB_INCLUDE_DIR})
# nlohmann/json (header-only): the edit files of surface editing (host/deform/edit_file.cpp).
target_link_libraries(harmonia_private_deps INTERFACE nlohmann_json::nlohmann_json)

# meshoptimizer and Draco: decoding glTF files compressed with EXT_meshopt_compression and
# KHR_draco_mesh_compression (host/io/gltf_container.cpp, host/io/gltf_draco.cpp). Debian's
# libmeshoptimizer-dev and libdraco-dev. The glTF JSON itself is read with nlohmann/json.
find_package(meshoptimizer REQUIRED)
find_package(draco REQUIRED)
target_link_libraries(harmonia_private_deps INTERFACE meshoptimizer::meshoptimizer draco::draco)

# SuiteSparse CHOLMOD (optional): supernodal Cholesky for the CPU backend and the benchmark floor.
set(HARMONIA_CHOLMOD_FOUND OFF)
set(HARMONIA_OPENMP_FOUND OFF)
set(HARMONIA_LAPACK_FOUND OFF)
set(HARMONIA_METIS_FOUND OFF)
set(HARMONIA_UMFPACK_FOUND OFF)
if(HARMONIA_WITH_CHOLMOD)
  find_path(HARMONIA_CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
  find_library(HARMONIA_CHOLMOD_LIBRARY cholmod)
  if(HARMONIA_CHOLMOD_INCLUDE_DIR AND HARMONIA_CHOLMOD_LIBRARY)
    set(HARMONIA_CHOLMOD_FOUND ON)
    target_include_directories(harmonia_private_deps INTERFACE ${HARMONIA_CHOLMOD_INCLUDE_DIR})
    target_link_libraries(harmonia_private_deps INTERFACE ${HARMONIA_CHOLMOD_LIBRARY})
    message(STATUS "harmonia: CHOLMOD found (${HARMONIA_CHOLMOD_LIBRARY})")
    # CHOLMOD's OpenMP runtime: harmonia keeps the calling thread's regions serial while CHOLMOD
    # factorizes (fallback/serial_openmp_regions.h). Linked only; harmonia's own code has no
    # OpenMP regions.
    # LAPACK and BLAS: the dense separator block of the two-thread factorization
    # (fallback/subtree_parallel_cholesky.cpp). The generic libraries, which are CHOLMOD's own
    # (Debian's alternatives point them at OpenBLAS), so that one BLAS serves the process.
    set(BLA_VENDOR Generic)
    find_package(LAPACK)
    if(LAPACK_FOUND)
      set(HARMONIA_LAPACK_FOUND ON)
      target_link_libraries(harmonia_private_deps INTERFACE ${LAPACK_LIBRARIES})
    endif()
    # UMFPACK (SuiteSparse's multifrontal LU, same package): the LU of the non-symmetric systems
    # (mean value weights), about 2.5 times faster than Eigen's SparseLU at 100K vertices.
    find_path(HARMONIA_UMFPACK_INCLUDE_DIR umfpack.h PATH_SUFFIXES suitesparse)
    find_library(HARMONIA_UMFPACK_LIBRARY umfpack)
    if(HARMONIA_UMFPACK_INCLUDE_DIR AND HARMONIA_UMFPACK_LIBRARY)
      set(HARMONIA_UMFPACK_FOUND ON)
      target_include_directories(harmonia_private_deps INTERFACE ${HARMONIA_UMFPACK_INCLUDE_DIR})
      target_link_libraries(harmonia_private_deps INTERFACE ${HARMONIA_UMFPACK_LIBRARY})
    endif()
    # METIS (the nested dissection CHOLMOD calls): called directly to compute the top separator
    # first and each side's order after it (fallback/separator_first_ordering.h).
    find_path(HARMONIA_METIS_INCLUDE_DIR metis.h)
    find_library(HARMONIA_METIS_LIBRARY metis)
    if(HARMONIA_METIS_INCLUDE_DIR AND HARMONIA_METIS_LIBRARY)
      set(HARMONIA_METIS_FOUND ON)
      target_include_directories(harmonia_private_deps INTERFACE ${HARMONIA_METIS_INCLUDE_DIR})
      target_link_libraries(harmonia_private_deps INTERFACE ${HARMONIA_METIS_LIBRARY})
    endif()
    find_package(OpenMP COMPONENTS CXX)
    if(OpenMP_CXX_FOUND)
      set(HARMONIA_OPENMP_FOUND ON)
      target_link_libraries(harmonia_private_deps INTERFACE ${OpenMP_CXX_LIBRARIES})
    endif()
  else()
    message(STATUS "harmonia: CHOLMOD not found; the CPU backend uses Eigen's Cholesky")
  endif()
endif()
