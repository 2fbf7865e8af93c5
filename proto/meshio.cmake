# fq_meshio: mesh files in (PLY/OBJ/STL/DRC through Draco, ASCII STL through assimp) and out
# (our PLY writer, Draco .drc, OBJ and glb through assimp).
find_package(assimp CONFIG REQUIRED)
add_library(fq_meshio STATIC
  ${CMAKE_CURRENT_LIST_DIR}/assimp_io.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mesh_attributes.cpp
  ${CMAKE_CURRENT_LIST_DIR}/cluster_colors.cpp
  ${CMAKE_CURRENT_LIST_DIR}/draco_reader.cpp
  ${CMAKE_CURRENT_LIST_DIR}/drc_writer.cpp
  ${CMAKE_CURRENT_LIST_DIR}/mesh_io.cpp
  ${CMAKE_CURRENT_LIST_DIR}/ply_extent_check.cpp
  ${CMAKE_CURRENT_LIST_DIR}/ply_reader.cpp
  ${CMAKE_CURRENT_LIST_DIR}/ply_writer.cpp)
target_link_libraries(fq_meshio PUBLIC fq_kernels fq_options PRIVATE draco::draco assimp::assimp)
