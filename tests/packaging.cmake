# Packaging checks (issue 3), included at the end of tests/CMakeLists.txt. Each is a script run by
# ctest: they exercise the built `mbgen` command, the install tree and the committed output, not a
# C++ API. Exit code 77 means "skipped" (a tool that CI has is missing on this machine).

# Firmware: float code for a shared arm and for the Lola biped compiles for a Cortex-M7 with
# Debian's arm-none-eabi-g++ and references no heap or C++ runtime symbol (tests/firmware/).
function(mbgen_add_firmware_test robot description)
  add_test(NAME firmware.${robot}
           COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/firmware/check_firmware.sh
                   $<TARGET_FILE:mbgen> ${PROJECT_SOURCE_DIR}/runtime/include
                   ${CMAKE_CURRENT_BINARY_DIR}/firmware/${robot} ${robot} ${description} ${ARGN})
  # The script compiles on every core. COST (here and below): ctest starts the longest checks
  # first, so that on a fresh machine, with no timings of a previous run, they do not run last,
  # one after another, while the short tests are done (CI's test phase ended with these 61 s).
  set_tests_properties(firmware.${robot} PROPERTIES SKIP_RETURN_CODE 77 PROCESSORS 2 TIMEOUT 900 COST 100)
endfunction()
mbgen_add_firmware_test(iiwa14 ${MBGEN_SHARED_ROBOTS}/iiwa14/iiwa14_primitive_collision.urdf --fixed)
# Lola in parts of at most 2,000 statements, as the README advises for firmware: arm-none-eabi-g++
# 12's combine pass grows faster than a function's length (full_accelerations whole: 68 s of the
# check's 70-100 s, 5.6 s in parts); iiwa14 and ankle_2dof keep each function whole.
mbgen_add_firmware_test(lola ${PROJECT_SOURCE_DIR}/robots/lola/lola.urdf
                        --extras ${PROJECT_SOURCE_DIR}/robots/lola/lola.yaml --max-statements 2000)
# The c flavour (docs/templates.md): its C99 header and C++ sources, for the same target.
mbgen_add_firmware_test(ankle_2dof_c ${PROJECT_SOURCE_DIR}/robots/mechanisms/ankle_2dof.urdf
                        --extras ${PROJECT_SOURCE_DIR}/robots/mechanisms/ankle_2dof.yaml --flavour c)

# Install: `cmake --install` into a fresh prefix, then a separate project (tests/consumer) finds
# the package, generates tests/data/tiny_arm.urdf with the installed mbgen, builds and runs.
add_test(NAME install.consumer
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/consumer/run_consumer_test.sh
                 ${PROJECT_BINARY_DIR} ${CMAKE_CURRENT_BINARY_DIR}/consumer ${CMAKE_BUILD_TYPE})
# One processor: its configure step and most of its build run on one core (1.4 cores on average).
set_tests_properties(install.consumer PROPERTIES PROCESSORS 1 TIMEOUT 600 COST 100)
mbgen_python_test_environment(SCRIPT install.consumer)  # its python3 line

# Committed output: generated/ equals what this mbgen makes of robots/, byte for byte
# (scripts/regenerate.sh updates it).
add_test(NAME generated.up_to_date
         COMMAND bash ${PROJECT_SOURCE_DIR}/scripts/regenerate.sh --check --mbgen $<TARGET_FILE:mbgen>)

# bench/report.py (Markdown table + gnuplot chart from Google Benchmark JSON), on a checked-in
# sample. Debian's python3 first: the script uses its standard library only.
find_program(MBGEN_PYTHON3 python3 PATHS /usr/bin NO_DEFAULT_PATH)
find_program(MBGEN_PYTHON3 python3)
add_test(NAME bench.report COMMAND ${MBGEN_PYTHON3} ${CMAKE_CURRENT_SOURCE_DIR}/test_bench_report.py)

# Instructions per call of the generated forward dynamics under callgrind (bench/), against the
# operation count: fails above 4 instructions per operation (the code stopped being straight-line).
if(MBGEN_BUILD_BENCH)
  add_test(NAME bench.instructions_per_call
           COMMAND bash ${PROJECT_SOURCE_DIR}/bench/instructions_per_call.sh ${PROJECT_BINARY_DIR})
  set_tests_properties(bench.instructions_per_call PROPERTIES TIMEOUT 300 COST 50)
endif()
add_test(NAME bench.scaling_chart COMMAND ${MBGEN_PYTHON3} ${CMAKE_CURRENT_SOURCE_DIR}/test_scaling_chart.py)
# mbgen_add_robot included from a source checkout reads the catalogue's lists from its source.
add_test(NAME cmake.catalogue_from_source
         COMMAND ${CMAKE_COMMAND} -DMBGEN_SOURCE=${PROJECT_SOURCE_DIR} -DBUILT_LISTS=${PROJECT_BINARY_DIR}/mbgen_functions.cmake
                 -P ${CMAKE_CURRENT_SOURCE_DIR}/catalogue_from_source.cmake)
# The docs' figures that come from a program, against the program's output.
add_test(NAME docs.figures COMMAND ${MBGEN_PYTHON3} ${CMAKE_CURRENT_SOURCE_DIR}/test_docs_figures.py)

# The generator's stages depend downward only (generator/README.md), and the check catches a
# planted upward include in a copy of the tree.
add_test(NAME layout.stages COMMAND bash ${PROJECT_SOURCE_DIR}/scripts/check_layout.sh)
add_test(NAME layout.stages_catches_upward_include
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/check_layout_planted.sh ${PROJECT_SOURCE_DIR}
                 ${CMAKE_CURRENT_BINARY_DIR}/layout_planted)

# The fuzz targets (fuzz/README.md), a few seconds each: built with clang in a tree of their own.
# Label `slow`: building the generator a second time, instrumented, takes 4 minutes of both cores,
# so scripts/test.sh (CI) leaves it out (`ctest -L slow` runs it; scripts/test_sanitized.sh
# includes it). The kept findings are replayed in every run by test_fuzz_regressions.
add_test(NAME fuzz.smoke COMMAND bash ${PROJECT_SOURCE_DIR}/fuzz/run_fuzzers.sh ${CMAKE_CURRENT_BINARY_DIR}/fuzz-build 5)
set_tests_properties(fuzz.smoke PROPERTIES PROCESSORS 2 TIMEOUT 900 LABELS slow
                     ENVIRONMENT "MBGEN_SHARED_ROBOTS=${MBGEN_SHARED_ROBOTS};MBGEN_FUZZ_SEED=1")
