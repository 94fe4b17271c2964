# A project that includes cmake/mbgen_add_robot.cmake from a source checkout (no installed package)
# gets the generated functions from the catalogue's source, the same lists mbgen's own build wrote
# for the package (BUILT_LISTS: ${PROJECT_BINARY_DIR}/mbgen_functions.cmake). Run with cmake -P.
include(${BUILT_LISTS})
set(built_functions ${MBGEN_GENERATED_FUNCTIONS})
set(built_batched ${MBGEN_BATCHED_FUNCTIONS})
unset(MBGEN_GENERATED_FUNCTIONS)
unset(MBGEN_BATCHED_FUNCTIONS)
include(${MBGEN_SOURCE}/cmake/mbgen_add_robot.cmake)
if(NOT MBGEN_GENERATED_FUNCTIONS STREQUAL built_functions OR NOT MBGEN_BATCHED_FUNCTIONS STREQUAL built_batched)
  message(FATAL_ERROR "from the source checkout: '${MBGEN_GENERATED_FUNCTIONS}' / '${MBGEN_BATCHED_FUNCTIONS}'; "
                      "the build's: '${built_functions}' / '${built_batched}'")
endif()
list(LENGTH MBGEN_GENERATED_FUNCTIONS n)
message(STATUS "the catalogue's ${n} functions, read from the source checkout as from the build")
