# cyclic_scripts: scripts/cyclic-campaign and scripts/plot-cyclic on the reduced specimen
# (tests/integration/check_cyclic_scripts.py says what is checked), with Debian's python3 as
# plot_figures uses (plot.cmake).
add_test(NAME cyclic_scripts
         COMMAND ${LIBDEM_PLOT_PYTHON} ${PROJECT_SOURCE_DIR}/tests/integration/check_cyclic_scripts.py
                 ${PROJECT_SOURCE_DIR} ${PROJECT_BINARY_DIR})
set_tests_properties(cyclic_scripts PROPERTIES TIMEOUT 600 LABELS "scripts")
