# mbgen_add_robot(TARGET <target> DESCRIPTION <urdf>
#                 [EXTRAS <yaml>] [NAME <namespace>] [SCALAR double|float|both]
#                 [FLOATING | FIXED] [FRAMES <frame>...] [OUTPUTS <output>... | all] [OUTPUT_DIR <dir>]
#                 [FLAVOUR cpp|c | TEMPLATES <dir>] [ARCH <cpu> | ARCH <flag>...] [BATCH <W>]
#                 [MAX_STATEMENTS <n>] [PYTHON])
#
# Generates a robot's unrolled C++ at build time and adds the static library <target> whose
# public include directory holds its header (<NAME>.hpp; <NAME>.h in the c flavour). Shaped like protobuf_generate: the outputs follow
# from the arguments alone, and they are regenerated when the description, the extras or the
# generator change. The generator is ${MBGEN_EXECUTABLE} when set (cross builds: point it at a
# host build of mbgen), else the mbgen target of this build or of the installed package.
#
#   NAME        C++ namespace and file prefix (default: <target>)
#   SCALAR      scalar types emitted (default: the extras' scene `scalar:`, else both)
#   OUTPUTS     what to generate, overriding the extras' scene `outputs:` (docs/extras.md), or
#               `all`; a function left out still has its (empty) source file
#   OUTPUT_DIR  default: ${CMAKE_CURRENT_BINARY_DIR}/mbgen/<NAME>
#   FLAVOUR     the installed templates to use (docs/templates.md): cpp (default; namespace
#               <NAME>, overloads per scalar) or c (a C99 header, <NAME>_<function>_<scalar>)
#   TEMPLATES   a folder of your own templates instead (a copy of a flavour, edited); the file
#               names come from its header_file.fmt and source_file.fmt
#   ARCH        the instruction set the generated sources are compiled for: a CPU name for
#               -march (native, x86-64-v3, cortex-a72, ...) or compiler flags (values starting
#               with '-', used as given). Generated code is straight-line arithmetic: with FMA
#               (x86-64-v3) g++ contracts a*b+c into one instruction and it runs about twice as
#               fast (bench/README.md). Only this library's sources: the code calling it keeps its
#               own flags. Default: the build's flags.
#   BATCH       also generate <function>_batch over W states per call (W = 2, 4, 8 or 16; q[i][w]
#               layout) for the functions of MBGEN_BATCHED_FUNCTIONS: sampling-based control and
#               learning. Each state equals the one-state function bit for bit under the same
#               flags; with ARCH x86-64-v3, W = 4 fills the AVX2 registers with double.
#   MAX_STATEMENTS  statements per part above which a function is split into noinline parts
#               (default 20000; compile time against a few loads and stores)
#   PYTHON      also generate <NAME>_python.cpp and build it as the Python module <NAME> (target
#               <target>_python, in its binary folder: import it with that folder on PYTHONPATH):
#               every generated function for double, NumPy arrays in and out (docs/python.md).
#               Needs find_package(pybind11) (Debian's pybind11-dev, python3-numpy) and the cpp
#               flavour.

# The source files of every generation, one per function of the generator's catalogue
# (generator/codegen/function_catalog.hpp: MBGEN_GENERATED_FUNCTIONS, and MBGEN_BATCHED_FUNCTIONS
# with BATCH, <NAME>_<function>_batch.cpp), so that the outputs follow from the arguments alone: a
# function the scene's outputs leave out gets a file holding only a note; self_distances,
# contact_points and contact_accelerations, when generated, are empty (num_distance_pairs or
# num_contact_spheres = 0, or a call of full_accelerations) for a description without SSV pairs
# or a scene without contact. An installed package reads the lists from the copy made at mbgen's
# build; a source checkout (this project's build, or a project that includes this file from one)
# reads them from the catalogue's source (cmake/mbgen_function_catalog.cmake).
if(NOT DEFINED MBGEN_GENERATED_FUNCTIONS)
  if(EXISTS ${CMAKE_CURRENT_LIST_DIR}/mbgen_functions.cmake)
    include(${CMAKE_CURRENT_LIST_DIR}/mbgen_functions.cmake)
  else()
    include(${CMAKE_CURRENT_LIST_DIR}/mbgen_function_catalog.cmake)
  endif()
endif()

function(mbgen_add_robot)
  cmake_parse_arguments(MB "FLOATING;FIXED;PYTHON" "TARGET;DESCRIPTION;EXTRAS;NAME;SCALAR;OUTPUT_DIR;FLAVOUR;TEMPLATES;BATCH;MAX_STATEMENTS" "FRAMES;OUTPUTS;ARCH"
                        ${ARGN})
  if(NOT MB_TARGET OR NOT MB_DESCRIPTION)
    message(FATAL_ERROR "mbgen_add_robot: TARGET and DESCRIPTION are required")
  endif()
  if(MB_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "mbgen_add_robot: unknown arguments ${MB_UNPARSED_ARGUMENTS}")
  endif()
  if(NOT MB_NAME)
    set(MB_NAME ${MB_TARGET})
  endif()
  if(NOT MB_OUTPUT_DIR)
    set(MB_OUTPUT_DIR ${CMAKE_CURRENT_BINARY_DIR}/mbgen/${MB_NAME})
  endif()
  get_filename_component(description ${MB_DESCRIPTION} ABSOLUTE)

  set(arguments generate ${description} --out ${MB_OUTPUT_DIR} --name ${MB_NAME} --quiet)
  if(MB_SCALAR)
    list(APPEND arguments --scalar ${MB_SCALAR})
  endif()
  set(inputs ${description})
  if(MB_EXTRAS)
    get_filename_component(extras ${MB_EXTRAS} ABSOLUTE)
    list(APPEND arguments --extras ${extras})
    list(APPEND inputs ${extras})
  else()
    # The generator picks up a robot.yaml beside the URDF: depend on it too.
    get_filename_component(description_dir ${description} DIRECTORY)
    if(EXISTS ${description_dir}/robot.yaml)
      list(APPEND inputs ${description_dir}/robot.yaml)
    endif()
  endif()
  if(MB_FLOATING)
    list(APPEND arguments --floating)
  elseif(MB_FIXED)
    list(APPEND arguments --fixed)
  endif()
  if(MB_FRAMES)
    string(REPLACE ";" "," frames "${MB_FRAMES}")
    list(APPEND arguments --frames ${frames})
  endif()
  if(MB_OUTPUTS)
    string(REPLACE ";" "," outputs "${MB_OUTPUTS}")
    list(APPEND arguments --outputs ${outputs})
  endif()

  if(MB_BATCH)
    list(APPEND arguments --batch ${MB_BATCH})
  endif()
  if(MB_MAX_STATEMENTS)
    list(APPEND arguments --max-statements ${MB_MAX_STATEMENTS})
  endif()
  if(MB_PYTHON)
    if(MB_FLAVOUR AND NOT MB_FLAVOUR STREQUAL "cpp" OR MB_TEMPLATES)
      message(FATAL_ERROR "mbgen_add_robot: PYTHON binds the cpp flavour's functions: drop FLAVOUR ${MB_FLAVOUR} / TEMPLATES")
    endif()
    if(NOT COMMAND pybind11_add_module)
      message(FATAL_ERROR "mbgen_add_robot: PYTHON needs pybind11: find_package(pybind11 CONFIG REQUIRED) first "
                          "(Debian: pybind11-dev python3-dev python3-numpy)")
    endif()
    list(APPEND arguments --python)
  endif()

  if(MB_FLAVOUR AND MB_TEMPLATES)
    message(FATAL_ERROR "mbgen_add_robot: FLAVOUR and TEMPLATES exclude each other")
  endif()
  if(MB_TEMPLATES)
    get_filename_component(templates ${MB_TEMPLATES} ABSOLUTE)
    list(APPEND arguments --templates ${templates})
  else()
    if(NOT MB_FLAVOUR)
      set(MB_FLAVOUR cpp)
    endif()
    set(templates ${MBGEN_TEMPLATES_DIR}/${MB_FLAVOUR})
    if(NOT MB_FLAVOUR STREQUAL "cpp")
      list(APPEND arguments --flavour ${MB_FLAVOUR})
    endif()
  endif()
  if(NOT EXISTS ${templates}/header_file.fmt OR NOT EXISTS ${templates}/source_file.fmt)
    message(FATAL_ERROR "mbgen_add_robot: ${templates} is not a template folder (no header_file.fmt, source_file.fmt)")
  endif()
  file(GLOB template_files ${templates}/*.fmt)
  if(MB_PYTHON)
    file(GLOB python_template_files ${templates}/python/*.fmt)  # the module's own (docs/templates.md)
    list(APPEND template_files ${python_template_files})
  endif()
  list(APPEND inputs ${template_files})
  # The file names, as mbgen makes them: the first line of the name templates.
  file(STRINGS ${templates}/header_file.fmt header_name LIMIT_COUNT 1)
  file(STRINGS ${templates}/source_file.fmt source_name LIMIT_COUNT 1)
  string(REPLACE "{robot}" "${MB_NAME}" header_name "${header_name}")
  string(REPLACE "{robot}" "${MB_NAME}" source_name "${source_name}")

  if(MBGEN_EXECUTABLE)
    set(generator ${MBGEN_EXECUTABLE})
    list(APPEND inputs ${MBGEN_EXECUTABLE})
  elseif(TARGET mbgen::mbgen)
    set(generator $<TARGET_FILE:mbgen::mbgen>)
    list(APPEND inputs mbgen::mbgen)
  elseif(TARGET mbgen)
    set(generator $<TARGET_FILE:mbgen>)
    list(APPEND inputs mbgen)
  else()
    message(FATAL_ERROR "mbgen_add_robot: no generator: set MBGEN_EXECUTABLE or find_package(mbgen)")
  endif()

  set(header ${MB_OUTPUT_DIR}/${header_name})
  set(sources)
  foreach(function IN LISTS MBGEN_GENERATED_FUNCTIONS)
    string(REPLACE "{function}" "${function}" source "${source_name}")
    list(APPEND sources ${MB_OUTPUT_DIR}/${source})
  endforeach()
  if(MB_BATCH)
    foreach(function IN LISTS MBGEN_BATCHED_FUNCTIONS)
      string(REPLACE "{function}" "${function}_batch" source "${source_name}")
      list(APPEND sources ${MB_OUTPUT_DIR}/${source})
    endforeach()
  endif()
  set(python_source)
  if(MB_PYTHON)
    set(python_source ${MB_OUTPUT_DIR}/${MB_NAME}_python.cpp)
  endif()
  add_custom_command(
    OUTPUT ${header} ${sources} ${python_source}
    COMMAND ${generator} ${arguments}
    # mbgen leaves unchanged files untouched; the build tool still needs them newer than the inputs.
    COMMAND ${CMAKE_COMMAND} -E touch_nocreate ${header} ${sources} ${python_source}
    DEPENDS ${inputs}
    COMMENT "mbgen: generating ${MB_NAME} from ${MB_DESCRIPTION}"
    VERBATIM)
  add_library(${MB_TARGET} STATIC ${sources} ${header})
  target_include_directories(${MB_TARGET} PUBLIC $<BUILD_INTERFACE:${MB_OUTPUT_DIR}>)
  # <NAME>_self_distances.cpp calls the runtime's header-only SSV primitives: the runtime's include
  # directory only (not its Eigen dependency: generated code needs none).
  if(NOT TARGET mbgen::runtime)
    message(FATAL_ERROR "mbgen_add_robot: no mbgen::runtime target: add mbgen's runtime/ or find_package(mbgen)")
  endif()
  target_include_directories(${MB_TARGET} PRIVATE $<TARGET_PROPERTY:mbgen::runtime,INTERFACE_INCLUDE_DIRECTORIES>)
  target_compile_features(${MB_TARGET} PUBLIC cxx_std_17)
  if(MB_ARCH)
    list(GET MB_ARCH 0 first)
    if(first MATCHES "^-")
      target_compile_options(${MB_TARGET} PRIVATE ${MB_ARCH})
    else()
      list(LENGTH MB_ARCH count)
      if(count GREATER 1)
        message(FATAL_ERROR "mbgen_add_robot: ARCH takes one CPU name (for -march) or flags starting with '-', not ${MB_ARCH}")
      endif()
      target_compile_options(${MB_TARGET} PRIVATE -march=${MB_ARCH})
    endif()
  endif()
  set_target_properties(${MB_TARGET} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  if(MB_PYTHON)
    # NO_EXTRAS: no link-time optimisation across the module (the generated library is built and
    # optimised as it says), so a module links in seconds.
    pybind11_add_module(${MB_TARGET}_python MODULE NO_EXTRAS ${python_source})
    set_target_properties(${MB_TARGET}_python PROPERTIES OUTPUT_NAME ${MB_NAME})
    # mbgen/python/: the module's helpers and, with a Backend, the runtime's simulator (Eigen).
    target_link_libraries(${MB_TARGET}_python PRIVATE ${MB_TARGET} mbgen::runtime)
  endif()
endfunction()
