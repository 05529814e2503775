# `cpack -G DEB` in the build folder: nlsoft_<version>_<arch>.deb, laid out
# as cmake/install.cmake says under /usr. The version is the project's, read
# from shared/version.hpp by the top CMakeLists.txt.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME nlsoft)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "learned-model predictive control for soft actuators: console and firmware")
set(CPACK_PACKAGE_DESCRIPTION
    "nlsoft-console tunes a learned model-predictive controller running on a microcontroller live on\n"
    "the rig, records and compares runs, and runs the controller offline against simulated rigs.\n"
    "Ships the firmware simulator (no hardware needed), the Cortex-M4F images for QEMU and\n"
    "STM32F4 Nucleo-64 boards, and the trained models of the msd, hasel and tendon rigs.")
string(REPLACE ";" "" CPACK_PACKAGE_DESCRIPTION "${CPACK_PACKAGE_DESCRIPTION}")
set(NLSOFT_PACKAGE_MAINTAINER "nlsoft maintainers" CACHE STRING "the .deb's Maintainer field")
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${NLSOFT_PACKAGE_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
# The host binaries only (install(TARGETS)); the Cortex-M images keep their
# symbols for a debugger on the board.
set(CPACK_STRIP_FILES ON)

# Runtime dependencies: dpkg-shlibdeps reads them off the binaries when it
# is there (dpkg-dev; CPack picks the binaries with `file`); otherwise the
# libraries this build links, by their Debian bookworm package names
# (Boost.Asio is header-only: no Boost library at run time).
find_program(NLSOFT_DPKG_SHLIBDEPS dpkg-shlibdeps)
find_program(NLSOFT_FILE file)
if(NLSOFT_DPKG_SHLIBDEPS AND NLSOFT_FILE)
  set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
else()
  set(CPACK_DEBIAN_PACKAGE_DEPENDS
      "libc6, libstdc++6, libgcc-s1, libncursesw6, libtinfo6, libsqlite3-0, libhdf5-103-1, libfmt9")
endif()
# --qemu and `runs plot` need them; the console says which is missing.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "qemu-system-arm, gnuplot-nox")
# `flash` writes a real board; the completion needs bash-completion to load.
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "openocd, bash-completion")

include(CPack)
