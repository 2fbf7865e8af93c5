#include "tests/wire/wire_test_meshes.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "wire/draco_budget.h"

namespace fq::test_wire {

Mesh make_bumpy_grid(int nx, int ny) {
  Mesh m;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      m.positions.insert(m.positions.end(),
                         {0.1f * i, 0.1f * j, 0.05f * std::sin(0.7f * i) * std::cos(0.5f * j)});
    }
  }
  const auto idx = [&](int i, int j) { return static_cast<uint32_t>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      m.triangles.insert(m.triangles.end(), {idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)});
      m.triangles.insert(m.triangles.end(), {idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)});
    }
  }
  return m;
}

Mesh make_soup(const Mesh& m) {
  Mesh s;
  for (uint32_t v : m.triangles) {
    s.positions.insert(s.positions.end(), m.positions.begin() + 3 * v, m.positions.begin() + 3 * v + 3);
    s.triangles.push_back(static_cast<uint32_t>(s.triangles.size()));
  }
  return s;
}

namespace {

/// Reads the header of a binary little-endian PLY; returns vertex and face counts.
bool read_ply_header(std::istream& in, size_t& nv, size_t& nf) {
  std::string line;
  if (!std::getline(in, line) || line.rfind("ply", 0) != 0) return false;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string a, b;
    ls >> a >> b;
    if (a == "format" && b != "binary_little_endian") return false;
    if (a == "element" && b == "vertex") ls >> nv;
    if (a == "element" && b == "face") ls >> nf;
    if (a == "end_header") return true;
  }
  return false;
}

}  // namespace

std::optional<Mesh> load_shared_mesh(const std::string& file_name) {
  const char* env = std::getenv("FQ_MESH_DIR");
  const std::filesystem::path dir = (env && *env) ? env : FQ_DEFAULT_MESH_DIR;
  std::ifstream in(dir / file_name, std::ios::binary);
  size_t nv = 0, nf = 0;
  if (!in || !read_ply_header(in, nv, nf)) return std::nullopt;
  Mesh m;
  m.positions.resize(3 * nv);
  in.read(reinterpret_cast<char*>(m.positions.data()), std::streamsize(m.positions.size() * sizeof(float)));
  m.triangles.resize(3 * nf);
  for (size_t f = 0; f < nf && in; ++f) {
    unsigned char n = 0;
    in.read(reinterpret_cast<char*>(&n), 1);
    if (n != 3) return std::nullopt;
    in.read(reinterpret_cast<char*>(&m.triangles[3 * f]), 3 * sizeof(uint32_t));
  }
  if (!in) return std::nullopt;
  return m;
}

std::vector<std::array<uint32_t, 3>> triangle_set(const std::vector<uint32_t>& triangles) {
  std::vector<std::array<uint32_t, 3>> out;
  for (size_t t = 0; t + 2 < triangles.size(); t += 3) {
    std::array<uint32_t, 3> f{triangles[t], triangles[t + 1], triangles[t + 2]};
    std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
    out.push_back(f);
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace fq::test_wire

namespace fq::test_wire {
namespace {

std::string varint(uint64_t v) {
  std::string out;
  do {
    uint8_t b = v & 0x7f;
    v >>= 7;
    out.push_back(static_cast<char>(v ? (b | 0x80) : b));
  } while (v);
  return out;
}

}  // namespace

std::string forge_face_count(const std::string& chunk, uint64_t faces) {
  const StatusOr<wire::ChunkCounts> c = wire::read_chunk_counts(chunk);
  if (!c.ok()) return chunk;
  // Rewrite each place that holds the face count as a varint until the header reads back
  // the forged count: that place is the field, whichever coder wrote the chunk.
  const std::string old = varint(c->faces);
  for (size_t at = chunk.find(old, 11); at != std::string::npos; at = chunk.find(old, at + 1)) {
    std::string forged = chunk.substr(0, at) + varint(faces) + chunk.substr(at + old.size());
    const StatusOr<wire::ChunkCounts> f = wire::read_chunk_counts(forged);
    if (f.ok() && f->faces == faces && f->points == c->points) return forged;
  }
  return chunk;
}

}  // namespace fq::test_wire
