# layout: no file of the library over 600 lines and no include up a floor (scripts/check-layout).
find_program(LIBDEM_LAYOUT_PYTHON NAMES python3)
if(LIBDEM_LAYOUT_PYTHON)
  add_test(NAME layout COMMAND ${LIBDEM_LAYOUT_PYTHON} ${PROJECT_SOURCE_DIR}/scripts/check-layout ${PROJECT_SOURCE_DIR})
  set_tests_properties(layout PROPERTIES LABELS "scripts")
endif()
