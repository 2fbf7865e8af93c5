#include "python/numpy_mesh.h"

#include <algorithm>
#include <limits>
#include <string>

namespace fq::py {

namespace {

using FloatArray = pyb::array_t<float, pyb::array::c_style | pyb::array::forcecast>;
using IndexArray = pyb::array_t<int64_t, pyb::array::c_style | pyb::array::forcecast>;

[[noreturn]] void value_error(const std::string& message) { throw pyb::value_error(message); }

void check_n_by_3(const pyb::array& a, const char* name) {
  if (a.ndim() != 2 || a.shape(1) != 3)
    value_error(std::string(name) + " must have shape (n, 3), got " + std::string(pyb::str(a.attr("shape"))));
}

}  // namespace

std::vector<float> to_positions(const pyb::handle& vertices, const char* name) {
  const pyb::array any = pyb::array::ensure(vertices);
  if (!any) value_error(std::string(name) + " must be an array of shape (n, 3)");
  if (any.dtype().kind() != 'f' && any.dtype().kind() != 'i' && any.dtype().kind() != 'u')
    value_error(std::string(name) + " must hold numbers, got dtype " + std::string(pyb::str(any.dtype())));
  check_n_by_3(any, name);
  if (any.shape(0) > ssize_t(std::numeric_limits<uint32_t>::max()))
    value_error(std::string(name) + " has more than 2^32 - 1 vertices");
  const FloatArray v = FloatArray::ensure(any);
  return std::vector<float>(v.data(), v.data() + v.size());
}

Mesh to_mesh(const pyb::handle& vertices, const pyb::handle& faces) {
  Mesh mesh;
  mesh.positions = to_positions(vertices, "V");
  const pyb::array any = pyb::array::ensure(faces);
  if (!any || (any.dtype().kind() != 'i' && any.dtype().kind() != 'u'))
    value_error("F must be an integer array of shape (m, 3)");
  check_n_by_3(any, "F");
  const IndexArray f = IndexArray::ensure(any);
  const int64_t n = mesh.num_vertices();
  mesh.triangles.resize(size_t(f.size()));
  for (ssize_t i = 0; i < f.size(); ++i) {
    const int64_t v = f.data()[i];
    if (v < 0 || v >= n)
      value_error("F: triangle " + std::to_string(i / 3) + " references vertex " + std::to_string(v) +
                  " of " + std::to_string(n));
    mesh.triangles[size_t(i)] = static_cast<uint32_t>(v);
  }
  return mesh;
}

pyb::array positions_array(const std::vector<float>& positions, const pyb::handle& like) {
  const ssize_t n = ssize_t(positions.size() / 3);
  const pyb::array in = pyb::array::ensure(like);
  if (in && in.dtype().is(pyb::dtype::of<double>())) {
    pyb::array_t<double> out({n, ssize_t(3)});
    std::copy(positions.begin(), positions.end(), out.mutable_data());
    return out;
  }
  pyb::array_t<float> out({n, ssize_t(3)});
  std::copy(positions.begin(), positions.end(), out.mutable_data());
  return out;
}

pyb::array faces_array(const std::vector<uint32_t>& triangles) {
  pyb::array_t<int64_t> out({ssize_t(triangles.size() / 3), ssize_t(3)});
  std::copy(triangles.begin(), triangles.end(), out.mutable_data());
  return out;
}

pyb::array labels_array(const std::vector<uint32_t>& labels) {
  pyb::array_t<uint32_t> out(ssize_t(labels.size()));
  std::copy(labels.begin(), labels.end(), out.mutable_data());
  return out;
}

}  // namespace fq::py
