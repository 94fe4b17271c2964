# AddressSanitizer + UndefinedBehaviorSanitizer (docs/reliability.md), two ways:
#
# MBGEN_SANITIZE: everything instrumented (generator, tests, generated code) in a build tree of its
#   own: scripts/test_sanitized.sh, the whole suite, ~3x the normal one.
# MBGEN_SANITIZE_SUBSET (on by default): in an ordinary build, the executables of the sanitized
#   subset — the tests of the runtime's numerics (the generic algorithms are header-only templates,
#   so instrumenting a test file instruments the runtime code it runs) and twins of the examples
#   whose short runs the subset holds (mbgen_sim_sanitized, ...). This is what CI runs under the
#   sanitizers on every stop: the normal build's tests of those files, instrumented instead of
#   plain, rather than a second build of everything. The generator and generated code they link
#   stay plain (the whole run checks those).
option(MBGEN_SANITIZE "Build everything with -fsanitize=address,undefined" OFF)
option(MBGEN_SANITIZE_SUBSET "Build the sanitized subset's executables with -fsanitize=address,undefined" ON)

set(MBGEN_SANITIZER_COMPILE_OPTIONS -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
set(MBGEN_SANITIZER_LINK_OPTIONS -fsanitize=address,undefined)
# The subset's files (mbgen_instrument) leave out the UndefinedBehaviorSanitizer checks that
# AddressSanitizer, on beside them, already covers or that this code cannot trip, because they cost
# more than the rest of the instrumentation together (test_differential_ik_qp.cpp, g++ 12, -O1:
# 132.6 s to compile with the full set, 58.6 s without them, 52.5 s plain):
#   null, object-size, pointer-overflow: an access through a null pointer faults and ASan reports
#     it with its stack; an access outside an object is ASan's own check, with exact bounds;
#   alignment: Eigen's aligned vector loads fault on a misaligned address, and the plain build's
#     tests run the same code;
#   vptr: mbgen has no virtual functions (its algorithms are templates).
# What stays is what only UBSan sees in numerical code: signed overflow, shifts, division by zero,
# float-to-integer overflow, invalid bool and enum values (the canary's, issue 61's report), array
# bounds by index, missing returns and unreachable code. The whole run (MBGEN_SANITIZE,
# scripts/test_sanitized.sh) keeps every check.
set(MBGEN_SUBSET_SANITIZER_COMPILE_OPTIONS ${MBGEN_SANITIZER_COMPILE_OPTIONS}
    -fno-sanitize=null,object-size,pointer-overflow,alignment,vptr)
# Eigen turns its glibc-malloc-is-aligned assumption off under ASan and pairs its own aligned
# malloc/free instead, while Debian's Eigen-based libraries (orocos-kdl, FCL) and, in the subset's
# mixed build, mbgen's own plain libraries keep it: an object made by one and freed by the other is
# a heap-buffer-overflow. Keep the assumption everywhere.
set(MBGEN_SANITIZER_DEFINITIONS EIGEN_MALLOC_ALREADY_ALIGNED=1)
if(MBGEN_SANITIZE)
  add_compile_options(${MBGEN_SANITIZER_COMPILE_OPTIONS})
  add_link_options(${MBGEN_SANITIZER_LINK_OPTIONS})
  add_compile_definitions(${MBGEN_SANITIZER_DEFINITIONS})
endif()

# True when the sanitized subset's own executables must be instrumented here (the whole build is
# when MBGEN_SANITIZE is on, and the fuzzers' build has its own instrumentation).
if(MBGEN_SANITIZE_SUBSET AND NOT MBGEN_SANITIZE AND NOT MBGEN_FUZZ)
  set(MBGEN_INSTRUMENT_SUBSET TRUE)
else()
  set(MBGEN_INSTRUMENT_SUBSET FALSE)
endif()

# What an instrumented executable runs with unless ASAN_OPTIONS etc. say otherwise: any report
# ends it with a failure; urdfdom's leak on a failed parse is known (scripts/lsan_suppressions.txt).
# Compiled into each instrumented executable (tests/sanitizer_options.cpp), so that ctest, a script
# or a hand-run gets the same. scripts/test_sanitized.sh exports the same options for the whole run.
if(MBGEN_INSTRUMENT_SUBSET)
  add_library(mbgen_sanitizer_options OBJECT ${PROJECT_SOURCE_DIR}/tests/sanitizer_options.cpp)
  target_compile_definitions(mbgen_sanitizer_options PRIVATE
    MBGEN_LSAN_SUPPRESSIONS="${PROJECT_SOURCE_DIR}/scripts/lsan_suppressions.txt")
endif()

# Python tests of the whole sanitized build load instrumented extension modules (the generated
# robots', the runtime's) into Debian's python3, which is not instrumented: ASan's runtime must be
# loaded first, so it is preloaded, with libstdc++ (loaded later, by the module, ASan's interceptor
# of __cxa_throw finds no real one and aborts at the first C++ exception), and what CPython still
# holds at exit is not a leak of ours.
# mbgen_python_test_environment(test...) adds that to the tests' environment. With SCRIPT first, the
# tests run a script that starts python3 among other programs (compilers, cmake): they get it as
# MBGEN_SANITIZED_PYTHON instead, `env` arguments for the script's python3 line alone. Nothing in
# any other build.
set(MBGEN_SANITIZED_PYTHON_ENVIRONMENT)
if(MBGEN_SANITIZE)
  execute_process(COMMAND ${CMAKE_CXX_COMPILER} -print-file-name=libasan.so OUTPUT_VARIABLE asan_runtime
                  OUTPUT_STRIP_TRAILING_WHITESPACE)
  execute_process(COMMAND ${CMAKE_CXX_COMPILER} -print-file-name=libstdc++.so.6 OUTPUT_VARIABLE cxx_runtime
                  OUTPUT_STRIP_TRAILING_WHITESPACE)
  set(MBGEN_SANITIZED_PYTHON_ENVIRONMENT LD_PRELOAD=${asan_runtime}:${cxx_runtime} ASAN_OPTIONS=abort_on_error=1:detect_leaks=0)
endif()
function(mbgen_python_test_environment)
  cmake_parse_arguments(PARSE_ARGV 0 arg "SCRIPT" "" "")
  if(NOT MBGEN_SANITIZED_PYTHON_ENVIRONMENT)
    return()
  endif()
  set(environment ${MBGEN_SANITIZED_PYTHON_ENVIRONMENT})
  if(arg_SCRIPT)
    list(JOIN MBGEN_SANITIZED_PYTHON_ENVIRONMENT " " as_arguments)
    set(environment "MBGEN_SANITIZED_PYTHON=${as_arguments}")
  endif()
  set_property(TEST ${arg_UNPARSED_ARGUMENTS} APPEND PROPERTY ENVIRONMENT ${environment})
endfunction()

# Instrument one target (the subset's executables and the objects only they link).
function(mbgen_instrument target)
  target_compile_options(${target} PRIVATE ${MBGEN_SUBSET_SANITIZER_COMPILE_OPTIONS})
  target_compile_definitions(${target} PRIVATE ${MBGEN_SANITIZER_DEFINITIONS})
  get_target_property(type ${target} TYPE)
  if(type STREQUAL "EXECUTABLE")
    target_link_options(${target} PRIVATE ${MBGEN_SANITIZER_LINK_OPTIONS})
    target_link_libraries(${target} PRIVATE mbgen_sanitizer_options)
  endif()
endfunction()

# The subset's executables are listed, so that the target mbgen_sanitized_subset builds those and
# nothing else (scripts/test_sanitized.sh --subset); their tests carry the ctest label
# `sanitized_subset`.
function(mbgen_in_sanitized_subset target)
  set_property(GLOBAL APPEND PROPERTY MBGEN_SANITIZED_SUBSET_TARGETS ${target})
endfunction()

# The instrumented form of an example whose short runs the subset holds, for the subset's tests to
# run: `target` itself when the whole build is sanitized, else an instrumented twin,
# `target`_sanitized, built from the same sources, definitions and libraries at -O1 (the example
# itself stays plain: its runs make the docs' charts and timings). Sets `out_var` to the one to
# run, or to nothing when no sanitizer is on (the subset's tests are then not added).
function(mbgen_sanitized_subset_executable target out_var)
  if(MBGEN_SANITIZE)
    mbgen_in_sanitized_subset(${target})
    set(${out_var} ${target} PARENT_SCOPE)
    return()
  elseif(NOT MBGEN_INSTRUMENT_SUBSET)
    set(${out_var} "" PARENT_SCOPE)
    return()
  endif()
  set(twin ${target}_sanitized)
  if(TARGET ${twin})  # made by an earlier call
    set(${out_var} ${twin} PARENT_SCOPE)
    return()
  endif()
  get_target_property(sources ${target} SOURCES)
  add_executable(${twin} ${sources})
  foreach(property LINK_LIBRARIES INCLUDE_DIRECTORIES COMPILE_DEFINITIONS COMPILE_OPTIONS)
    get_target_property(value ${target} ${property})
    if(value)
      set_property(TARGET ${twin} PROPERTY ${property} ${value})
    endif()
  endforeach()
  target_compile_options(${twin} PRIVATE -O1)
  mbgen_instrument(${twin})
  mbgen_in_sanitized_subset(${twin})
  set(${out_var} ${twin} PARENT_SCOPE)
endfunction()
