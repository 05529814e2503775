# Compiles the controller for Cortex-M4F and fails if the object references
# any allocation function.
file(MAKE_DIRECTORY ${OUT})
file(STRINGS ${ROOT}/cmake/warning_flags.txt warnings REGEX "^-")
execute_process(
  COMMAND ${GXX} -std=c++17 -Os -mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard
          -fno-exceptions -fno-rtti ${warnings} -Werror -I${ROOT} -c ${SRC} -o ${OUT}/controller.o
  RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "Cortex-M4F compile failed:\n${err}")
endif()
execute_process(COMMAND ${NM} -u ${OUT}/controller.o OUTPUT_VARIABLE undefined)
foreach(sym malloc calloc realloc free _Znwj _Znaj _ZdlPv _ZdaPv __cxa_throw __cxa_allocate_exception)
  string(REGEX MATCH "[ \t]${sym}\n" hit "${undefined}\n")
  if(hit)
    message(FATAL_ERROR "Cortex-M4F object references ${sym}:\n${undefined}")
  endif()
endforeach()
message(STATUS "Cortex-M4F object is heap-free; undefined symbols:\n${undefined}")
