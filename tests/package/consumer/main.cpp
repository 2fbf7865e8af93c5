// Reads a mesh, smooths it with the CPU engine and prints what it did. Uses both include
// styles the installed package supports.
#include <fq/kernels/engine.h>

#include <cmath>
#include <cstdio>

#include "common/version.h"
#include "io/mesh_io.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: fq_consumer MESH\n");
    return 2;
  }
  fq::Mesh mesh;
  if (fq::Status s = fq::io::read_mesh(argv[1], mesh); !s.ok()) {
    std::fprintf(stderr, "fq_consumer: %s\n", s.message().c_str());
    return 1;
  }
  fq::EngineOptions options;
  options.kind = fq::EngineKind::kCpu;
  options.threads = 1;
  fq::StatusOr<std::unique_ptr<fq::Engine>> made = fq::make_engine(options);
  if (!made.ok()) {
    std::fprintf(stderr, "fq_consumer: %s\n", made.status().message().c_str());
    return 1;
  }
  const std::unique_ptr<fq::Engine> engine = std::move(*made);
  fq::FrameResult result;
  if (fq::Status s = engine->process(mesh.view(), fq::Params{}, result); !s.ok()) {
    std::fprintf(stderr, "fq_consumer: %s\n", s.message().c_str());
    return 1;
  }
  double moved = 0.0;
  for (size_t i = 0; i < mesh.positions.size(); ++i)
    moved += std::abs(result.positions[i] - mesh.positions[i]);
  std::printf("fq %s, engine %s\nvertices %u\nmoved %g\n", fq::version_string(), engine->name().c_str(),
              mesh.num_vertices(), moved);
  return 0;
}
