// ASCII STL through assimp (internal to fq_io; use read_mesh): Draco reads binary STL
// only. Assimp also writes our glb (glb_writer.h).
#pragma once

#include <cstdint>
#include <string>

#include "common/status.h"
#include "core/mesh_view.h"

namespace fq::io {

/// ASCII STL, welded like binary STL: one vertex per distinct position, in order of first use.
Status read_ascii_stl(const std::string& path, Mesh& out);

}  // namespace fq::io
