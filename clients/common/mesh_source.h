// Frames for a producer: one mesh file, or a folder of them played as a sequence, looped,
// optionally with fresh Gaussian noise per frame (a live noisy capture).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/status.h"
#include "core/mesh_view.h"

namespace fq::client {

class MeshSource {
 public:
  /// Reads `path`: a mesh file, or every readable mesh file of a folder in name order.
  Status open(const std::string& path);

  size_t size() const { return meshes_.size(); }
  const std::string& name(uint64_t frame) const { return names_[frame % names_.size()]; }
  const Mesh& mesh(uint64_t frame) const { return meshes_[frame % meshes_.size()]; }

  /// Frame `frame` of the loop: the mesh itself, or (noise > 0) a copy in `scratch` with
  /// noise of `noise` mean edges drawn from seed + frame.
  const Mesh& frame(uint64_t frame, double noise, uint64_t seed, Mesh& scratch) const;

 private:
  std::vector<std::string> names_;
  std::vector<Mesh> meshes_;
};

}  // namespace fq::client
