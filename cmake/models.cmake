# The shipped models (app/models/*.nlsm): copied into the build tree where an
# install prefix has them, <build>/share/nlsoft/models, so the console and
# the simulator find them relative to themselves in both (cmake/layout.cmake)
# and no binary carries the source folder's path; installed to
# <prefix>/share/nlsoft/models.
file(GLOB NLSOFT_SHIPPED_MODELS CONFIGURE_DEPENDS ${NLSOFT_ROOT}/app/models/*.nlsm)
set(_staged "")
foreach(_model IN LISTS NLSOFT_SHIPPED_MODELS)
  get_filename_component(_name ${_model} NAME)
  add_custom_command(OUTPUT ${NLSOFT_BUILD_DATADIR}/models/${_name}
    COMMAND ${CMAKE_COMMAND} -E copy ${_model} ${NLSOFT_BUILD_DATADIR}/models/${_name}
    DEPENDS ${_model}
    COMMENT "Model ${_name} into the build tree's share/nlsoft/models")
  list(APPEND _staged ${NLSOFT_BUILD_DATADIR}/models/${_name})
endforeach()
add_custom_target(nlsoft-models ALL DEPENDS ${_staged})
# Building either binary alone (as the tests do) brings the models along.
add_dependencies(nlsoft-console nlsoft-models)
add_dependencies(nlsoft-firmware-sim nlsoft-models)

install(FILES ${NLSOFT_SHIPPED_MODELS} DESTINATION ${NLSOFT_INSTALL_DATADIR}/models)
