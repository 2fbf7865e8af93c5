# fq_meshio: mesh files in (PLY/OBJ/STL/DRC through Draco) and out (our PLY writer, Draco .drc).
add_library(fq_meshio STATIC
  ${CMAKE_CURRENT_LIST_DIR}/cluster_colors.cpp
  ${CMAKE_CURRENT_LIST_DIR}/draco_reader.cpp
  ${CMAKE_CURRENT_LIST_DIR}/drc_writer.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mesh_io.cpp
  ${CMAKE_CURRENT_LIST_DIR}/ply_extent_check.cpp
  ${CMAKE_CURRENT_LIST_DIR}/ply_reader.cpp
  ${CMAKE_CURRENT_LIST_DIR}/ply_writer.cpp)
target_link_libraries(fq_meshio PUBLIC fq_kernels fq_options PRIVATE draco::draco)
