# The live console: link and session over Boost.Asio, SQLite
# recording, scripts and the ncurses TUI. Included from app/CMakeLists.txt.
find_package(Boost REQUIRED COMPONENTS system)
find_package(SQLite3 REQUIRED)
# runs export --h5 (the same library the Keras import reads with).
find_package(HDF5 REQUIRED COMPONENTS C)
set(CURSES_NEED_WIDE TRUE)
set(CURSES_NEED_NCURSES TRUE)
find_package(Curses REQUIRED)
# The tuner's derivative-free optimisers (BOBYQA, Nelder-Mead): Debian's
# libnlopt-cxx-dev, found through its pkg-config file.
find_package(PkgConfig REQUIRED)
pkg_check_modules(NLOPT REQUIRED IMPORTED_TARGET nlopt)

file(GLOB NLSOFT_CONSOLE_LIVE_SOURCES CONFIGURE_DEPENDS
  ${CMAKE_CURRENT_SOURCE_DIR}/link/*.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/target/*.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/conformance/*.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/record/*.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/script/*.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/tui/*.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/tune/*.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/replay/*.cpp
  ${CMAKE_CURRENT_SOURCE_DIR}/live/*.cpp)
add_library(nlsoft_console_live STATIC ${NLSOFT_CONSOLE_LIVE_SOURCES})
# The kernel's termios2 (asm/termbits.h) redefines glibc's struct termios:
# compiled alone, never in a unity source beside a file using <termios.h>.
set_source_files_properties(${CMAKE_CURRENT_SOURCE_DIR}/link/custom_baud.cpp PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
target_include_directories(nlsoft_console_live PUBLIC ${NLSOFT_APP_INCLUDE} PRIVATE ${CURSES_INCLUDE_DIRS})
target_include_directories(nlsoft_console_live SYSTEM PRIVATE ${HDF5_C_INCLUDE_DIRS} ${HDF5_INCLUDE_DIRS})
target_compile_definitions(nlsoft_console_live PUBLIC BOOST_ASIO_NO_DEPRECATED)
target_link_libraries(nlsoft_console_live
  PUBLIC nlsoft_console_core nlsoft_console_text nlsoft_firmware_image nlsoft_model_pipeline nlsoft_rig_console nlsoft_gnuplot_text nlsoft::protocol Boost::system SQLite::SQLite3 Threads::Threads
  PRIVATE ${CURSES_LIBRARIES} PkgConfig::NLOPT ${HDF5_C_LIBRARIES} ${HDF5_LIBRARIES}
  # runs replay runs the simulator's firmware core in the console's process.
  nlsoft_firmware_core)

target_link_libraries(nlsoft-console PRIVATE nlsoft_console_live)
target_compile_definitions(nlsoft-console PRIVATE NLSOFT_VERSION="${PROJECT_VERSION}")

# The console's intake (port bytes -> session -> samples -> recorder and
# live buffer) under libFuzzer (NLSOFT_FUZZ: protocol/CMakeLists.txt).
if(NLSOFT_FUZZ AND CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  add_subdirectory(${CMAKE_CURRENT_SOURCE_DIR}/link/fuzz ${CMAKE_CURRENT_BINARY_DIR}/link/fuzz)
endif()
