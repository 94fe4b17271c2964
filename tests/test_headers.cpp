// Builds the precompiled header the test files share (mbgen_test_headers, tests/CMakeLists.txt).
