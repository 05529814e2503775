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

# The images keep the build tree's folders (m4/, m7/, stm32f4/: one per board
# of NLSOFT_IMAGE_BOARDS), so the console asks for one relative name in
# either place; a board's images are nlsoft-<folder>-*. ELF for QEMU and openocd, .bin
# for st-flash; the link maps and no-heap reports stay behind.
foreach(_dir ${NLSOFT_IMAGE_BOARD_DIRS})
  get_filename_component(_folder ${_dir} NAME)
  if(TARGET nlsoft-${_folder}-images)
    install(DIRECTORY ${_dir}/ DESTINATION ${NLSOFT_INSTALL_DATADIR}/firmware/${_folder}
            FILES_MATCHING PATTERN "nlsoft-${_folder}-*.elf" PATTERN "nlsoft-${_folder}-*.bin" PATTERN CMakeFiles EXCLUDE)
  endif()
endforeach()

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
