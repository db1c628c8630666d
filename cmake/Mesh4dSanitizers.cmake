# Sanitizer builds apply to every target, including the tests and the server they start.
if(MESH4D_ASAN AND MESH4D_TSAN)
  message(FATAL_ERROR "MESH4D_ASAN and MESH4D_TSAN cannot be combined")
endif()
if(MESH4D_ASAN)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer
                      -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()
if(MESH4D_TSAN)
  add_compile_options(-fsanitize=thread -fno-omit-frame-pointer)
  add_link_options(-fsanitize=thread)
endif()
