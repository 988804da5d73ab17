# Installs the library, its headers and a relocatable CMake package so that a research code can
#   find_package(libdem CONFIG REQUIRED)
#   target_link_libraries(mycode PRIVATE libdem::dem)
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(LIBDEM_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/libdem)
set(LIBDEM_INSTALL_TARGETS dem)
set(LIBDEM_WITH_MPI OFF)
if(TARGET dem_mpi)
  list(APPEND LIBDEM_INSTALL_TARGETS dem_mpi)  # libdem::mpi
  set(LIBDEM_WITH_MPI ON)
endif()
install(TARGETS ${LIBDEM_INSTALL_TARGETS} EXPORT libdemTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/libdem/include/dem DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT libdemTargets NAMESPACE libdem:: DESTINATION ${LIBDEM_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/libdemConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/libdemConfig.cmake
                              INSTALL_DESTINATION ${LIBDEM_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/libdemConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/libdemConfig.cmake ${PROJECT_BINARY_DIR}/libdemConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/FindFFTW3.cmake
        DESTINATION ${LIBDEM_CMAKE_DIR})
