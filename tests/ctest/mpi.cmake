# mpi_task_farms: dem-calibrate and dem-ensemble under mpirun at 1, 2 and 3 ranks give the
# one-process results (tests/integration/check_mpi_farms.py). Needs the apps built with MPI
# (libdem::mpi, from Debian's libopenmpi-dev) and mpirun; about a minute on two cores.
if(TARGET dem_mpi AND TARGET dem-calibrate AND TARGET dem-ensemble AND TARGET dem-simple-shear AND TARGET dem-consolidate
   AND TARGET dem-bench)
  set(LIBDEM_TEST_PYTHON /usr/bin/python3 CACHE FILEPATH "Python 3 for the app tests (standard library only)")
  find_program(LIBDEM_MPIRUN NAMES mpirun.openmpi mpirun)  # OpenMPI's: the test uses --oversubscribe
  if(LIBDEM_MPIRUN)
    add_test(NAME mpi_task_farms
             COMMAND ${LIBDEM_TEST_PYTHON} ${PROJECT_SOURCE_DIR}/tests/integration/check_mpi_farms.py
                     $<TARGET_FILE:dem-calibrate> $<TARGET_FILE:dem-ensemble> ${LIBDEM_MPIRUN})
    set_tests_properties(mpi_task_farms PROPERTIES TIMEOUT 900 LABELS "app;mpi" ENVIRONMENT "OMP_WAIT_POLICY=passive")
    # mpi_domains: one simulation spread over 1, 2 and 3 ranks gives the one-process results bit for
    # bit (tests/integration/check_mpi_domains.py); about a minute and a half on two cores.
    add_test(NAME mpi_domains
             COMMAND ${LIBDEM_TEST_PYTHON} ${PROJECT_SOURCE_DIR}/tests/integration/check_mpi_domains.py
                     $<TARGET_FILE:dem-bench> $<TARGET_FILE:dem-simple-shear> $<TARGET_FILE:dem-consolidate>
                     ${LIBDEM_MPIRUN})
    set_tests_properties(mpi_domains PROPERTIES TIMEOUT 900 LABELS "app;mpi" ENVIRONMENT "OMP_WAIT_POLICY=passive")
  endif()
endif()
