# The shipped rig files (rigs/*.toml, docs/rig-file.md): staged into the
# build tree's share/nlsoft/rigs as an install prefix has them, so
# `--rig hasel` finds them relative to the binary in both (host/paths), and
# installed to <prefix>/share/nlsoft/rigs.
file(GLOB NLSOFT_SHIPPED_RIGS CONFIGURE_DEPENDS ${NLSOFT_ROOT}/rigs/*.toml)
set(_staged "")
foreach(_rig IN LISTS NLSOFT_SHIPPED_RIGS)
  get_filename_component(_name ${_rig} NAME)
  add_custom_command(OUTPUT ${NLSOFT_BUILD_DATADIR}/rigs/${_name}
    COMMAND ${CMAKE_COMMAND} -E copy ${_rig} ${NLSOFT_BUILD_DATADIR}/rigs/${_name}
    DEPENDS ${_rig}
    COMMENT "Rig ${_name} into the build tree's share/nlsoft/rigs")
  list(APPEND _staged ${NLSOFT_BUILD_DATADIR}/rigs/${_name})
endforeach()
add_custom_target(nlsoft-rigs ALL DEPENDS ${_staged})
add_dependencies(nlsoft-console nlsoft-rigs)

install(FILES ${NLSOFT_SHIPPED_RIGS} DESTINATION ${NLSOFT_INSTALL_DATADIR}/rigs)

# Example rig files to copy and edit (rigs/examples/*.toml: docs/rig-file.md
# shows each in full, and the docs test keeps the two one text): not rigs by
# name, installed beside them in <prefix>/share/nlsoft/rigs/examples.
file(GLOB NLSOFT_EXAMPLE_RIGS CONFIGURE_DEPENDS ${NLSOFT_ROOT}/rigs/examples/*.toml)
install(FILES ${NLSOFT_EXAMPLE_RIGS} DESTINATION ${NLSOFT_INSTALL_DATADIR}/rigs/examples)
