# kill_resume: dem-simple-shear killed with SIGKILL in each stage and resumed with --from equals an
# uninterrupted run byte for byte; damaged restart files are refused with exit code 2; history.csv
# is never torn by a kill (tests/integration/kill_resume.py says what is checked). It needs only
# the Python standard library. About a minute in Release; the sanitizer stage leaves it out.
if(TARGET dem-simple-shear)
  set(LIBDEM_TEST_PYTHON /usr/bin/python3 CACHE FILEPATH "Python 3 for the kill_resume test (standard library only)")
  add_test(NAME kill_resume
           COMMAND ${LIBDEM_TEST_PYTHON} ${PROJECT_SOURCE_DIR}/tests/integration/kill_resume.py
                   $<TARGET_FILE:dem-simple-shear> ${CMAKE_CURRENT_BINARY_DIR}/kill_resume)
  set_tests_properties(kill_resume PROPERTIES TIMEOUT 1200 LABELS "app;slow" ENVIRONMENT "OMP_WAIT_POLICY=passive")
endif()
