# fq_proto: the wire protocol. Protobuf headers (fq.proto, generated into the build dir by
# Debian's protoc 3.21) and the chunked Draco frame codec.
fq_require_package(Protobuf DEBIAN_PKG "libprotobuf-dev protobuf-compiler")
find_package(Threads REQUIRED)

add_library(fq_proto STATIC
  ${CMAKE_CURRENT_LIST_DIR}/fq.proto
  ${CMAKE_CURRENT_LIST_DIR}/header_codec.cpp
  ${CMAKE_CURRENT_LIST_DIR}/param_wire.cpp
  ${CMAKE_CURRENT_LIST_DIR}/frame_split.cpp
  ${CMAKE_CURRENT_LIST_DIR}/frame_chunk.cpp
  ${CMAKE_CURRENT_LIST_DIR}/draco_sequential.cpp
  ${CMAKE_CURRENT_LIST_DIR}/draco_sequential_read.cpp
  ${CMAKE_CURRENT_LIST_DIR}/vertex_id_runs.cpp
  ${CMAKE_CURRENT_LIST_DIR}/frame_encode.cpp
  ${CMAKE_CURRENT_LIST_DIR}/frame_decode.cpp
  ${CMAKE_CURRENT_LIST_DIR}/draco_budget.cpp
  ${CMAKE_CURRENT_LIST_DIR}/position_chunks.cpp)

# The quantizer and the dequantizer must round as Draco's do (a multiply, then an add): no
# fused multiply-add, whatever -march a build adds. Quantization is inlined where chunks are written.
set_source_files_properties(
  ${CMAKE_CURRENT_LIST_DIR}/frame_chunk.cpp ${CMAKE_CURRENT_LIST_DIR}/draco_sequential.cpp
  ${CMAKE_CURRENT_LIST_DIR}/draco_sequential_read.cpp
  PROPERTIES COMPILE_OPTIONS "-ffp-contract=off")

# Generated fq.pb.h / fq.pb.cc land in <build>/generated/proto (never in the source tree).
set(FQ_PROTO_GEN_DIR "${PROJECT_BINARY_DIR}/generated/proto")
file(MAKE_DIRECTORY "${FQ_PROTO_GEN_DIR}")
protobuf_generate(TARGET fq_proto LANGUAGE cpp
  IMPORT_DIRS "${CMAKE_CURRENT_LIST_DIR}"
  PROTOC_OUT_DIR "${FQ_PROTO_GEN_DIR}")

target_link_libraries(fq_proto
  PUBLIC fq_kernels fq_options protobuf::libprotobuf draco::draco
  PRIVATE Threads::Threads)
