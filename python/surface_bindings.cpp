// The compiled parts of fq.surface_sample and fq.surface_flicker (wrapped and documented in
// fq/_measures.py): eval/surface_flicker.h on numpy meshes, sampled without the GIL.
#include <pybind11/numpy.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "eval/surface_flicker.h"
#include "python/bindings.h"
#include "python/numpy_mesh.h"

namespace fq::py {

namespace {

using namespace pybind11::literals;

/// `values` as a float64 array of shape (len / columns, columns), or 1-D when columns is 1.
pyb::array doubles(const std::vector<double>& values, size_t columns) {
  std::vector<ssize_t> shape{ssize_t(values.size() / columns)};
  if (columns > 1) shape.push_back(ssize_t(columns));
  pyb::array_t<double> a(shape);
  std::copy(values.begin(), values.end(), a.mutable_data());
  return a;
}

pyb::object number_or_none(std::optional<double> x) {
  return x && std::isfinite(*x) ? pyb::object(pyb::float_(*x)) : pyb::object(pyb::none());
}

SurfaceSample sample(const pyb::handle& v_clean, const pyb::handle& f_clean, const pyb::handle& v_result,
                     const pyb::handle& f_result, int threads) {
  const Mesh clean = to_mesh(v_clean, f_clean), result = to_mesh(v_result, f_result);
  const pyb::gil_scoped_release unlocked;
  return sample_surface(clean.view(), result.view(), threads);
}

pyb::dict surface_sample(const pyb::handle& v_clean, const pyb::handle& f_clean, const pyb::handle& v_result,
                         const pyb::handle& f_result, int threads) {
  const SurfaceSample s = sample(v_clean, f_clean, v_result, f_result, threads);
  pyb::array_t<bool> hit(ssize_t(s.hit.size()));
  std::copy(s.hit.begin(), s.hit.end(), hit.mutable_data());
  return pyb::dict("height"_a = doubles(s.height, 1), "result_normal"_a = doubles(s.result_normal, 3),
                   "clean_normal"_a = doubles(s.clean_normal, 3), "area"_a = doubles(s.area, 1),
                   "hit"_a = hit, "mean_edge"_a = s.mean_edge, "height_rms"_a = height_rms(s),
                   "smooth_normal_error_rad"_a = smooth_normal_error(s));
}

pyb::dict surface_flicker(const pyb::iterable& frames, int threads) {
  SurfaceFlickerSeries series;
  pyb::list per_frame;
  for (const pyb::handle frame : frames) {
    const auto parts = frame.cast<pyb::sequence>();
    if (parts.size() != 4)
      throw pyb::value_error("each frame must be (clean_V, clean_F, result_V, result_F)");
    const SurfaceFrameMetrics m = series.add(sample(parts[0], parts[1], parts[2], parts[3], threads));
    per_frame.append(pyb::dict("height_rms"_a = m.height_rms,
                               "smooth_normal_error_rad"_a = m.smooth_normal_error,
                               "surface_flicker"_a = number_or_none(m.surface_flicker),
                               "shading_flicker"_a = number_or_none(m.shading_flicker)));
  }
  return pyb::dict("height_rms"_a = series.mean_height_rms(),
                   "smooth_normal_error_rad"_a = series.mean_smooth_normal_error(),
                   "surface_flicker"_a = series.mean_surface_flicker(),
                   "shading_flicker"_a = series.mean_shading_flicker(),
                   "transitions"_a = series.transitions(), "frames"_a = per_frame);
}

}  // namespace

void bind_surface_measures(pyb::module_& m) {
  // Documented where fq/_measures.py wraps them.
  m.def("surface_sample", &surface_sample, "V_clean"_a, "F_clean"_a, "V_result"_a, "F_result"_a, "threads"_a);
  m.def("surface_flicker", &surface_flicker, "frames"_a, "threads"_a);
}

}  // namespace fq::py
