# The generated functions' names, read from the generator's catalogue
# (generator/codegen/function_catalog.cpp: each row begins `row("name", Batch::yes|no,`), so that
# mbgen_add_robot declares exactly the files mbgen writes without a list of its own. In mbgen's own
# build it also writes them to ${PROJECT_BINARY_DIR}/mbgen_functions.cmake, which the package
# installs beside mbgen_add_robot.cmake (an installed mbgen has no catalogue source to read).
get_filename_component(_catalog ${CMAKE_CURRENT_LIST_DIR}/../generator/codegen/function_catalog.cpp ABSOLUTE)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${_catalog})
file(STRINGS ${_catalog} _rows REGEX "^ *row\\(\"[a-z_]+\", Batch::(yes|no),")
set(MBGEN_GENERATED_FUNCTIONS)
set(MBGEN_BATCHED_FUNCTIONS)
foreach(_row IN LISTS _rows)
  string(REGEX MATCH "\"([a-z_]+)\", Batch::(yes|no)" _ ${_row})
  list(APPEND MBGEN_GENERATED_FUNCTIONS ${CMAKE_MATCH_1})
  if(CMAKE_MATCH_2 STREQUAL "yes")
    list(APPEND MBGEN_BATCHED_FUNCTIONS ${CMAKE_MATCH_1})
  endif()
endforeach()
if(NOT MBGEN_GENERATED_FUNCTIONS)
  message(FATAL_ERROR "mbgen: no function rows found in ${_catalog}")
endif()
if(PROJECT_NAME STREQUAL "mbgen")
  file(WRITE ${PROJECT_BINARY_DIR}/mbgen_functions.cmake
       "# Written by cmake/mbgen_function_catalog.cmake from the generator's function catalogue.\n"
       "set(MBGEN_GENERATED_FUNCTIONS ${MBGEN_GENERATED_FUNCTIONS})\n"
       "set(MBGEN_BATCHED_FUNCTIONS ${MBGEN_BATCHED_FUNCTIONS})\n")
endif()
