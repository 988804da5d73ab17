# ensemble_seeds: scripts/ensemble runs two seeds of a reduced specimen, and its statistics equal
# those computed here from the seeds' own history.csv (tests/integration/check_ensemble.py). It
# needs dem-ensemble and Debian's python3 with numpy and matplotlib (scripts/install-deps).
if(TARGET dem-ensemble)
  set(LIBDEM_ENSEMBLE_PYTHON /usr/bin/python3 CACHE FILEPATH "Python 3 with numpy, used by the ensemble_seeds test")
  add_test(NAME ensemble_seeds
           COMMAND ${LIBDEM_ENSEMBLE_PYTHON} ${PROJECT_SOURCE_DIR}/tests/integration/check_ensemble.py
                   ${PROJECT_SOURCE_DIR} $<TARGET_FILE:dem-ensemble>)
  set_tests_properties(ensemble_seeds PROPERTIES TIMEOUT 600 LABELS "scripts" ENVIRONMENT "OMP_WAIT_POLICY=passive")
endif()
