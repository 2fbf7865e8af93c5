# fq_require_package(<name> DEBIAN_PKG "<package> [...]" [CONFIG] [COMPONENTS <c>...])
# find_package that stops the configure with the Debian package to install, instead of a
# long CMake search report or (for optional finds) a build that silently lacks a part.
# A macro, not a function: find_package's result variables must reach the caller.
macro(fq_require_package fq_req_name)
  cmake_parse_arguments(FQ_REQ "CONFIG" "DEBIAN_PKG" "COMPONENTS" ${ARGN})
  if(NOT FQ_REQ_DEBIAN_PKG)
    message(FATAL_ERROR "fq_require_package(${fq_req_name}): DEBIAN_PKG is required")
  endif()
  set(fq_req_args QUIET)
  if(FQ_REQ_CONFIG)
    list(APPEND fq_req_args CONFIG)
  endif()
  if(FQ_REQ_COMPONENTS)
    list(APPEND fq_req_args COMPONENTS ${FQ_REQ_COMPONENTS})
  endif()
  find_package(${fq_req_name} ${fq_req_args})
  if(NOT ${fq_req_name}_FOUND)
    message(FATAL_ERROR "fq needs ${fq_req_name}: install the Debian package(s) ${FQ_REQ_DEBIAN_PKG} "
                        "(bash scripts/setup-deps.sh installs every dependency)")
  endif()
endmacro()
