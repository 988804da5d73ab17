# Installs the library, its headers and a relocatable CMake package so that a research code can
#   find_package(libdem CONFIG REQUIRED)
#   target_link_libraries(mycode PRIVATE libdem::dem)
# and, when libdem was built with MPI, find_package(libdem CONFIG REQUIRED COMPONENTS mpi) for
# libdem::mpi.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(LIBDEM_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/libdem)
install(TARGETS dem EXPORT libdemTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT libdemTargets NAMESPACE libdem:: DESTINATION ${LIBDEM_CMAKE_DIR})
# libdem::mpi in an export of its own, which the package loads only where MPI is found, so that
# a consumer of libdem::dem alone never needs MPI.
set(LIBDEM_WITH_MPI OFF)
set(libdem_header_excludes)
if(TARGET dem_mpi)
  set(LIBDEM_WITH_MPI ON)
  install(TARGETS dem_mpi EXPORT libdemMpiTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  install(EXPORT libdemMpiTargets NAMESPACE libdem:: DESTINATION ${LIBDEM_CMAKE_DIR})
else()
  set(libdem_header_excludes PATTERN mpi_farm.hpp EXCLUDE)
endif()
install(DIRECTORY ${PROJECT_SOURCE_DIR}/libdem/include/dem DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} ${libdem_header_excludes})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/libdemConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/libdemConfig.cmake
                              INSTALL_DESTINATION ${LIBDEM_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/libdemConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/libdemConfig.cmake ${PROJECT_BINARY_DIR}/libdemConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/FindFFTW3.cmake
        DESTINATION ${LIBDEM_CMAKE_DIR})
