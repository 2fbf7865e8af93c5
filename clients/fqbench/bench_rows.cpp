#include "clients/fqbench/bench_rows.h"

#include <sstream>

namespace fq::bench {

namespace {

BenchRow filter_row(std::string id, std::string file, std::string paper_row, double paper_ms, float sigma_s,
                    float sigma_r) {
  BenchRow r{std::move(id), std::move(file), std::move(paper_row), paper_ms, {}};
  r.params.filtering.sigma_s = sigma_s;
  r.params.filtering.sigma_r = sigma_r;
  return r;
}

BenchRow cluster_row(std::string id, std::string file, std::string paper_row, double paper_ms, float sigma_s,
                     float sigma_r, float sigma_d, float sigma_q, float theta) {
  BenchRow r = filter_row(std::move(id), std::move(file), std::move(paper_row), paper_ms, sigma_s, sigma_r);
  r.params.cluster = true;
  r.params.clustering.sigma_d = sigma_d;
  r.params.clustering.sigma_q = sigma_q;
  r.params.clustering.theta = theta;
  return r;
}

BenchRow bilateral(BenchRow r) {
  r.params.filtering.method = FilterMethod::kBilateral;
  return r;
}

}  // namespace

std::vector<BenchRow> paper_rows() {
  return {
      // Table 2: filtering (QF), milliseconds on the paper's GTX 980 Ti.
      filter_row("f-bunny", "bunny.ply", "T2 Bunny 70K", 68, 5.f, 2.f),
      filter_row("f-igea", "igea.ply", "T2 Igea 200K", 81, 3.f, 0.4f),
      bilateral(filter_row("f-bunny-bf", "bunny.ply", "T2 Bunny 70K, BF", 51, 5.f, 2.f)),
      bilateral(filter_row("f-igea-bf", "igea.ply", "T2 Igea 200K, BF", 56, 3.f, 0.4f)),
      filter_row("f-dragon-grog", "dragon.ply", "T2 Grog 1M", 459, 4.f, 0.4f),
      filter_row("f-dragon", "dragon.ply", "T2 Dragon 7M params (mesh 0.87M)", 0, 5.5f, 1.f),
      filter_row("f-armadillo16", "armadillo_x16.drc", "T2 Raptor 2M", 849, 4.f, 0.7f),
      filter_row("f-armadillo16-garg", "armadillo_x16.drc", "T2 Gargoyle 1.7M", 1106, 5.f, 1.5f),
      filter_row("f-igea16", "igea_x16.drc", "T2 Raptor params (mesh 4.3M)", 0, 4.f, 0.7f),
      // Table 3: filtering + clustering.
      cluster_row("c-bunny", "bunny.ply", "T3 Bunny 70K", 161, 3.f, 1.f, 5.f, 0.8f, 0.9f),
      cluster_row("c-igea", "igea.ply", "T3 Igea 200K", 419, 2.f, 1.f, 6.f, 1.f, 0.87f),
      cluster_row("c-dragon-050", "dragon.ply", "T3 Grog 1M th 0.5", 1676, 2.f, 1.f, 6.f, 1.f, 0.5f),
      cluster_row("c-dragon-075", "dragon.ply", "T3 Grog 1M th 0.75", 1883, 2.f, 1.f, 6.f, 1.f, 0.75f),
      cluster_row("c-dragon-099", "dragon.ply", "T3 Grog 1M th 0.99", 2864, 2.f, 1.f, 6.f, 1.f, 0.99f),
      cluster_row("c-armadillo16", "armadillo_x16.drc", "T3 Gargoyle 1.7M", 3928, 3.f, 1.f, 6.f, 1.f, 0.95f),
      cluster_row("c-igea16", "igea_x16.drc", "T3 Raptor 2M params (mesh 4.3M)", 0, 3.f, 1.f, 4.f, 1.f,
                  0.95f),
  };
}

std::vector<BenchRow> select_rows(const std::string& ids, std::string& unknown) {
  const std::vector<BenchRow> all = paper_rows();
  if (ids == "all") return all;
  std::vector<BenchRow> out;
  std::stringstream ss(ids);
  std::string id;
  while (std::getline(ss, id, ',')) {
    bool found = false;
    for (const BenchRow& r : all) {
      if (r.id == id) {
        out.push_back(r);
        found = true;
      }
    }
    if (!found) unknown += (unknown.empty() ? "" : ",") + id;
  }
  return out;
}

}  // namespace fq::bench
