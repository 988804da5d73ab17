# python_api: the pytest tests of the Python module (tests/python), with Debian's python3 and
# python3-pytest, the module from this build tree and the apps beside it.
if(TARGET libdem_python)
  add_test(NAME python_api
           COMMAND ${LIBDEM_PYTHON_EXECUTABLE} -m pytest -q -p no:cacheprovider ${CMAKE_CURRENT_SOURCE_DIR}/python)
  set_tests_properties(python_api PROPERTIES TIMEOUT 600 LABELS "python"
                       ENVIRONMENT "PYTHONPATH=${PROJECT_BINARY_DIR}/python;LIBDEM_BUILD_DIR=${PROJECT_BINARY_DIR};OMP_WAIT_POLICY=passive")
endif()
