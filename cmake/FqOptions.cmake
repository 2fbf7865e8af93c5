# Interface target carrying the language standard, warnings and the include roots for every
# fq target. Every include names its folder from the repository root ("kernels/engine.h",
# "wire/fq.pb.h"); generated headers mirror that layout under <build>/generated.
add_library(fq_options INTERFACE)
target_include_directories(fq_options INTERFACE
  "$<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>"
  "$<BUILD_INTERFACE:${PROJECT_BINARY_DIR}/generated>")
target_compile_features(fq_options INTERFACE cxx_std_20)
# Warnings are ours: the installed package does not impose them on its users.
target_compile_options(fq_options INTERFACE
  $<BUILD_INTERFACE:$<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wpedantic>>
  $<BUILD_INTERFACE:$<$<AND:$<COMPILE_LANGUAGE:CXX>,$<BOOL:${FQ_WARNINGS_AS_ERRORS}>>:-Werror>>
  # nvcc's front end takes every assignment of a [[nodiscard]] class (Status) for a dropped
  # value (its warning 2810); a Status really dropped is its warning 3004, which stays on.
  $<BUILD_INTERFACE:$<$<COMPILE_LANGUAGE:CUDA>:-diag-suppress=2810>>)
if(NOT CMAKE_BUILD_TYPE AND NOT CMAKE_CONFIGURATION_TYPES)
  set(CMAKE_BUILD_TYPE Release CACHE STRING "Build type" FORCE)
endif()
