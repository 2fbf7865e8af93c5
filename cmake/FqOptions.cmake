# Interface target carrying the language standard and warnings for every fq target.
add_library(fq_options INTERFACE)
target_compile_features(fq_options INTERFACE cxx_std_20)
target_compile_options(fq_options INTERFACE
  $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wpedantic>
  $<$<AND:$<COMPILE_LANGUAGE:CXX>,$<BOOL:${FQ_WARNINGS_AS_ERRORS}>>:-Werror>)
if(NOT CMAKE_BUILD_TYPE AND NOT CMAKE_CONFIGURATION_TYPES)
  set(CMAKE_BUILD_TYPE Release CACHE STRING "Build type" FORCE)
endif()
