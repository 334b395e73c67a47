# Runs one example and checks what it did: the test of each example (examples/CMakeLists.txt).
#
#   cmake -D WORK_DIR=DIR [-D EXIT_CODE=N] [-D OUTPUT_MATCHES=REGEX] [-D OUTPUT_NOT_MATCHES=REGEX]
#         [-D OBJ_FILES=GLOB [-D OBJ_COUNT=N] [-D UV=per_vertex|per_corner|none] [-D FACES=N]]
#         [-D SKIP_EXIT_CODE=N] -P check_example.cmake -- PROGRAM [ARGUMENTS...]
#
# The program runs in WORK_DIR, emptied first so that no file of an earlier run passes for this
# one. It must exit with EXIT_CODE (default 0); its output (stdout and stderr together) must match
# OUTPUT_MATCHES and must not match OUTPUT_NOT_MATCHES. The OBJ files it wrote (OBJ_FILES, a glob
# in WORK_DIR; OBJ_COUNT of them, default at least one) are read back: each needs FACES `f` lines
# when given, and texture coordinates as UV says:
#   per_vertex  one `vt` per `v`, every face `f a/a b/b c/c` (a map of a disk, harmonia/io.h);
#   per_corner  every corner with a `vt`, every `vt` inside [0, 1] (a texture atlas, atlas_io.h);
#   none        no `vt` (a mesh).
# SKIP_EXIT_CODE: the exit status by which the program says it cannot run here (no device); the
# check then prints "example skipped" (the test's SKIP_REGULAR_EXPRESSION), except under CI=true,
# where everything must run.
cmake_minimum_required(VERSION 3.22)

function(fail message)
  message(FATAL_ERROR "${message}")
endfunction()

# The command: everything after "--".
set(command)
set(after_separator FALSE)
math(EXPR last_argument "${CMAKE_ARGC} - 1")
foreach(index RANGE ${last_argument})
  if(after_separator)
    list(APPEND command "${CMAKE_ARGV${index}}")
  elseif(CMAKE_ARGV${index} STREQUAL "--")
    set(after_separator TRUE)
  endif()
endforeach()
if(NOT command OR NOT WORK_DIR)
  fail("usage: cmake -D WORK_DIR=DIR [...] -P check_example.cmake -- PROGRAM [ARGUMENTS...]")
endif()
if(NOT DEFINED EXIT_CODE)
  set(EXIT_CODE 0)
endif()

file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
execute_process(COMMAND ${command} WORKING_DIRECTORY "${WORK_DIR}"
                RESULT_VARIABLE exit_code OUTPUT_VARIABLE output ERROR_VARIABLE output)
message("${output}")

if(DEFINED SKIP_EXIT_CODE AND exit_code STREQUAL SKIP_EXIT_CODE)
  if("$ENV{CI}" STREQUAL "true")
    fail("exit status ${exit_code}: the example cannot run here, and under CI=true it must")
  endif()
  message("example skipped: it cannot run here (exit status ${exit_code})")
  return()
endif()
if(NOT exit_code STREQUAL EXIT_CODE)
  fail("exit status ${exit_code}, expected ${EXIT_CODE}")
endif()
if(DEFINED OUTPUT_MATCHES AND NOT output MATCHES "${OUTPUT_MATCHES}")
  fail("the output does not match ${OUTPUT_MATCHES}")
endif()
if(DEFINED OUTPUT_NOT_MATCHES AND output MATCHES "${OUTPUT_NOT_MATCHES}")
  fail("the output matches ${OUTPUT_NOT_MATCHES}")
endif()

# The OBJ files, read back line by line.
function(check_obj path)
  file(STRINGS "${path}" positions REGEX "^v ")
  file(STRINGS "${path}" texture_coordinates REGEX "^vt ")
  file(STRINGS "${path}" faces REGEX "^f ")
  list(LENGTH positions position_count)
  list(LENGTH texture_coordinates uv_count)
  list(LENGTH faces face_count)
  if(DEFINED FACES AND NOT face_count EQUAL FACES)
    fail("${path}: ${face_count} faces, expected ${FACES}")
  endif()
  if(UV STREQUAL "none" AND uv_count GREATER 0)
    fail("${path}: ${uv_count} vt lines, expected none")
  elseif(UV STREQUAL "per_vertex")
    if(NOT uv_count EQUAL position_count)
      fail("${path}: ${uv_count} vt lines for ${position_count} vertices")
    endif()
    foreach(face IN LISTS faces)
      if(NOT face MATCHES "^f ([0-9]+)/([0-9]+) ([0-9]+)/([0-9]+) ([0-9]+)/([0-9]+)$" OR
         NOT CMAKE_MATCH_1 EQUAL CMAKE_MATCH_2 OR NOT CMAKE_MATCH_3 EQUAL CMAKE_MATCH_4 OR
         NOT CMAKE_MATCH_5 EQUAL CMAKE_MATCH_6)
        fail("${path}: the face '${face}' does not use its vertices' own vt")
      endif()
    endforeach()
  elseif(UV STREQUAL "per_corner")
    set(number "-?[0-9]+(\\.[0-9]*)?(e[-+]?[0-9]+)?")
    foreach(uv IN LISTS texture_coordinates)
      if(NOT uv MATCHES "^vt (${number}) (${number})$" OR CMAKE_MATCH_1 LESS 0 OR
         CMAKE_MATCH_1 GREATER 1 OR CMAKE_MATCH_4 LESS 0 OR CMAKE_MATCH_4 GREATER 1)
        fail("${path}: '${uv}' is no texture coordinate inside [0, 1]")
      endif()
    endforeach()
    foreach(face IN LISTS faces)
      if(NOT face MATCHES "^f [0-9]+/([1-9][0-9]*) [0-9]+/([1-9][0-9]*) [0-9]+/([1-9][0-9]*)$" OR
         CMAKE_MATCH_1 GREATER uv_count OR CMAKE_MATCH_2 GREATER uv_count OR
         CMAKE_MATCH_3 GREATER uv_count)
        fail("${path}: the face '${face}' has a corner without a vt of the file")
      endif()
    endforeach()
  endif()
endfunction()

if(DEFINED OBJ_FILES)
  file(GLOB obj_files "${WORK_DIR}/${OBJ_FILES}")
  list(LENGTH obj_files obj_count)
  if(NOT DEFINED OBJ_COUNT AND obj_count EQUAL 0)
    fail("no file ${OBJ_FILES} written")
  elseif(DEFINED OBJ_COUNT AND NOT obj_count EQUAL OBJ_COUNT)
    fail("${obj_count} files ${OBJ_FILES} written, expected ${OBJ_COUNT}")
  endif()
  foreach(obj IN LISTS obj_files)
    check_obj("${obj}")
  endforeach()
endif()
