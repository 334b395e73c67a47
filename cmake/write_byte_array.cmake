# Script mode (cmake -DINPUT=... -DOUTPUT=... -DSYMBOL=... -DHEADER=... -P write_byte_array.cmake),
# run by harmonia_embed_file (cmake/embed_file.cmake): writes OUTPUT, a C++ file that defines the
# bytes of INPUT as harmonia::detail::SYMBOL and their count as SYMBOL_size, 16 bytes a line.
foreach(variable INPUT OUTPUT SYMBOL HEADER)
  if(NOT DEFINED ${variable})
    message(FATAL_ERROR "write_byte_array.cmake: ${variable} is not set")
  endif()
endforeach()
if(NOT EXISTS ${INPUT})
  message(FATAL_ERROR "write_byte_array.cmake: ${INPUT} does not exist")
endif()

file(READ ${INPUT} hex HEX)
string(LENGTH "${hex}" hex_length)
if(hex_length EQUAL 0)
  message(FATAL_ERROR "write_byte_array.cmake: ${INPUT} is empty")
endif()
# A line break after every 16 bytes (32 hex digits), then "0xNN," for every byte.
string(REPEAT "[0-9a-f]" 32 line_of_digits)
string(REGEX REPLACE "(${line_of_digits})" "\\1\n" hex "${hex}")
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," bytes "${hex}")

get_filename_component(input_name ${INPUT} NAME)
file(WRITE ${OUTPUT}.tmp
     "// Generated at build time by cmake/write_byte_array.cmake from ${input_name}; do not edit.\n"
     "#include <cstddef>\n\n#include \"${HEADER}\"\n\nnamespace harmonia::detail {\n\n"
     "const unsigned char ${SYMBOL}[] = {\n${bytes}\n};\n"
     "const std::size_t ${SYMBOL}_size = sizeof(${SYMBOL});\n\n}  // namespace harmonia::detail\n")
# Replaced only when complete, so that an interrupted build never compiles half an array.
file(RENAME ${OUTPUT}.tmp ${OUTPUT})
