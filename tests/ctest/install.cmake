# Installs libdem into a temporary prefix, then builds and runs examples/hello_pour.cpp as an
# outside project against it (find_package(libdem) + libdem::dem); with the Python module built,
# also imports the installed module with Debian's python3.
set(libdem_python_check "")
if(TARGET libdem_python)
  set(libdem_python_check -DPYTHON=${LIBDEM_PYTHON_EXECUTABLE} -DPYTHON_DIR=${LIBDEM_PYTHON_INSTALL_DIR})
endif()
add_test(NAME installed_package_links
         COMMAND ${CMAKE_COMMAND} -DBINARY_DIR=${PROJECT_BINARY_DIR} -DSOURCE_DIR=${PROJECT_SOURCE_DIR} ${libdem_python_check}
                 -P ${CMAKE_CURRENT_SOURCE_DIR}/consumer/install_check.cmake)
set_tests_properties(installed_package_links PROPERTIES TIMEOUT 900 ENVIRONMENT "OMP_NUM_THREADS=1")
