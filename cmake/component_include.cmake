# Every include names the component it comes from ("shared/model.hpp",
# "protocol/frame.hpp"). Each component's include directory is a folder of
# the build tree holding one link, to that component alone, so a target sees
# the headers of the components it links and no others: CMake, not habit,
# keeps the layering (a "protocol/..." include in a target that does not
# link nlsoft_protocol fails to compile).
function(nlsoft_component_include_dir component out_var)
  set(dir ${CMAKE_BINARY_DIR}/include/${component})
  if(NOT EXISTS ${dir}/${component})
    file(MAKE_DIRECTORY ${dir})
    file(CREATE_LINK ${NLSOFT_ROOT}/${component} ${dir}/${component} SYMBOLIC)
  endif()
  set(${out_var} ${dir} PARENT_SCOPE)
endfunction()
