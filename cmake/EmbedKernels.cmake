# clpt_embed_kernels(TARGET NAME ROOT FILES...)
# Compiles the kernel sources FILES (under ROOT) into TARGET as a table of
# {relative path, contents} returned by clpt::embedded::<NAME>(). The table is regenerated
# whenever a listed file changes. Files are stored as byte arrays, so any content is safe.
function(clpt_embed_kernels target name root)
  set(out "${CMAKE_CURRENT_BINARY_DIR}/embedded_${name}.cpp")
  set(list_file "${CMAKE_CURRENT_BINARY_DIR}/embedded_${name}.files")
  file(WRITE "${list_file}.in" "")
  foreach(f IN LISTS ARGN)
    file(APPEND "${list_file}.in" "${f}\n")
  endforeach()
  configure_file("${list_file}.in" "${list_file}" COPYONLY)
  add_custom_command(
    OUTPUT "${out}"
    COMMAND ${CMAKE_COMMAND} -DNAME=${name} -DROOT=${root} -DLIST=${list_file} -DOUT=${out}
            -P "${CLPT_SOURCE_DIR}/cmake/EmbedKernelsScript.cmake"
    DEPENDS ${ARGN} "${list_file}" "${CLPT_SOURCE_DIR}/cmake/EmbedKernelsScript.cmake"
    COMMENT "Embedding ${name} kernel sources"
    VERBATIM)
  target_sources(${target} PRIVATE "${out}")
endfunction()
