# fq_meshio: mesh files in (PLY/OBJ/STL/DRC through Draco) and out (our PLY writer, Draco .drc).
# Included from proto/CMakeLists.txt, so source paths are relative to proto/.
add_library(fq_meshio STATIC cluster_colors.cpp draco_reader.cpp drc_writer.cpp mesh_io.cpp
  ply_extent_check.cpp ply_reader.cpp ply_writer.cpp)
target_link_libraries(fq_meshio PUBLIC fq_kernels fq_options PRIVATE draco::draco)
