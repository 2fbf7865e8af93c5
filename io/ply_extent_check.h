// Bounds check of a binary PLY body before Draco's PlyReader sees it (internal to
// fq_io). Draco 1.5's reader copies binary element data without checking that the
// file holds it, so a truncated file or a header announcing too much makes it read past
// the end of the buffer (undefined behaviour, seen as garbage faces or a crash).
#pragma once

#include <string>
#include <vector>

#include "common/status.h"

namespace fq::io {

/// For `format binary_little_endian` files: walks the header's elements and properties
/// (reading only the list counts) and fails with a clear message when the body is shorter
/// than the header requires or an element count exceeds 2^31 - 1 (Draco's limit). Other
/// formats and headers this check does not understand pass; Draco reports those itself.
Status check_binary_ply_extent(const std::string& path, const std::vector<char>& bytes);

}  // namespace fq::io
