# Where things go in an install prefix (GNUInstallDirs), and the paths the
# binaries use to find their companion files from their own location. Only
# relative paths are compiled in: a prefix, or the .deb's /usr, works
# wherever it is put, and nothing points into the source or build folder.
include(GNUInstallDirs)

# The console's files under the prefix.
set(NLSOFT_INSTALL_LIBEXECDIR ${CMAKE_INSTALL_LIBEXECDIR}/nlsoft)   # nlsoft-firmware-sim
set(NLSOFT_INSTALL_DATADIR ${CMAKE_INSTALL_DATADIR}/nlsoft)         # firmware/, models/

# The build tree keeps the shipped models where an install prefix does,
# relative to <build>/app and <build>/firmware: <build>/share/nlsoft/models.
set(NLSOFT_BUILD_DATADIR ${CMAKE_BINARY_DIR}/share/nlsoft)

# A made-up root stands for the prefix: only the relative layout matters.
function(_nlsoft_relative out from to)
  file(RELATIVE_PATH _rel /nlsoft-prefix/${from} /nlsoft-prefix/${to})
  set(${out} ${_rel} PARENT_SCOPE)
endfunction()
_nlsoft_relative(NLSOFT_BIN_TO_LIBEXEC ${CMAKE_INSTALL_BINDIR} ${NLSOFT_INSTALL_LIBEXECDIR})
_nlsoft_relative(NLSOFT_BIN_TO_DATA ${CMAKE_INSTALL_BINDIR} ${NLSOFT_INSTALL_DATADIR})
_nlsoft_relative(NLSOFT_LIBEXEC_TO_DATA ${NLSOFT_INSTALL_LIBEXECDIR} ${NLSOFT_INSTALL_DATADIR})
foreach(_dir CMAKE_INSTALL_BINDIR CMAKE_INSTALL_LIBEXECDIR CMAKE_INSTALL_DATADIR)
  if(IS_ABSOLUTE "${${_dir}}")
    message(FATAL_ERROR "${_dir}=${${_dir}}: nlsoft finds its files relative to its binaries; give a path "
                        "relative to the prefix")
  endif()
endforeach()
