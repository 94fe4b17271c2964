# Install rules and the `mbgen` package: `cmake --install build --prefix P` puts the generator in
# P/bin, its templates in P/share/mbgen/templates, the runtime headers in P/include/mbgen and the
# package files in P/lib/cmake/mbgen, so that
# another project can write
#
#   find_package(mbgen REQUIRED)          # mbgen::mbgen (the generator), mbgen::runtime (headers)
#   mbgen_add_robot(TARGET my_robot DESCRIPTION robot.urdf ...)
#
# The generator is built for the host; a cross build sets MBGEN_EXECUTABLE instead.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(MBGEN_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/mbgen)

set_target_properties(mbgen_runtime PROPERTIES EXPORT_NAME runtime)
install(TARGETS mbgen mbgen_runtime EXPORT mbgenTargets
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/runtime/include/mbgen DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${MBGEN_TEMPLATES_DIR}/ DESTINATION ${MBGEN_TEMPLATES_INSTALL_DIR})
install(EXPORT mbgenTargets NAMESPACE mbgen:: DESTINATION ${MBGEN_INSTALL_CMAKEDIR})

configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/mbgenConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/mbgenConfig.cmake
                              INSTALL_DESTINATION ${MBGEN_INSTALL_CMAKEDIR}
                              PATH_VARS MBGEN_TEMPLATES_INSTALL_DIR)
# 0.x: a minor release may change the generated API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/mbgenConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/mbgenConfig.cmake ${PROJECT_BINARY_DIR}/mbgenConfigVersion.cmake
              ${CMAKE_CURRENT_LIST_DIR}/mbgen_add_robot.cmake ${PROJECT_BINARY_DIR}/mbgen_functions.cmake
        DESTINATION ${MBGEN_INSTALL_CMAKEDIR})
