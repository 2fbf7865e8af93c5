// fq.Stream's compiled part (fq/_stream.py): one stream's frames filtered in order, each with
// the stream's last result (kernels/temporal.h), on the cached engines of fq.filter.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <string>

#include "core/params.h"
#include "kernels/temporal.h"
#include "python/bindings.h"
#include "python/engine_options.h"
#include "python/interruptible.h"
#include "python/keywords.h"
#include "python/numpy_mesh.h"
#include "python/py_errors.h"

namespace fq::py {

namespace {

namespace pyb = pybind11;
using namespace pybind11::literals;

class Stream {
 public:
  Stream(const pyb::dict& keywords, float temporal, const std::string& engine, int threads)
      : options_(engine_options(engine, threads)) {
    apply_keywords("filter", keywords, params_);
    if (params_.filtering.method != FilterMethod::kQuadricRefined)
      throw pyb::value_error("fq.Stream filters across frames with mode='qf+' only");
    params_.filtering.temporal = temporal;
    throw_if_error(validate(params_));
  }

  pyb::array filter(const pyb::handle& v, const pyb::handle& f) {
    const Mesh mesh = to_mesh(v, f);
    throw_if_error(run_interruptible(options_, mesh.view(), params_, last_, &history_));
    return positions_array(last_.positions, v);
  }

  void reset() { history_.forget(); }
  uint64_t frames() const { return history_.frames; }
  uint64_t resets() const { return history_.resets; }
  float temporal() const { return params_.filtering.temporal; }
  pyb::dict last() const {
    return pyb::dict("noise_estimate"_a = last_.noise_estimate, "prior_coverage"_a = last_.prior_coverage,
                     "prior_share"_a = last_.prior_share, "history_reset"_a = last_.history_reset,
                     "track"_a = temporal_track_name(last_.temporal_track),
                     "ids_refused"_a = last_.ids_refused, "ids_wide"_a = last_.ids_wide);
  }

 private:
  EngineOptions options_;
  Params params_;
  TemporalHistory history_;
  FrameResult last_;
};

}  // namespace

void bind_stream(pyb::module_& m) {
  pyb::class_<Stream>(m, "Stream")
      .def(pyb::init<const pyb::dict&, float, const std::string&, int>(), "keywords"_a, "temporal"_a,
           "engine"_a, "threads"_a)
      .def("filter", &Stream::filter, "V"_a, "F"_a)
      .def("reset", &Stream::reset)
      .def_property_readonly("frames", &Stream::frames)
      .def_property_readonly("resets", &Stream::resets)
      .def_property_readonly("temporal", &Stream::temporal)
      .def_property_readonly("last", &Stream::last);
}

}  // namespace fq::py
