# pip_package: a virtual environment, `pip install -e` and `pip install` of this source tree offline
# (the README's commands), then the package from a folder outside the repository: pour.py, help()
# and type stubs that define every public name (tests/consumer/pip_install_check.py). The pip build
# makes the library and the module only, in build/pip-check/build-pip; from a clean clone that is
# the long part (7.5 min on 2 cores shared with other builds), and a re-run takes about 15 s. A high COST
# starts it first, so that it overlaps the other tests.
if(TARGET libdem_python)
  add_test(NAME pip_package
           COMMAND ${LIBDEM_PYTHON_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/consumer/pip_install_check.py ${PROJECT_SOURCE_DIR}
                   ${PROJECT_BINARY_DIR}/pip-check)
  set_tests_properties(pip_package PROPERTIES TIMEOUT 3000 LABELS "pip;python" COST 10000
                       ENVIRONMENT "OMP_NUM_THREADS=1;OMP_WAIT_POLICY=passive")
endif()
