// The engines for fq.filter and fq.cluster (fq/_engine.py): numpy in, numpy out, the engine
// run without the GIL and stopped by Ctrl-C. The keywords come from python/keywords.h.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <array>
#include <string>

#include "core/params.h"
#include "eval/vertex_moves.h"
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

FrameResult run(const Mesh& mesh, const Params& params, const EngineOptions& o) {
  FrameResult result;
  throw_if_error(run_interruptible(o, mesh.view(), params, result));
  return result;
}

/// What fq.filter(return_info=True) adds (documented in fq/_engine.py).
pyb::dict filter_info(const Mesh& mesh, const Params& p, const FrameResult& r) {
  const VertexMoves moved =
      vertex_moves(mesh.positions.data(), r.positions.data(), mesh.num_vertices(), r.mean_edge);
  const bool qf_plus = p.filter && p.filtering.method == FilterMethod::kQuadricRefined;
  const pyb::object none = pyb::none();
  return pyb::dict(
      "mean_edge"_a = r.mean_edge, "noise_estimate"_a = qf_plus ? pyb::cast(r.noise_estimate) : none,
      "noise_residual"_a = qf_plus ? pyb::cast(r.noise_residual) : none,
      "noise_directional"_a = qf_plus ? pyb::cast(r.noise_directional) : none,
      "noise_direction"_a = qf_plus ? pyb::cast(std::array<float, 3>{r.noise_direction.x, r.noise_direction.y,
                                                                     r.noise_direction.z})
                                    : none,
      "noise_alignment"_a = qf_plus ? pyb::cast(r.noise_alignment) : none,
      "filtered_for"_a = qf_plus ? pyb::cast(r.filter_noise) : none, "moved_mean"_a = moved.mean,
      "moved_p99"_a = moved.p99, "moved_max"_a = moved.max, "welded_vertices"_a = r.welded_vertices);
}

pyb::object filter(const pyb::handle& v, const pyb::handle& f, const pyb::dict& keywords,
                   const std::string& engine, int threads, bool info) {
  Params p;  // fqfilter's defaults: the same positions as fqfilter for the same keywords
  apply_keywords("filter", keywords, p);
  const Mesh mesh = to_mesh(v, f);
  const FrameResult r = run(mesh, p, engine_options(engine, threads));
  pyb::array positions = positions_array(r.positions, v);
  if (!info) return positions;
  return pyb::make_tuple(positions, filter_info(mesh, p, r));
}

pyb::array cluster(const pyb::handle& v, const pyb::handle& f, const pyb::dict& keywords,
                   const std::string& engine, int threads) {
  Params p;  // as `fqfilter --no-filter`
  p.filter = false;
  p.cluster = true;
  apply_keywords("cluster", keywords, p);
  return labels_array(run(to_mesh(v, f), p, engine_options(engine, threads)).labels);
}

}  // namespace

void bind_engine_functions(pyb::module_& m) {
  m.def("filter", &filter, "V"_a, "F"_a, "keywords"_a, "engine"_a, "threads"_a, "info"_a = false);
  m.def("cluster", &cluster, "V"_a, "F"_a, "keywords"_a, "engine"_a, "threads"_a);
  m.def("keywords", &keyword_rows, "function"_a);
  m.def("param_rows", &param_rows);
  m.def(
      "engine_name",
      [](const std::string& engine, int threads) {
        const EngineOptions o = engine_options(engine, threads);
        StatusOr<std::unique_ptr<Engine>> e = make_engine(o);
        throw_if_error(e.status());
        return (*e)->name();
      },
      "engine"_a, "threads"_a);
}

}  // namespace fq::py
