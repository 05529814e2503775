# Compiles codegen_m4.cpp for Cortex-M4F with the generated headers.
file(STRINGS ${ROOT}/cmake/warning_flags.txt warnings REGEX "^-")
execute_process(
  COMMAND ${GXX} -std=c++17 -Os -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard
          -fno-exceptions -fno-rtti ${warnings} -Werror -I${ROOT} -I${GEN} -c ${SRC} -o ${GEN}/codegen_m4.o
  RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "Cortex-M4F compile of the generated model failed:\n${err}")
endif()
