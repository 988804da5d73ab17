# Installs libdem into a temporary prefix, then builds and runs examples/hello_pour.cpp as an
# outside project against it (find_package(libdem) + libdem::dem).
add_test(NAME installed_package_links
         COMMAND ${CMAKE_COMMAND} -DBINARY_DIR=${PROJECT_BINARY_DIR} -DSOURCE_DIR=${PROJECT_SOURCE_DIR}
                 -P ${CMAKE_CURRENT_SOURCE_DIR}/consumer/install_check.cmake)
set_tests_properties(installed_package_links PROPERTIES TIMEOUT 900 ENVIRONMENT "OMP_NUM_THREADS=1")
