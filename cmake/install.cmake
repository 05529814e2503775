# What `cmake --install` and the .deb put where (cmake/layout.cmake):
#   bin/nlsoft-console
#   libexec/nlsoft/nlsoft-firmware-sim            started by --sim, not a command of its own
#   share/nlsoft/firmware/{m4,stm32f4}/           the Cortex-M images, when built
#   share/nlsoft/models/                          the shipped models (cmake/models.cmake)
#   share/man/man1/nlsoft-console.1               (cmake/man_page.cmake)
#   share/bash-completion/completions/nlsoft-console
#   share/doc/nlsoft/                             README.md, CONSOLE.md, PROTOCOL.md
install(TARGETS nlsoft-console RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS nlsoft-firmware-sim RUNTIME DESTINATION ${NLSOFT_INSTALL_LIBEXECDIR})

# The images keep the build tree's m4/ and stm32f4/ folders, so the console
# asks for one relative name in either place. ELF for QEMU and openocd, .bin
# for st-flash; the link maps and no-heap reports stay behind.
if(TARGET nlsoft-m4-images)
  install(DIRECTORY ${NLSOFT_M4_BINARY_DIR}/ DESTINATION ${NLSOFT_INSTALL_DATADIR}/firmware/m4
          FILES_MATCHING PATTERN "nlsoft-m4-*.elf" PATTERN "nlsoft-m4-*.bin" PATTERN CMakeFiles EXCLUDE)
endif()
if(TARGET nlsoft-stm32f4-images)
  install(DIRECTORY ${NLSOFT_STM32F4_BINARY_DIR}/ DESTINATION ${NLSOFT_INSTALL_DATADIR}/firmware/stm32f4
          FILES_MATCHING PATTERN "nlsoft-stm32f4-*.elf" PATTERN "nlsoft-stm32f4-*.bin" PATTERN CMakeFiles EXCLUDE)
endif()

include(${CMAKE_CURRENT_LIST_DIR}/man_page.cmake)

# Named after the command: bash-completion loads it on first use.
install(FILES ${NLSOFT_ROOT}/app/dist/nlsoft-console.bash-completion
        DESTINATION ${CMAKE_INSTALL_DATADIR}/bash-completion/completions RENAME nlsoft-console)

install(FILES ${NLSOFT_ROOT}/README.md ${NLSOFT_ROOT}/app/CONSOLE.md ${NLSOFT_ROOT}/protocol/PROTOCOL.md
        DESTINATION ${CMAKE_INSTALL_DOCDIR})
