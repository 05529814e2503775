# What `cmake --install` and the .deb put where (cmake/layout.cmake):
#   bin/nlsoft-console
#   libexec/nlsoft/nlsoft-firmware-sim            started by --sim, not a command of its own
#   share/nlsoft/firmware/{m4,m7,stm32f4}/        the Cortex-M images, when built
#   share/nlsoft/models/                          the shipped models (cmake/models.cmake)
#   share/nlsoft/firmware-src/                    what `firmware build` builds an image from
#   share/man/man1/nlsoft-console.1               (cmake/man_page.cmake)
#   share/bash-completion/completions/nlsoft-console
#   share/doc/nlsoft/                             README.md, CONSOLE.md, PROTOCOL.md
install(TARGETS nlsoft-console RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS nlsoft-firmware-sim RUNTIME DESTINATION ${NLSOFT_INSTALL_LIBEXECDIR})

# The images keep the build tree's m4/, m7/ and stm32f4/ folders, so the console
# asks for one relative name in either place. ELF for QEMU and openocd, .bin
# for st-flash; the link maps and no-heap reports stay behind.
if(TARGET nlsoft-m4-images)
  install(DIRECTORY ${NLSOFT_M4_BINARY_DIR}/ DESTINATION ${NLSOFT_INSTALL_DATADIR}/firmware/m4
          FILES_MATCHING PATTERN "nlsoft-m4-*.elf" PATTERN "nlsoft-m4-*.bin" PATTERN CMakeFiles EXCLUDE)
endif()
if(TARGET nlsoft-m7-images)
  install(DIRECTORY ${NLSOFT_M7_BINARY_DIR}/ DESTINATION ${NLSOFT_INSTALL_DATADIR}/firmware/m7
          FILES_MATCHING PATTERN "nlsoft-m7-*.elf" PATTERN "nlsoft-m7-*.bin" PATTERN CMakeFiles EXCLUDE)
endif()
if(TARGET nlsoft-stm32f4-images)
  install(DIRECTORY ${NLSOFT_STM32F4_BINARY_DIR}/ DESTINATION ${NLSOFT_INSTALL_DATADIR}/firmware/stm32f4
          FILES_MATCHING PATTERN "nlsoft-stm32f4-*.elf" PATTERN "nlsoft-stm32f4-*.bin" PATTERN CMakeFiles EXCLUDE)
endif()

# The sources `nlsoft-console firmware build` compiles an image from: the
# firmware core, the sensor chip drivers and the Cortex-M ports, the header-only shared/ and
# protocol/, and the warnings list the images are built with. The build
# tree has a link to the source tree in the same place (firmware/CMakeLists.txt).
install(DIRECTORY ${NLSOFT_ROOT}/firmware/core ${NLSOFT_ROOT}/firmware/drivers
        DESTINATION ${NLSOFT_INSTALL_DATADIR}/firmware-src/firmware)
install(DIRECTORY ${NLSOFT_ROOT}/firmware/ports/cortex-m ${NLSOFT_ROOT}/firmware/ports/mps2-an386
                  ${NLSOFT_ROOT}/firmware/ports/mps2-an500 ${NLSOFT_ROOT}/firmware/ports/mps2-an385
                  ${NLSOFT_ROOT}/firmware/ports/stm32f4
        DESTINATION ${NLSOFT_INSTALL_DATADIR}/firmware-src/firmware/ports)
install(DIRECTORY ${NLSOFT_ROOT}/shared ${NLSOFT_ROOT}/protocol DESTINATION ${NLSOFT_INSTALL_DATADIR}/firmware-src
        FILES_MATCHING PATTERN "*.hpp" PATTERN "*.h")
install(FILES ${NLSOFT_ROOT}/cmake/warning_flags.txt DESTINATION ${NLSOFT_INSTALL_DATADIR}/firmware-src/cmake)

include(${CMAKE_CURRENT_LIST_DIR}/man_page.cmake)

# Named after the command: bash-completion loads it on first use.
install(FILES ${NLSOFT_ROOT}/app/dist/nlsoft-console.bash-completion
        DESTINATION ${CMAKE_INSTALL_DATADIR}/bash-completion/completions RENAME nlsoft-console)

install(FILES ${NLSOFT_ROOT}/README.md ${NLSOFT_ROOT}/app/CONSOLE.md ${NLSOFT_ROOT}/protocol/PROTOCOL.md
        DESTINATION ${CMAKE_INSTALL_DOCDIR})
