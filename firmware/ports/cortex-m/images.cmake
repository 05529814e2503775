# The images every Cortex-M4F port builds, included by the port's own
# project (ports/mps2-an386, ports/stm32f4) after project():
#
#   nlsoft_cortex_m_images(PREFIX nlsoft-m4 NAME nlsoft-an386 LINKER_SCRIPT an386.ld
#                          BOARD_SOURCES board.cpp ... [DEFINITIONS X=1 ...] [BIN])
#
# Per platform (msd, hasel, tendon): <PREFIX>-<p>-hil.elf with the simulated
# plant in the loop and <PREFIX>-<p>.elf with the port's rig HAL
# (rig_hal.hpp in the port folder), each checked for a linked heap; BIN also
# writes <image>.bin, the raw flash contents a programmer writes.
set(NLSOFT_CORTEX_M_DIR ${CMAKE_CURRENT_LIST_DIR})

get_filename_component(_root ${CMAKE_CURRENT_LIST_DIR}/../../.. ABSOLUTE)
set(NLSOFT_ROOT ${_root} CACHE PATH "the nlsoft repository")
set(NLSOFT_MODELS_DIR ${NLSOFT_ROOT}/app/models CACHE PATH "where <platform>.nlsm models are embedded from")
# A model added to (or removed from) the folder changes its mtime: reconfigure.
if(IS_DIRECTORY ${NLSOFT_MODELS_DIR})
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${NLSOFT_MODELS_DIR})
endif()
# The hasel image compiles the kernel of one network shape (platform_config.hpp):
# ours (36 -> 5 -> 5 -> 3, app/models/hasel.nlsm embedded) or the authors'
# published 36 -> 10 -> 5 -> 3, which embeds NLSOFT_M4_HASEL_MODEL if given
# (a `model import --platform hasel` of their .h5) and otherwise waits for an upload.
set(NLSOFT_M4_HASEL_SHAPE ours CACHE STRING "network shape of the hasel images: ours or authors")
set_property(CACHE NLSOFT_M4_HASEL_SHAPE PROPERTY STRINGS ours authors)
set(NLSOFT_M4_HASEL_MODEL "" CACHE FILEPATH "model file embedded in the hasel images built for the authors' shape")
if(NOT NLSOFT_M4_HASEL_SHAPE MATCHES "^(ours|authors)$")
  message(FATAL_ERROR "NLSOFT_M4_HASEL_SHAPE is '${NLSOFT_M4_HASEL_SHAPE}': ours or authors")
endif()
# -O2 vs -Os measured with firmware/tools/m4-report (ports/mps2-an386/README.md).
set(NLSOFT_M4_OPT -Os CACHE STRING "optimisation flag of the images")

find_program(NLSOFT_ARM_NM arm-none-eabi-nm REQUIRED)
find_program(NLSOFT_ARM_SIZE arm-none-eabi-size REQUIRED)
find_program(NLSOFT_ARM_OBJCOPY arm-none-eabi-objcopy REQUIRED)

# The host build's warnings list, the one list (cmake/warning_flags.txt).
file(STRINGS ${NLSOFT_ROOT}/cmake/warning_flags.txt NLSOFT_WARNING_FLAGS REGEX "^-")

function(nlsoft_cortex_m_images)
  cmake_parse_arguments(A "BIN" "PREFIX;NAME;LINKER_SCRIPT" "BOARD_SOURCES;DEFINITIONS" ${ARGN})
  set(cpu -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard)
  add_library(m4_flags INTERFACE)
  target_compile_options(m4_flags INTERFACE ${cpu} ${NLSOFT_M4_OPT} -g -ffunction-sections -fdata-sections
    $<$<COMPILE_LANGUAGE:CXX>:-std=c++17 -fno-exceptions -fno-rtti -fno-threadsafe-statics -fno-use-cxa-atexit
      ${NLSOFT_WARNING_FLAGS}>)
  target_include_directories(m4_flags INTERFACE ${NLSOFT_ROOT})
  target_compile_definitions(m4_flags INTERFACE ${A_DEFINITIONS})
  # newlib objects lack .note.GNU-stack; an execstack note means nothing on an MPU-less image.
  target_link_options(m4_flags INTERFACE ${cpu} -nostartfiles --specs=nano.specs -Wl,--gc-sections
    -Wl,--no-warn-execstack -L${NLSOFT_CORTEX_M_DIR} -L${CMAKE_CURRENT_BINARY_DIR} -T${A_LINKER_SCRIPT})

  # Reset, SysTick and the board's drivers: the same for every image. Objects,
  # not an archive: nothing calls into the vector table, so an archive member
  # holding it would never be pulled into the link.
  add_library(m4_board OBJECT ${NLSOFT_CORTEX_M_DIR}/reset.cpp ${NLSOFT_CORTEX_M_DIR}/systick.cpp
    ${A_BOARD_SOURCES})
  target_link_libraries(m4_board PUBLIC m4_flags)

  set(images "")
  foreach(platform msd hasel tendon)
    string(TOUPPER ${platform} P)
    set(model ${NLSOFT_MODELS_DIR}/${platform}.nlsm)
    set(shape_definitions "")
    if(platform STREQUAL "hasel" AND NLSOFT_M4_HASEL_SHAPE STREQUAL "authors")
      set(model "${NLSOFT_M4_HASEL_MODEL}")
      set(shape_definitions NLSOFT_HASEL_AUTHORS_SHAPE)
    endif()
    foreach(hil 1 0)
      set(name ${A_PREFIX}-${platform})
      set(id ${A_NAME})
      if(hil)
        set(name ${name}-hil)
        set(id ${id}-hil)
      endif()
      set(sources ${NLSOFT_CORTEX_M_DIR}/main.cpp)
      set(have_model 0)
      # The shipped model is embedded when it exists; without it the image waits
      # for an upload.
      if(model AND EXISTS ${model})
        list(APPEND sources ${NLSOFT_CORTEX_M_DIR}/model_blob.S)
        set(have_model 1)
      endif()
      add_executable(${name} ${sources})
      set_target_properties(${name} PROPERTIES SUFFIX .elf)
      target_link_libraries(${name} PRIVATE m4_board m4_flags)
      target_include_directories(${name} PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})  # the port's rig_hal.hpp
      target_link_options(${name} PRIVATE -Wl,-Map=$<TARGET_FILE_DIR:${name}>/${name}.map)
      target_compile_definitions(${name} PRIVATE NLSOFT_PLATFORM_${P} NLSOFT_HIL=${hil}
        NLSOFT_FIRMWARE_NAME="${id}" NLSOFT_HAVE_MODEL=${have_model} ${shape_definitions})
      if(model AND EXISTS ${model})
        set_source_files_properties(${NLSOFT_CORTEX_M_DIR}/model_blob.S TARGET_DIRECTORY ${name}
          PROPERTIES OBJECT_DEPENDS ${model})
        target_compile_definitions(${name} PRIVATE NLSOFT_MODEL_FILE="${model}")
      endif()
      # The no-heap check is a build step: a stamp only appears when it passes,
      # so a failing image fails every build until fixed.
      set(stamp ${CMAKE_CURRENT_BINARY_DIR}/${name}.noheap)
      set(bin_command "")
      if(A_BIN)
        set(bin_command COMMAND ${NLSOFT_ARM_OBJCOPY} -O binary $<TARGET_FILE:${name}>
                                $<TARGET_FILE_DIR:${name}>/${name}.bin)
      endif()
      add_custom_command(OUTPUT ${stamp}
        COMMAND ${CMAKE_COMMAND} -DNM=${NLSOFT_ARM_NM} -DELF=$<TARGET_FILE:${name}> -DSTAMP=${stamp}
                -P ${NLSOFT_CORTEX_M_DIR}/check_no_heap.cmake
        COMMAND ${NLSOFT_ARM_SIZE} $<TARGET_FILE:${name}>
        ${bin_command}
        DEPENDS ${name} ${NLSOFT_CORTEX_M_DIR}/check_no_heap.cmake
        VERBATIM)
      list(APPEND images ${stamp})
    endforeach()
  endforeach()
  add_custom_target(nlsoft-m4-checks ALL DEPENDS ${images})
endfunction()
