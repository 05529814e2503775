# nlsoft-console(1), made from the console's own --help and --version by
# Debian's help2man at build time, so it never disagrees with the binary;
# app/dist/nlsoft-console.h2m adds what --help does not say (the
# environment, where files are looked for).
option(NLSOFT_MAN_PAGE "Generate and install the nlsoft-console man page (needs help2man)" ON)
if(NOT NLSOFT_MAN_PAGE)
  return()
endif()
find_program(NLSOFT_HELP2MAN help2man)
if(NOT NLSOFT_HELP2MAN)
  message(FATAL_ERROR "help2man not found: apt-get install help2man (bash cmake/dev deps does), "
                      "or configure with -DNLSOFT_MAN_PAGE=OFF to build without the man page")
endif()
set(NLSOFT_MAN_PAGE_FILE ${CMAKE_BINARY_DIR}/share/man/man1/nlsoft-console.1)
set(_include ${NLSOFT_ROOT}/app/dist/nlsoft-console.h2m)
add_custom_command(OUTPUT ${NLSOFT_MAN_PAGE_FILE}
  COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_BINARY_DIR}/share/man/man1
  # A fixed width and locale: the page must not depend on who built it.
  COMMAND ${CMAKE_COMMAND} -E env COLUMNS=80 LC_ALL=C.UTF-8
          ${NLSOFT_HELP2MAN} --no-info --section=1 --include=${_include} --output=${NLSOFT_MAN_PAGE_FILE}
          $<TARGET_FILE:nlsoft-console>
  DEPENDS nlsoft-console ${_include}
  COMMENT "Man page nlsoft-console.1 from --help (help2man)")
add_custom_target(nlsoft-man-page ALL DEPENDS ${NLSOFT_MAN_PAGE_FILE})
install(FILES ${NLSOFT_MAN_PAGE_FILE} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
