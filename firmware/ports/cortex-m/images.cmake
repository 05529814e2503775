# The images of a Cortex-M port, included by the port's own project
# (ports/mps2-an386, ports/mps2-an500, ports/stm32f4) after project():
#
#   nlsoft_cortex_m_images(PREFIX nlsoft-m4 NAME nlsoft-an386 LINKER_SCRIPT an386.ld
#                          BOARD_SOURCES board.cpp ... [DEFINITIONS X=1 ...] [BIN]
#                          [CPU -mcpu=... ...] [PORT_DIR dir])
#
# CPU: the core's flags (default the Cortex-M4F's, the toolchain file's
# NLSOFT_M4_CPU_FLAGS). PORT_DIR: the folder whose rig_hal.hpp the board
# image includes (default the calling project's own), so a port for another
# core on the same peripherals (mps2-an500) builds the same sources.
#
# One image per rig folder under NLSOFT_RIG_DIR: each holds the rig header
# nlsoft_rig.hpp and image.cmake, both generated from a rig file
# (`nlsoft-console firmware build --rig FILE`, or the host build for the
# shipped rigs, firmware/CMakeLists.txt). image.cmake names the rig
# (NLSOFT_IMAGE_RIG), the model file embedded (NLSOFT_IMAGE_MODEL, or none:
# the image waits for an upload), and which images the header is for: the
# board image (NLSOFT_IMAGE_BOARD: 0 when the rig's chips are on another
# board's buses) and the HIL one (NLSOFT_IMAGE_HIL: the rig has a simulated
# plant), with NLSOFT_IMAGE_NOTE saying why a board gets fewer. Per rig:
# <PREFIX>-<rig>.elf with the port's rig HAL (rig_hal.hpp in the port
# folder) and, with a plant, <PREFIX>-<rig>-hil.elf with the plant in the
# loop; each checked for a linked heap; BIN also
# writes <image>.bin, the raw flash contents a programmer writes.
# NLSOFT_IMAGE_KINDS (board, hil or both) narrows what is built.
set(NLSOFT_CORTEX_M_DIR ${CMAKE_CURRENT_LIST_DIR})

get_filename_component(_root ${CMAKE_CURRENT_LIST_DIR}/../../.. ABSOLUTE)
set(NLSOFT_ROOT ${_root} CACHE PATH "the nlsoft sources (firmware/, shared/, protocol/)")
set(NLSOFT_RIG_DIR "" CACHE PATH "a folder of rig folders, each with a generated nlsoft_rig.hpp and image.cmake")
set(NLSOFT_IMAGE_KINDS both CACHE STRING "which images per rig: board, hil or both")
if(NOT IS_DIRECTORY "${NLSOFT_RIG_DIR}")
  message(FATAL_ERROR "NLSOFT_RIG_DIR='${NLSOFT_RIG_DIR}' is not a folder of generated rig headers: build an image "
                      "with `nlsoft-console firmware build --rig FILE --board BOARD`, or the shipped ones with the "
                      "main build (bash cmake/dev build)")
endif()
# A rig that comes, goes or changes its image.cmake: reconfigure.
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${NLSOFT_RIG_DIR})
# -O2 vs -Os measured with firmware/tools/m4-report (ports/mps2-an386/README.md).
set(NLSOFT_M4_OPT -Os CACHE STRING "optimisation flag of the images")
find_program(NLSOFT_ARM_NM arm-none-eabi-nm REQUIRED)
find_program(NLSOFT_ARM_SIZE arm-none-eabi-size REQUIRED)
find_program(NLSOFT_ARM_OBJCOPY arm-none-eabi-objcopy REQUIRED)

# The host build's warnings list, the one list (cmake/warning_flags.txt).
file(STRINGS ${NLSOFT_ROOT}/cmake/warning_flags.txt NLSOFT_WARNING_FLAGS REGEX "^-")

# The no-heap check is a build step: a stamp only appears when it passes,
# so a failing image fails every build until fixed. Then the image's size,
# and with BIN its raw flash contents.
function(nlsoft_cortex_m_checks name bin out_stamp)
  set(stamp ${CMAKE_CURRENT_BINARY_DIR}/${name}.noheap)
  set(bin_command "")
  if(bin)
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
  set(${out_stamp} ${stamp} PARENT_SCOPE)
endfunction()

# A test-only image (tests/firmware/bus_probe/): the board's objects with a
# main of its own, no rig. Call after nlsoft_cortex_m_images().
function(nlsoft_cortex_m_test_image name)
  add_executable(${name} ${ARGN})
  set_target_properties(${name} PROPERTIES SUFFIX .elf)
  target_link_libraries(${name} PRIVATE m4_board m4_flags)
  target_link_options(${name} PRIVATE -Wl,-Map=$<TARGET_FILE_DIR:${name}>/${name}.map)
  nlsoft_cortex_m_checks(${name} "" stamp)
  add_custom_target(${name}-checks ALL DEPENDS ${stamp})
endfunction()

# One image: the rig header's folder first on the include path.
function(nlsoft_cortex_m_image prefix id rig model rig_dir hil bin out_stamp)
  set(name ${prefix}-${rig})
  if(hil)
    set(name ${name}-hil)
    set(id ${id}-hil)
  endif()
  set(sources ${NLSOFT_CORTEX_M_DIR}/main.cpp)
  set(have_model 0)
  # The model is embedded when it exists; without it the image waits for an upload.
  if(model AND EXISTS ${model})
    list(APPEND sources ${NLSOFT_CORTEX_M_DIR}/model_blob.S)
    set(have_model 1)
  endif()
  add_executable(${name} ${sources})
  set_target_properties(${name} PROPERTIES SUFFIX .elf)
  target_link_libraries(${name} PRIVATE m4_board m4_flags)
  # nlsoft_rig.hpp, then the port's rig_hal.hpp.
  target_include_directories(${name} BEFORE PRIVATE ${rig_dir})
  target_include_directories(${name} PRIVATE ${NLSOFT_PORT_DIR})
  target_link_options(${name} PRIVATE -Wl,-Map=$<TARGET_FILE_DIR:${name}>/${name}.map)
  target_compile_definitions(${name} PRIVATE NLSOFT_HIL=${hil} NLSOFT_FIRMWARE_NAME="${id}"
    NLSOFT_HAVE_MODEL=${have_model} ${NLSOFT_IMAGE_DEFINITIONS})
  if(have_model)
    # One source for every image of the folder: it depends on each model (the
    # compiler's dependency list does not name an .incbin file).
    set_property(SOURCE ${NLSOFT_CORTEX_M_DIR}/model_blob.S TARGET_DIRECTORY ${name}
      APPEND PROPERTY OBJECT_DEPENDS ${model})
    target_compile_definitions(${name} PRIVATE NLSOFT_MODEL_FILE="${model}")
  endif()
  nlsoft_cortex_m_checks(${name} "${bin}" stamp)
  set(${out_stamp} ${stamp} PARENT_SCOPE)
endfunction()

function(nlsoft_cortex_m_images)
  cmake_parse_arguments(A "BIN" "PREFIX;NAME;LINKER_SCRIPT;PORT_DIR" "BOARD_SOURCES;DEFINITIONS;CPU" ${ARGN})
  set(cpu ${NLSOFT_M4_CPU_FLAGS})
  if(A_CPU)
    set(cpu ${A_CPU})
  endif()
  if(NOT cpu)
    message(FATAL_ERROR "no CPU flags: give CPU, or configure with ports/cortex-m/cmake/arm-none-eabi.cmake")
  endif()
  # Read by nlsoft_cortex_m_image, called from here.
  set(NLSOFT_PORT_DIR ${CMAKE_CURRENT_SOURCE_DIR})
  if(A_PORT_DIR)
    set(NLSOFT_PORT_DIR ${A_PORT_DIR})
  endif()
  add_library(m4_flags INTERFACE)
  # -flto: the image is one program, so what one translation unit never
  # calls from another (and the copies of shared/'s inline functions) goes.
  target_compile_options(m4_flags INTERFACE ${cpu} ${NLSOFT_M4_OPT} -g -flto -ffunction-sections -fdata-sections -fno-tree-loop-distribute-patterns
    -fno-unwind-tables -fno-asynchronous-unwind-tables
    $<$<COMPILE_LANGUAGE:CXX>:-std=c++17 -fno-exceptions -fno-rtti -fno-threadsafe-statics -fno-use-cxa-atexit
      ${NLSOFT_WARNING_FLAGS}>)
  target_include_directories(m4_flags INTERFACE ${NLSOFT_ROOT})
  target_compile_definitions(m4_flags INTERFACE ${A_DEFINITIONS})
  # newlib objects lack .note.GNU-stack; an execstack note means nothing on an MPU-less image.
  # -flto=auto at the link: a larger image's LTO parts are compiled by the
  # build's jobs (plain -flto compiles them one by one and warns that it does).
  target_link_options(m4_flags INTERFACE ${cpu} ${NLSOFT_M4_OPT} -flto=auto -nostartfiles --specs=nano.specs -Wl,--gc-sections
    -Wl,--no-warn-execstack -L${NLSOFT_CORTEX_M_DIR} -L${CMAKE_CURRENT_BINARY_DIR} -T${A_LINKER_SCRIPT})

  # Reset, SysTick and the board's drivers: the same for every image. Objects,
  # not an archive: nothing calls into the vector table, so an archive member
  # holding it would never be pulled into the link.
  # The sensor chip drivers too: an image whose rig names no chip calls none
  # of them, and the link leaves them out.
  include(${NLSOFT_ROOT}/firmware/drivers/sources.cmake)
  list(TRANSFORM NLSOFT_DRIVER_SOURCES PREPEND ${NLSOFT_ROOT}/firmware/drivers/ OUTPUT_VARIABLE drivers)
  add_library(m4_board OBJECT ${NLSOFT_CORTEX_M_DIR}/reset.cpp ${NLSOFT_CORTEX_M_DIR}/systick.cpp
    ${A_BOARD_SOURCES} ${drivers})
  target_link_libraries(m4_board PUBLIC m4_flags)

  set(images "")
  file(GLOB rigs LIST_DIRECTORIES true ${NLSOFT_RIG_DIR}/*)
  foreach(rig_dir ${rigs})
    if(NOT EXISTS ${rig_dir}/image.cmake)
      continue()
    endif()
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${rig_dir}/image.cmake)
    # The images the header is for (NLSOFT_IMAGE_BOARD, NLSOFT_IMAGE_HIL), as
    # many of them as NLSOFT_IMAGE_KINDS asks; none left is an error.
    unset(NLSOFT_IMAGE_BOARD)
    set(NLSOFT_IMAGE_NOTE "")
    # The rig's own compile definitions (NLSOFT_SIZE_FIRST: [firmware] optimize = "size").
    set(NLSOFT_IMAGE_DEFINITIONS "")
    include(${rig_dir}/image.cmake)
    if(NOT DEFINED NLSOFT_IMAGE_BOARD)
      message(FATAL_ERROR "${rig_dir}/image.cmake does not say whether the header is for the board image "
                          "(NLSOFT_IMAGE_BOARD): an older generator wrote it; generate it again")
    endif()
    set(kinds "")
    if(NLSOFT_IMAGE_HIL AND NOT NLSOFT_IMAGE_KINDS STREQUAL "board")
      list(APPEND kinds 1)
    endif()
    if(NLSOFT_IMAGE_BOARD AND NOT NLSOFT_IMAGE_KINDS STREQUAL "hil")
      list(APPEND kinds 0)
    endif()
    if(kinds STREQUAL "")
      message(FATAL_ERROR "${rig_dir}/image.cmake: the header is for no ${NLSOFT_IMAGE_KINDS} image "
                          "(NLSOFT_IMAGE_BOARD ${NLSOFT_IMAGE_BOARD}, NLSOFT_IMAGE_HIL ${NLSOFT_IMAGE_HIL})")
    endif()
    if(NLSOFT_IMAGE_NOTE)
      message(STATUS "${NLSOFT_IMAGE_NOTE}")
    endif()
    foreach(hil ${kinds})
      nlsoft_cortex_m_image(${A_PREFIX} ${A_NAME} ${NLSOFT_IMAGE_RIG} "${NLSOFT_IMAGE_MODEL}" ${rig_dir} ${hil}
                            "${A_BIN}" stamp)
      list(APPEND images ${stamp})
    endforeach()
  endforeach()
  add_custom_target(nlsoft-m4-checks ALL DEPENDS ${images})
endfunction()
