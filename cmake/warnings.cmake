# Flags shared by every nlsoft target.
add_library(nlsoft_warnings INTERFACE)
target_compile_options(nlsoft_warnings INTERFACE
  -Wall -Wextra -Wshadow -Wconversion -Wno-sign-conversion -Wdouble-promotion)

# The MCU side (shared/, protocol/, firmware/ core) must build without
# exceptions or RTTI; host targets that hold MCU code use this too.
add_library(nlsoft_embedded_flags INTERFACE)
target_compile_options(nlsoft_embedded_flags INTERFACE
  $<$<COMPILE_LANGUAGE:CXX>:-fno-exceptions -fno-rtti>)
