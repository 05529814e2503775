# The console's test executables; the folders under tests/app add their
# files. Helpers shared by them are in tests/app/support.
#
# Unit tests: the session against an in-process fake peer on a pty, the
# recorder, scripts, CSV export, the TUI's pieces.
add_executable(nlsoft-test-console)
target_include_directories(nlsoft-test-console PRIVATE ${NLSOFT_ROOT}/tests)
target_link_libraries(nlsoft-test-console PRIVATE nlsoft_console_live GTest::gtest_main util)
target_compile_definitions(nlsoft-test-console PRIVATE NLSOFT_RIGS_DIR="${NLSOFT_ROOT}/rigs")
# The test binaries are not where the console is: the rig files are named for them.
gtest_discover_tests(nlsoft-test-console DISCOVERY_TIMEOUT 30 PROPERTIES TIMEOUT 60 LABELS console
  ENVIRONMENT NLSOFT_RIGS=${NLSOFT_ROOT}/rigs)

# End-to-end over a pty against the firmware simulator, and the TUI in tmux.
add_executable(nlsoft-test-console-e2e)
find_package(HDF5 REQUIRED COMPONENTS C)
target_include_directories(nlsoft-test-console-e2e PRIVATE ${NLSOFT_ROOT}/tests)
target_link_libraries(nlsoft-test-console-e2e PRIVATE nlsoft_console_live GTest::gtest_main ${HDF5_C_LIBRARIES} ${HDF5_LIBRARIES})
# test_h5_export reads the exported files back with HDF5's own reader.
target_include_directories(nlsoft-test-console-e2e SYSTEM PRIVATE ${HDF5_C_INCLUDE_DIRS} ${HDF5_INCLUDE_DIRS})
target_compile_definitions(nlsoft-test-console-e2e PRIVATE
  NLSOFT_CONSOLE_BIN="$<TARGET_FILE:nlsoft-console>"
  NLSOFT_FIRMWARE_SIM_BIN="$<TARGET_FILE:nlsoft-firmware-sim>"
  NLSOFT_SOURCE_MODELS_DIR="${NLSOFT_ROOT}/app/models")
add_dependencies(nlsoft-test-console-e2e nlsoft-console nlsoft-firmware-sim)
# ENVIRONMENT before LABELS: the discovered tests' properties are one flat
# list, so a list-valued LABELS must come last or it shifts the pairs after it.
gtest_discover_tests(nlsoft-test-console-e2e DISCOVERY_TIMEOUT 30 PROPERTIES TIMEOUT 90
  ENVIRONMENT NLSOFT_RIGS=${NLSOFT_ROOT}/rigs LABELS "console;e2e")
