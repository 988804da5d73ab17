# Fuzzed parsers (tests/fuzz/README.md): the config reader, the restart-file reader and the CSV
# reader each have one LLVMFuzzerTestOneInput. Every build compiles it with replay_main.cpp into
# fuzz_replay_<target>, and CTest replays the committed corpus through it, so the Release and the
# sanitizer stages both check that every known input is accepted or refused with an InputError.
# With LIBDEM_FUZZ=ON and clang (tests/fuzz/run-fuzz sets this up) the same sources also build
# as libFuzzer executables fuzz_<target>.
set(LIBDEM_FUZZ_DIR ${PROJECT_SOURCE_DIR}/tests/fuzz)
option(LIBDEM_FUZZ "Also build the libFuzzer executables (clang; see tests/fuzz/run-fuzz)" OFF)
if(LIBDEM_FUZZ AND NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  message(FATAL_ERROR "LIBDEM_FUZZ needs clang++ (libFuzzer); this build uses ${CMAKE_CXX_COMPILER_ID}")
endif()

foreach(target config checkpoint csv)
  add_executable(fuzz_replay_${target} ${LIBDEM_FUZZ_DIR}/fuzz_${target}.cpp ${LIBDEM_FUZZ_DIR}/replay_main.cpp)
  target_link_libraries(fuzz_replay_${target} PRIVATE libdem::dem libdem_flags)
  add_test(NAME fuzz_corpus_${target} COMMAND fuzz_replay_${target} ${LIBDEM_FUZZ_DIR}/corpus/${target})
  set_tests_properties(fuzz_corpus_${target} PROPERTIES TIMEOUT 300 LABELS "fuzz")
  if(LIBDEM_FUZZ)
    add_executable(fuzz_${target} ${LIBDEM_FUZZ_DIR}/fuzz_${target}.cpp)
    target_link_libraries(fuzz_${target} PRIVATE libdem::dem libdem_flags)
    target_link_options(fuzz_${target} PRIVATE -fsanitize=fuzzer)
  endif()
endforeach()

# Writes the seed files of the corpora; built on request only (tests/fuzz/make_seeds.cpp).
add_executable(fuzz_make_seeds EXCLUDE_FROM_ALL ${LIBDEM_FUZZ_DIR}/make_seeds.cpp)
target_link_libraries(fuzz_make_seeds PRIVATE libdem::dem libdem_flags)
