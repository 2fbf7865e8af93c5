// The compiled parts of fq.read_mesh, fq.write_mesh, fq.add_noise, fq.metrics and fq.scan_error (wrapped and
// documented in fq/_files.py and fq/_measures.py). File work and measures run without the GIL.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <filesystem>
#include <numbers>
#include <string>

#include "eval/error_metrics.h"
#include "eval/noise.h"
#include "eval/scan_error.h"
#include "eval/surface_distance.h"
#include "io/mesh_io.h"
#include "kernels/frame_prep.h"
#include "python/bindings.h"
#include "python/mesh_dict.h"
#include "python/numpy_mesh.h"
#include "python/py_errors.h"

namespace fq::py {

namespace {

namespace pyb = pybind11;
using namespace pybind11::literals;

std::string path_string(const pyb::handle& path) {
  return pyb::str(pyb::module_::import("os").attr("fspath")(path));
}

pyb::dict read_mesh(const pyb::handle& path_like) {
  const std::string path = path_string(path_like);
  if (!io::is_readable_mesh_file(path))
    throw pyb::value_error("cannot read '" + path + "': unsupported extension " +
                           io::expected_read_extensions());
  if (!std::filesystem::exists(path)) {
    PyErr_SetObject(PyExc_FileNotFoundError, pyb::make_tuple(2, "no such file", path).ptr());
    throw pyb::error_already_set();
  }
  Mesh mesh;
  io::MeshAttributes attributes;
  Status s;
  {
    const pyb::gil_scoped_release unlocked;
    s = io::read_mesh(path, mesh, &attributes);
  }
  throw_if_file_error(s);
  pyb::dict d = mesh_dict(mesh, attributes);
  d["dropped"] = pyb::cast(not_carried(attributes));
  return d;
}

/// Writes V, F, the labels and the attribute arrays of `arrays`; returns what the format
/// could not keep (one phrase a group).
std::vector<std::string> write_mesh(const pyb::handle& path_like, const pyb::handle& v, const pyb::handle& f,
                                    const std::optional<pyb::handle>& labels_like, const pyb::dict& arrays,
                                    int drc_bits) {
  const std::string path = path_string(path_like);
  if (!io::is_writable_mesh_file(path))
    throw pyb::value_error("cannot write '" + path + "': unsupported output extension '" +
                           io::lower_extension(path) + "' " + io::expected_write_extensions());
  const Mesh mesh = to_mesh(v, f);
  std::vector<uint32_t> labels;
  uint32_t num_clusters = 0;
  if (labels_like && !labels_like->is_none()) {
    const auto l = pyb::array_t<int64_t, pyb::array::c_style | pyb::array::forcecast>::ensure(*labels_like);
    if (!l || l.ndim() != 1 || l.shape(0) != ssize_t(mesh.num_vertices()))
      throw pyb::value_error("labels must be a 1-D integer array with one label per vertex");
    for (ssize_t i = 0; i < l.size(); ++i) {
      if (l.data()[i] < 0 || l.data()[i] > int64_t(UINT32_MAX - 1))
        throw pyb::value_error("labels: vertex " + std::to_string(i) + " has label " +
                               std::to_string(l.data()[i]));
      labels.push_back(uint32_t(l.data()[i]));
      num_clusters = std::max(num_clusters, labels.back() + 1);
    }
  }
  const io::MeshAttributes attributes = attributes_of(arrays, mesh.num_vertices(), mesh.num_triangles());
  io::WriteOptions options;
  options.drc_position_bits = drc_bits;
  options.attributes = &attributes;
  std::vector<std::string> dropped;
  Status s;
  {
    const pyb::gil_scoped_release unlocked;
    s = io::write_mesh(path, mesh.view(), labels.empty() ? nullptr : labels.data(), num_clusters, options,
                       &dropped);
  }
  throw_if_file_error(s);
  return dropped;
}

pyb::array add_noise(const pyb::handle& v, const pyb::handle& f, double sigma, uint64_t seed,
                     const std::string& kind, double length) {
  NoiseKind k;
  if (!parse_noise_kind(kind.c_str(), k))
    throw pyb::value_error("kind must be 'iso', 'normal', 'depth', 'correlated' or 'ripple', got '" + kind +
                           "'");
  Mesh mesh = to_mesh(v, f);
  {
    const pyb::gil_scoped_release unlocked;
    fq::add_noise(mesh, k, sigma, length, seed);
  }
  return positions_array(mesh.positions, v);
}

pyb::dict metrics(const pyb::handle& v_ref, const pyb::handle& f, const pyb::handle& v) {
  const Mesh reference = to_mesh(v_ref, f);
  const std::vector<float> candidate = to_positions(v, "V");
  if (candidate.size() != reference.positions.size())
    throw pyb::value_error("V has " + std::to_string(candidate.size() / 3) + " vertices but V_ref has " +
                           std::to_string(reference.num_vertices()));
  double rmse = 0;
  SurfaceDistance surface;
  MfneResult mfne;
  {
    const pyb::gil_scoped_release unlocked;
    rmse = rmse_over_diagonal(reference.view(), candidate.data());
    surface = distance_to_surface(reference.view(), candidate.data(), reference.num_vertices());
    mfne = mean_face_normal_error(reference.view(), candidate.data());
  }
  return pyb::dict(
      "rmse_over_diagonal"_a = rmse, "surface_rms_over_diagonal"_a = surface.rms_over_diagonal,
      "surface_max_over_diagonal"_a = surface.max_over_diagonal, "mfne_rad"_a = mfne.mean_radians,
      "mfne_deg"_a = mfne.mean_radians * 180.0 / std::numbers::pi, "faces_skipped"_a = mfne.faces_skipped);
}

pyb::dict scan_error(const pyb::handle& v_ref, const pyb::handle& f_ref, const pyb::handle& v_scan,
                     const pyb::handle& f_scan, const pyb::handle& v) {
  const Mesh reference = to_mesh(v_ref, f_ref);
  const Mesh scan = to_mesh(v_scan, f_scan);
  std::vector<float> moved;
  if (!v.is_none()) {
    moved = to_positions(v, "V");
    if (moved.size() != scan.positions.size())
      throw pyb::value_error("V has " + std::to_string(moved.size() / 3) + " vertices but V_scan has " +
                             std::to_string(scan.num_vertices()));
  }
  ScanError e;
  {
    const pyb::gil_scoped_release unlocked;
    const std::vector<uint8_t> over = faces_over_reference(reference.view(), scan.view());
    e = fq::scan_error(reference.view(), scan.view(), moved.empty() ? nullptr : moved.data(), over.data(),
                       mean_edge_length(scan.view()));
  }
  return pyb::dict("normal_error_rad"_a = e.normal_error, "distance_mean_edges"_a = e.distance,
                   "faces_used"_a = e.faces_used, "faces"_a = scan.num_triangles(), "flipped"_a = e.flipped,
                   "normal_error_coarse_rad"_a = e.normal_error_coarse,
                   "reference_faces_used"_a = e.reference_faces_used);
}

}  // namespace

void bind_mesh_functions(pyb::module_& m) {
  // Documented where fq/_files.py and fq/_measures.py wrap them.
  m.def("read_mesh", &read_mesh, "path"_a);
  m.def("write_mesh", &write_mesh, "path"_a, "V"_a, "F"_a, "labels"_a, "arrays"_a, "drc_bits"_a);
  m.def("add_noise", &add_noise, "V"_a, "F"_a, "sigma"_a, "seed"_a, "kind"_a, "length"_a);
  m.def("metrics", &metrics, "V_ref"_a, "F"_a, "V"_a);
  m.def("scan_error", &scan_error, "V_ref"_a, "F_ref"_a, "V_scan"_a, "F_scan"_a, "V"_a);
}

}  // namespace fq::py
