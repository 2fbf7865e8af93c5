# fq_meshio: mesh files in (PLY/OBJ/STL/DRC through Draco, ASCII STL through assimp) and out
# (our PLY and OBJ writers, Draco .drc, glb through assimp). Included from proto/CMakeLists.txt,
# so source paths are relative to proto/.
fq_require_package(assimp DEBIAN_PKG libassimp-dev CONFIG)
add_library(fq_meshio STATIC assimp_io.cpp mesh_attributes.cpp cluster_colors.cpp draco_reader.cpp drc_writer.cpp
  glb_writer.cpp mesh_io.cpp mtl_library.cpp obj_corners.cpp obj_writer.cpp ply_extent_check.cpp ply_reader.cpp ply_writer.cpp)
target_link_libraries(fq_meshio PUBLIC fq_kernels fq_options PRIVATE draco::draco assimp::assimp)
