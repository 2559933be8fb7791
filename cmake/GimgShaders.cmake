# Compiles GLSL to SPIR-V at build time and embeds it as C arrays, so no shader file is read at run
# time. Each shader ROOT/<family>/<name>.<stage> becomes the header
#   <binary dir>/gimg_shaders/<family>/<name>_<stage>.h
# declaring `const uint32_t gimg_spv_<family>_<name>_<stage>[]`. A GLSL error fails the build with
# glslang's "ERROR: file:line: message". Editing an #included file rebuilds only its includers
# (glslang writes a depfile). A .spv copy is kept beside each header for the spirv-val test.
function(gimg_add_shaders target)
  cmake_parse_arguments(ARG "" "ROOT" "SOURCES" ${ARGN})
  set(out_root "${CMAKE_CURRENT_BINARY_DIR}/gimg_shaders")
  set(headers "")
  foreach(src IN LISTS ARG_SOURCES)
    file(RELATIVE_PATH rel "${ARG_ROOT}" "${src}")
    get_filename_component(dir "${rel}" DIRECTORY)
    get_filename_component(name "${rel}" NAME_WE)
    get_filename_component(ext "${rel}" LAST_EXT)
    string(SUBSTRING "${ext}" 1 -1 stage)
    string(MAKE_C_IDENTIFIER "gimg_spv_${dir}_${name}_${stage}" var)
    set(header "${out_root}/${dir}/${name}_${stage}.h")
    set(spv "${out_root}/${dir}/${name}_${stage}.spv")
    add_custom_command(
      OUTPUT "${header}" "${spv}"
      COMMAND "${CMAKE_COMMAND}" -E make_directory "${out_root}/${dir}"
      COMMAND Vulkan::glslangValidator -V --target-env vulkan1.3 --quiet -I${ARG_ROOT}
              --depfile "${header}.d" --vn ${var} -o "${header}" "${src}"
      COMMAND Vulkan::glslangValidator -V --target-env vulkan1.3 --quiet -I${ARG_ROOT}
              -o "${spv}" "${src}"
      MAIN_DEPENDENCY "${src}"
      DEPFILE "${header}.d"
      COMMENT "GLSL ${rel}"
      VERBATIM)
    list(APPEND headers "${header}")
    set_property(GLOBAL APPEND PROPERTY GIMG_SPV_FILES "${spv}")
  endforeach()
  add_custom_target(${target}_shaders DEPENDS ${headers})
  add_dependencies(${target} ${target}_shaders)
  target_include_directories(${target} PRIVATE "${out_root}")
endfunction()
