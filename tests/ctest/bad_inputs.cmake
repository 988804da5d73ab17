# bad_inputs: the apps refuse a table of bad inputs (files that are not what they claim, absurd
# values, keys that do not apply, restart files of the wrong test) at the door: exit code 2, a
# short message naming what was wrong, --out not created (tests/integration/bad_inputs.py). It
# makes two small runs for their restart files, then each case takes a fraction of a second.
if(TARGET dem-simple-shear AND TARGET dem-cyclic-shear AND TARGET dem-calibrate AND TARGET dem-consolidate
   AND TARGET dem-element-test)
  set(LIBDEM_TEST_PYTHON /usr/bin/python3 CACHE FILEPATH "Python 3 for the app tests (standard library only)")
  add_test(NAME bad_inputs
           COMMAND ${LIBDEM_TEST_PYTHON} ${PROJECT_SOURCE_DIR}/tests/integration/bad_inputs.py
                   $<TARGET_FILE_DIR:dem-simple-shear> ${CMAKE_CURRENT_BINARY_DIR}/bad_inputs)
  set_tests_properties(bad_inputs PROPERTIES TIMEOUT 600 LABELS "app" ENVIRONMENT "OMP_WAIT_POLICY=passive")
endif()
