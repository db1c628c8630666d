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
# libFuzzer builds (fuzz/): every target gets coverage instrumentation and ASan + UBSan, so the
# decoders' callees in the engine and in ITK's callers are explored and checked too.
if(MESH4D_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "MESH4D_FUZZ needs clang (CC=clang CXX=clang++), not ${CMAKE_CXX_COMPILER_ID}")
  endif()
  if(MESH4D_ASAN OR MESH4D_TSAN)
    message(FATAL_ERROR "MESH4D_FUZZ brings its own sanitizers; leave MESH4D_ASAN/TSAN off")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer
                      -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()
