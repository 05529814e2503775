# One warnings list (cmake/warning_flags.txt) for every host target, set for
# the whole tree so no target can be added without it.
file(STRINGS ${CMAKE_CURRENT_LIST_DIR}/warning_flags.txt NLSOFT_WARNING_FLAGS REGEX "^-")
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${CMAKE_CURRENT_LIST_DIR}/warning_flags.txt)
add_compile_options(${NLSOFT_WARNING_FLAGS})

# CI builds fail on any warning (.ci/run through cmake/dev). Off by default
# so a newer compiler's new warning never stops someone building the demo.
option(NLSOFT_WERROR "Treat warnings as errors (CI)" OFF)
if(NLSOFT_WERROR)
  add_compile_options(-Werror)
endif()

# Sanitizer builds (CI: `bash cmake/dev sanitize`): NLSOFT_SANITIZE is
# "address,undefined" or "thread" (TSan cannot share a process with ASan).
# Set at directory scope, like the warnings, so no host target is left
# uninstrumented (an instrumented object linked without the runtime fails
# to link). The Cortex-M4F images are
# a separate configure (ExternalProject) and stay uninstrumented.
set(NLSOFT_SANITIZE "" CACHE STRING "Sanitizers for every host target: address,undefined | thread | empty")
if(NLSOFT_SANITIZE)
  set(_san_known address undefined thread)
  string(REPLACE "," ";" _san_list "${NLSOFT_SANITIZE}")
  foreach(_s IN LISTS _san_list)
    if(NOT _s IN_LIST _san_known)
      message(FATAL_ERROR "NLSOFT_SANITIZE: unknown sanitizer '${_s}' (use address,undefined or thread)")
    endif()
  endforeach()
  if("thread" IN_LIST _san_list AND "address" IN_LIST _san_list)
    message(FATAL_ERROR "NLSOFT_SANITIZE: thread and address cannot be combined; build twice")
  endif()
  set(_san_flags -fsanitize=${NLSOFT_SANITIZE} -fno-omit-frame-pointer)
  # A UBSan finding must fail the test that triggered it, not scroll by.
  if("undefined" IN_LIST _san_list)
    list(APPEND _san_flags -fno-sanitize-recover=all)
    # UBSan's vptr check needs the typeinfo of every polymorphic class, and
    # the MCU side is built without RTTI (the sensor drivers are a library
    # of it that tests link against): the check could not link there.
    list(APPEND _san_flags -fno-sanitize=vptr)
  endif()
  # GCC warns that TSan does not model atomic_thread_fence, which
  # Boost.Asio's handler dispatch uses; the warning is about a system header
  # and would stop every -Werror TSan build.
  if("thread" IN_LIST _san_list AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    add_compile_options(-Wno-tsan)
  endif()
  # The instrumentation hides initialisation from GCC's flow analysis:
  # -Wmaybe-uninitialized then fires inside libstdc++ (std::regex's
  # std::function). The uninstrumented -Werror build keeps the warning.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    add_compile_options(-Wno-maybe-uninitialized)
  endif()
  add_compile_options(${_san_flags})
  add_link_options(${_san_flags})
  message(STATUS "nlsoft: sanitizers ${NLSOFT_SANITIZE} on every host target")
endif()

# The MCU side (shared/, protocol/, firmware/ core) must build without
# exceptions or RTTI; host targets that hold MCU code use this too.
add_library(nlsoft_embedded_flags INTERFACE)
target_compile_options(nlsoft_embedded_flags INTERFACE
  $<$<COMPILE_LANGUAGE:CXX>:-fno-exceptions -fno-rtti>)
