# The images of an MPS2 FPGA board, for its core: QEMU maps the AN386's
# peripherals at the same addresses on the AN385 (Cortex-M3) and the AN500
# (Cortex-M7), so every MPS2 port builds this folder's board sources and
# rig HAL, with its core's flags and its linker script. Included by each
# MPS2 port's CMakeLists.txt after project():
#   nlsoft_mps2_images(PREFIX NAME LINKER_SCRIPT [CPU flags...])
set(NLSOFT_MPS2_DIR ${CMAKE_CURRENT_LIST_DIR})
include(${NLSOFT_MPS2_DIR}/../cortex-m/images.cmake)

function(nlsoft_mps2_images prefix name linker_script)
  nlsoft_cortex_m_images(PREFIX ${prefix} NAME ${name} ${ARGN}
    PORT_DIR ${NLSOFT_MPS2_DIR}
    LINKER_SCRIPT ${linker_script}
    BOARD_SOURCES ${NLSOFT_MPS2_DIR}/vectors.cpp ${NLSOFT_MPS2_DIR}/board.cpp ${NLSOFT_MPS2_DIR}/cmsdk_uart.cpp
                  ${NLSOFT_MPS2_DIR}/sbcon_i2c.cpp ${NLSOFT_MPS2_DIR}/pl022_spi.cpp)
endfunction()
