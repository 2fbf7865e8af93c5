// The few statements of an OBJ material library (.mtl) that a glb can carry: each material's
// diffuse colour (Kd) and diffuse texture (map_Kd). Internal to fq_io. Why our own lines:
// assimp reads a .mtl only while importing the OBJ that names it, and Draco only reads its
// material names; fq keeps the library by reference and needs just these two statements.
#pragma once

#include <array>
#include <map>
#include <string>

namespace fq::io {

struct MtlMaterial {
  bool has_diffuse = false;
  std::array<float, 3> diffuse{1.f, 1.f, 1.f};  ///< Kd
  std::string texture;                          ///< map_Kd as an absolute path; empty: none
};

/// The materials of the library at `path` by name; empty when it cannot be read (an OBJ
/// whose library is missing still loads, as in every OBJ reader).
std::map<std::string, MtlMaterial> read_mtl(const std::string& path);

}  // namespace fq::io
