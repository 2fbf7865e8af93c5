// A capture's frames to fqd: python/examples/producer.py in C++, with a torus (docs/PROTOCOL.md).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <thread>

#include "clients/common/frame_sender.h"

// A torus (ring radius 3, tube radius 1 + noise of sigma 0.03) into m: a 2n x n grid that wraps around.
void noisy_torus(uint32_t n, std::mt19937 random, fq::Mesh& m) {
  for (uint32_t a = 0; a < 2 * n * n; ++a) {
    const uint32_t i = a / n, j = a % n, b = (i + 1) % (2 * n) * n + j, next = (j + 1) % n;
    const float u = float(M_PI) * float(i) / float(n), v = 2 * float(M_PI) * float(j) / float(n);
    const float tube = std::normal_distribution<float>(1, 0.03f)(random), ring = 3 + tube * std::cos(v);
    m.positions.insert(m.positions.end(), {ring * std::cos(u), ring * std::sin(u), tube * std::sin(v)});
    m.triangles.insert(m.triangles.end(), {a, b, b - j + next, a, b - j + next, a - j + next});
  }
}

int main(int argc, char** argv) try {
  if (argc < 2) return std::fprintf(stderr, "usage: producer INGEST_ENDPOINT [FRAMES] [FPS]\n"), 2;
  zmq::context_t context;
  zmq::socket_t push(context, zmq::socket_type::push);
  push.set(zmq::sockopt::sndtimeo, 10000);  // a frame waits at most 10 s for fqd
  push.connect(argv[1]);
  for (int i = 0; i < (argc > 2 ? std::stoi(argv[2]) : 5); ++i) {
    fq::Mesh mesh;
    noisy_torus(48, std::mt19937(i), mesh);  // a new capture of the same surface
    std::vector<std::string> parts;
    if (fq::Status s = fq::client::build_frame(mesh.view(), {.stream_id = "cam"}, i, parts); !s.ok())
      throw std::runtime_error(s.message());
    if (!fq::client::send_parts(push, parts)) throw std::runtime_error("fqd took no frame within 10 s");
    std::printf("sent frame %d: %u vertices\n", i, mesh.num_vertices());
    std::this_thread::sleep_for(std::chrono::milliseconds(1000 / (argc > 3 ? std::stoi(argv[3]) : 5)));
  }
} catch (const std::exception& e) {  // also a bad endpoint (zmq::error_t) or number
  return std::fprintf(stderr, "producer: %s\n", e.what()), 1;
}
