// The paper's parameter rows (Tables 2 and 3) mapped onto the shared meshes of similar
// size, with the paper's time beside each.
#pragma once

#include <string>
#include <vector>

#include "core/params.h"

namespace fq::bench {

struct BenchRow {
  std::string id;         ///< short name used by --rows
  std::string file;       ///< mesh file in the mesh folder
  std::string paper_row;  ///< which row of the paper it stands for (model, size)
  double paper_ms = 0.0;  ///< the paper's time on a GTX 980 Ti; 0 = no comparable row
  Params params;
};

/// Every row fqbench knows, Table 2 (filter) first, then Table 3 (filter + clustering).
std::vector<BenchRow> paper_rows();

/// Rows whose id is in the comma-separated `ids` ("all" = every row); unknown ids are
/// returned in `unknown`.
std::vector<BenchRow> select_rows(const std::string& ids, std::string& unknown);

}  // namespace fq::bench
