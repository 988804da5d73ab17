# plot_figures: scripts/plot on small synthetic runs whose figures and tables are known by hand
# (tests/integration/check_plots.py says what is checked). scripts/plot needs numpy and matplotlib
# from Debian (scripts/install-deps); a python3 found first on PATH (pyenv, conda) may lack them,
# so the interpreter is Debian's by default and can be changed here.
set(LIBDEM_PLOT_PYTHON /usr/bin/python3 CACHE FILEPATH
    "Python 3 with numpy and matplotlib, used by the plot_figures test")
add_test(NAME plot_figures
         COMMAND ${LIBDEM_PLOT_PYTHON} ${PROJECT_SOURCE_DIR}/tests/integration/check_plots.py ${PROJECT_SOURCE_DIR})
set_tests_properties(plot_figures PROPERTIES TIMEOUT 600 LABELS "scripts")
