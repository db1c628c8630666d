# mesh4d_warnings: an interface target every mesh4d target links, so warnings are set in one place.
# Third-party headers come in as SYSTEM includes (imported targets), so their warnings stay out.
add_library(mesh4d_warnings INTERFACE)
target_compile_options(mesh4d_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow
                                                 -Wnon-virtual-dtor -Wcast-align)
if(MESH4D_WERROR)
  target_compile_options(mesh4d_warnings INTERFACE -Werror)
endif()
