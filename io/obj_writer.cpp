#include "io/obj_writer.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace fq::io {

namespace {

/// Writes floats in their shortest exact form: a round trip keeps every bit.
class Lines {
 public:
  void number(double v) {
    char text[32];
    const auto end = std::to_chars(text, text + sizeof text, float(v)).ptr;
    out_ += ' ';
    out_.append(text, end);
  }
  void text(std::string_view s) { out_ += s; }
  void index(uint64_t i) { out_ += std::to_string(i + 1); }  // OBJ counts from 1
  const std::string& str() const { return out_; }

 private:
  std::string out_;
};

/// Per-vertex properties as corner values (a corner takes its vertex's), so that one writer
/// serves both.
CornerValues from_vertices(const MeshView& mesh, const std::vector<const ElementProperty*>& props) {
  CornerValues c;
  c.components = int(props.size());
  c.values.resize(mesh.num_vertices * props.size());
  for (size_t v = 0; v < mesh.num_vertices; ++v)
    for (size_t k = 0; k < props.size(); ++k) c.values[v * props.size() + k] = float(props[k]->values[v]);
  c.corners.assign(mesh.triangles, mesh.triangles + 3 * size_t(mesh.num_triangles));
  return c;
}

void values(Lines& out, const char* tag, const CornerValues& c) {
  for (size_t i = 0; i < c.values.size(); i += size_t(c.components)) {
    out.text(tag);
    for (int k = 0; k < c.components; ++k) out.number(c.values[i + k]);
    out.text("\n");
  }
}

/// The library's path as seen from the output's folder (just its name when both are in one).
std::string library_reference(const std::string& library, const std::string& output) {
  namespace fs = std::filesystem;
  const fs::path folder = fs::absolute(output).parent_path();
  return fs::path(library).lexically_proximate(folder).generic_string();
}

void faces(Lines& out, const MeshView& mesh, const CornerValues& uv, const CornerValues& normal,
           const Materials& materials) {
  uint32_t current = UINT32_MAX;
  for (size_t t = 0; t < mesh.num_triangles; ++t) {
    if (!materials.empty() && materials.of_triangle[t] != current) {
      current = materials.of_triangle[t];
      out.text("usemtl " + materials.names[current] + "\n");
    }
    out.text("f");
    for (size_t c = 3 * t; c < 3 * t + 3; ++c) {
      out.text(" ");
      out.index(mesh.triangles[c]);
      if (!uv.empty() || !normal.empty()) out.text("/");
      if (!uv.empty()) out.index(uv.corners[c]);
      if (!normal.empty()) {
        out.text("/");
        out.index(normal.corners[c]);
      }
    }
    out.text("\n");
  }
}

}  // namespace

Status write_obj(const std::string& path, const MeshView& mesh, const uint32_t* labels,
                 const MeshAttributes* attributes, std::vector<std::string>& dropped) {
  const MeshAttributes none;
  const MeshAttributes& a = attributes ? *attributes : none;
  std::vector<std::string> used;
  CornerValues uv = a.corner_uv, normal = a.corner_normal;
  if (const auto vuv = a.vertex_uv(); uv.empty() && vuv[0]) {
    uv = from_vertices(mesh, {vuv[0], vuv[1]});
    used = {vuv[0]->name, vuv[1]->name};
  }
  const ElementProperty *nx = a.find_vertex("nx"), *ny = a.find_vertex("ny"), *nz = a.find_vertex("nz");
  if (normal.empty() && nx && ny && nz) {
    normal = from_vertices(mesh, {nx, ny, nz});
    used.insert(used.end(), {"nx", "ny", "nz"});
  }
  Lines out;
  out.text("# written by fq\n");
  if (!a.materials.library.empty()) out.text("mtllib " + library_reference(a.materials.library, path) + "\n");
  for (uint32_t v = 0; v < mesh.num_vertices; ++v) {
    out.text("v");
    for (int k = 0; k < 3; ++k) out.number(mesh.positions[3 * size_t(v) + k]);
    out.text("\n");
  }
  values(out, "vt", uv);
  values(out, "vn", normal);
  faces(out, mesh, uv, normal, a.materials);
  std::vector<std::string> lost;
  for (const ElementProperty& p : a.vertex)
    if (std::find(used.begin(), used.end(), p.name) == used.end()) lost.push_back(p.name);
  for (const std::string& phrase : group_property_names(lost)) dropped.push_back("vertex " + phrase);
  for (const ElementProperty& p : a.face) dropped.push_back("face property '" + p.name + "'");
  if (labels) dropped.emplace_back("cluster labels (OBJ has no per-vertex property for them)");
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) return io_error("cannot open '" + path + "' for writing: " + std::strerror(errno));
  f.write(out.str().data(), std::streamsize(out.str().size()));
  f.close();
  if (!f) return io_error("cannot write '" + path + "': write failed (disk full?)");
  return {};
}

}  // namespace fq::io
