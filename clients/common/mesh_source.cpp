#include "clients/common/mesh_source.h"

#include <algorithm>
#include <filesystem>

#include "eval/noise.h"
#include "io/mesh_io.h"

namespace fq::client {

Status MeshSource::open(const std::string& path) {
  namespace fs = std::filesystem;
  std::vector<std::string> files;
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    for (const auto& e : fs::directory_iterator(path, ec))
      if (e.is_regular_file() && io::is_readable_mesh_file(e.path().string()))
        files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    if (files.empty()) return invalid_argument("no mesh files (.ply .obj .stl .drc) in folder " + path);
  } else {
    files.push_back(path);
  }
  names_.clear();
  meshes_.clear();
  for (const std::string& f : files) {
    Mesh m;
    FQ_RETURN_IF_ERROR(io::read_mesh(f, m));
    names_.push_back(fs::path(f).filename().string());
    meshes_.push_back(std::move(m));
  }
  return {};
}

const Mesh& MeshSource::frame(uint64_t frame, double noise, uint64_t seed, Mesh& scratch) const {
  const Mesh& m = mesh(frame);
  if (!(noise > 0.0)) return m;
  scratch = m;
  add_gaussian_noise(scratch, noise, seed + frame);
  return scratch;
}

}  // namespace fq::client
