# harmonia_embed_file(<target> <file> <symbol> <declaring header>)
# Embeds <file> in <target> as a byte array generated at build time (like harmonia_embed_shaders
# for SPIR-V), so that the program needs no data file at run time. A custom command runs
# cmake/write_byte_array.cmake to write <binary dir>/embedded/<symbol>.cpp, which defines
#   const unsigned char <symbol>[]   and   const std::size_t <symbol>_size
# in namespace harmonia::detail and includes <declaring header> (a file of the library that
# declares both), so that declaration and definition cannot drift apart. The array is regenerated
# when <file> or the script changes. Nothing is generated into the source tree.
set(HARMONIA_WRITE_BYTE_ARRAY_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/write_byte_array.cmake)

function(harmonia_embed_file target file symbol declaring_header)
  set(output ${PROJECT_BINARY_DIR}/embedded/${symbol}.cpp)
  get_filename_component(file_name ${file} NAME)
  add_custom_command(
    OUTPUT ${output}
    COMMAND ${CMAKE_COMMAND} -DINPUT=${file} -DOUTPUT=${output} -DSYMBOL=${symbol}
            -DHEADER=${declaring_header} -P ${HARMONIA_WRITE_BYTE_ARRAY_SCRIPT}
    MAIN_DEPENDENCY ${file}
    DEPENDS ${HARMONIA_WRITE_BYTE_ARRAY_SCRIPT}
    COMMENT "Embedding ${file_name} as harmonia::detail::${symbol}"
    VERBATIM)
  target_sources(${target} PRIVATE ${output})
endfunction()
