# One place for compiler warnings, applied to every gimg target through gimg_set_warnings().
function(gimg_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
                                           -Wcast-align -Woverloaded-virtual
                                           # Vulkan structs are initialised as {sType}: fine.
                                           -Wno-missing-field-initializers)
  if(GIMG_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
