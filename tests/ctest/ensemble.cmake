# ensemble_seeds: scripts/ensemble runs two seeds of a reduced specimen, and its statistics equal
# those computed here from the seeds' own history.csv (tests/integration/check_ensemble.py).
add_test(NAME ensemble_seeds
         COMMAND ${LIBDEM_PLOT_PYTHON} ${PROJECT_SOURCE_DIR}/tests/integration/check_ensemble.py
                 ${PROJECT_SOURCE_DIR} $<TARGET_FILE:dem-simple-shear>)
set_tests_properties(ensemble_seeds PROPERTIES TIMEOUT 600 LABELS "scripts")
