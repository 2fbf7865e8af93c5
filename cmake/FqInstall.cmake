# Install rules: the tools, the libraries with their headers, a CMake package (find_package(fq)
# gives fq::kernels, fq::io, fq::eval, fq::wire, with fq::core and fq::common under them; its
# component client gives fq::client), pkg-config files (fq.pc: everything; fq-wire.pc: the wire
# format alone, without the engines; fq-client.pc: the client library) and fq.proto.
#
# Headers go to <prefix>/include/fq/<folder>/, so the installed targets carry include/fq (the
# root-relative "kernels/engine.h" of the source tree keeps working) and include (for
# <fq/kernels/engine.h>).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(FQ_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/fq")
set(FQ_INSTALL_INCLUDEDIR "${CMAKE_INSTALL_INCLUDEDIR}/fq")

target_include_directories(fq_options INTERFACE
  "$<INSTALL_INTERFACE:${FQ_INSTALL_INCLUDEDIR}>"
  "$<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>")

set(fq_installed_libraries fq_common fq_core fq_kernels fq_eval fq_io fq_wire)
foreach(lib ${fq_installed_libraries})
  string(REPLACE "fq_" "" short "${lib}")
  set_target_properties(${lib} PROPERTIES EXPORT_NAME ${short})
endforeach()
set_target_properties(fq_options PROPERTIES EXPORT_NAME options)

install(TARGETS fq_options ${fq_installed_libraries} EXPORT fqTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS ${FQ_TOOLS} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

# Public headers, folder by folder (kernels/cuda/ holds device code only and stays private).
foreach(folder common core kernels eval io wire)
  install(DIRECTORY "${PROJECT_SOURCE_DIR}/${folder}/" DESTINATION "${FQ_INSTALL_INCLUDEDIR}/${folder}"
    FILES_MATCHING PATTERN "*.h" PATTERN "cuda" EXCLUDE)
endforeach()
install(DIRECTORY "${PROJECT_BINARY_DIR}/generated/" DESTINATION "${FQ_INSTALL_INCLUDEDIR}"
  FILES_MATCHING PATTERN "*.h")

install(EXPORT fqTargets NAMESPACE fq:: DESTINATION "${FQ_INSTALL_CMAKEDIR}")

# The client component: fq::client (with fq::curve under it) in an export set of its own, read
# only when asked for (find_package(fq COMPONENTS client)), so that find_package(fq) alone does
# not need ZeroMQ. Its headers go to include/fq/clients/common/ ("clients/common/frame_sender.h").
set_target_properties(fq_client PROPERTIES EXPORT_NAME client)
set_target_properties(fq_curve PROPERTIES EXPORT_NAME curve)
install(TARGETS fq_client fq_curve EXPORT fqClientTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
get_target_property(fq_client_sources fq_client SOURCES)
list(FILTER fq_client_sources INCLUDE REGEX "\\.h$")
list(TRANSFORM fq_client_sources PREPEND "${PROJECT_SOURCE_DIR}/clients/common/")
install(FILES ${fq_client_sources} DESTINATION "${FQ_INSTALL_INCLUDEDIR}/clients/common")
install(EXPORT fqClientTargets NAMESPACE fq:: DESTINATION "${FQ_INSTALL_CMAKEDIR}")
# The protocol's schema, for clients in other languages (protoc --python_out ...).
install(FILES "${PROJECT_SOURCE_DIR}/wire/fq.proto" DESTINATION "${CMAKE_INSTALL_DATADIR}/fq")

set(FQ_CUDA_ROOT "")
if(FQ_WITH_CUDA)
  set(FQ_CUDA_ROOT "${CUDAToolkit_LIBRARY_ROOT}")
endif()
configure_package_config_file(cmake/fqConfig.cmake.in "${PROJECT_BINARY_DIR}/fqConfig.cmake"
  INSTALL_DESTINATION "${FQ_INSTALL_CMAKEDIR}")
# 0.x: a minor release may change the API, so only the same minor version is compatible.
write_basic_package_version_file("${PROJECT_BINARY_DIR}/fqConfigVersion.cmake"
  COMPATIBILITY SameMinorVersion)
install(FILES "${PROJECT_BINARY_DIR}/fqConfig.cmake" "${PROJECT_BINARY_DIR}/fqConfigVersion.cmake"
  DESTINATION "${FQ_INSTALL_CMAKEDIR}")

# pkg-config: the libraries are static, so Libs lists what they need too.
set(FQ_PC_CFLAGS "-std=c++20")
set(FQ_PC_LIBS "")
if(FQ_WITH_CUDA)
  string(APPEND FQ_PC_LIBS " -L${CUDAToolkit_LIBRARY_DIR} -lcudart_static -ldl -lrt")
endif()
file(RELATIVE_PATH FQ_PC_TO_PREFIX "/p/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/p")
configure_file(cmake/fq.pc.in "${PROJECT_BINARY_DIR}/fq.pc" @ONLY)
configure_file(cmake/fq-wire.pc.in "${PROJECT_BINARY_DIR}/fq-wire.pc" @ONLY)
configure_file(cmake/fq-client.pc.in "${PROJECT_BINARY_DIR}/fq-client.pc" @ONLY)
install(FILES "${PROJECT_BINARY_DIR}/fq.pc" "${PROJECT_BINARY_DIR}/fq-wire.pc"
  "${PROJECT_BINARY_DIR}/fq-client.pc" DESTINATION "${CMAKE_INSTALL_LIBDIR}/pkgconfig")
install(FILES "${PROJECT_SOURCE_DIR}/LICENSE" DESTINATION "${CMAKE_INSTALL_DATAROOTDIR}/doc/fq")
