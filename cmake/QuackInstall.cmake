include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

install(TARGETS ${QUACK_LAYERS} quack_all EXPORT quackTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/quack DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT quackTargets NAMESPACE quack:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/quack)

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/quackConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/quackConfig.cmake
                              INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/quack)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/quackConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/quackConfig.cmake ${PROJECT_BINARY_DIR}/quackConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/quack)
