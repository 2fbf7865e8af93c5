#include "io/mtl_library.h"

#include <filesystem>
#include <fstream>
#include <sstream>

namespace fq::io {

std::map<std::string, MtlMaterial> read_mtl(const std::string& path) {
  std::map<std::string, MtlMaterial> out;
  std::ifstream f(path);
  MtlMaterial* current = nullptr;
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  for (std::string line; std::getline(f, line);) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "newmtl") {
      std::string name;
      std::getline(words >> std::ws, name);
      current = &out[name];
    } else if (current && key == "Kd") {
      auto& d = current->diffuse;
      current->has_diffuse = static_cast<bool>(words >> d[0] >> d[1] >> d[2]);
    } else if (current && key == "map_Kd") {
      // Options (-s, -o, ...) come before the file name, which is the last word.
      std::string word, file;
      while (words >> word) file = word;
      if (!file.empty()) current->texture = (folder / file).lexically_normal().string();
    }
  }
  return out;
}

}  // namespace fq::io
