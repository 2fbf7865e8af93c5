// fq.filter and fq.cluster: numpy in, numpy out, the engine runs without the GIL.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <string>

#include "core/params.h"
#include "python/bindings.h"
#include "python/engine_cache.h"
#include "python/numpy_mesh.h"
#include "python/py_errors.h"

namespace fq::py {

namespace {

namespace pyb = pybind11;
using namespace pybind11::literals;

EngineOptions engine_options(const std::string& engine, int threads) {
  EngineOptions o;
  if (!parse_engine_kind(engine, o.kind))
    throw pyb::value_error("engine must be 'auto', 'cpu' or 'cuda', got '" + engine + "'");
  if (threads < 0) throw pyb::value_error("threads must be >= 0 (0: all hardware threads)");
  o.threads = threads;
  return o;
}

FrameResult run(const pyb::handle& v, const pyb::handle& f, const Params& params, const EngineOptions& o) {
  const Mesh mesh = to_mesh(v, f);
  FrameResult result;
  Status s;
  {
    const pyb::gil_scoped_release unlocked;
    s = run_cached_engine(o, mesh.view(), params, result);
  }
  throw_if_error(s);
  return result;
}

FilterParams filter_params(float sigma_s, float sigma_r, float sigma_b, const std::string& mode) {
  FilterParams f;
  f.sigma_s = sigma_s;
  f.sigma_r = sigma_r;
  f.sigma_b = sigma_b;
  if (mode == "qf")
    f.method = FilterMethod::kQuadric;
  else if (mode == "bf")
    f.method = FilterMethod::kBilateral;
  else
    throw pyb::value_error("mode must be 'qf' or 'bf', got '" + mode + "'");
  return f;
}

pyb::array filter(const pyb::handle& v, const pyb::handle& f, float sigma_s, float sigma_r, float sigma_b,
                  float sigma_n, bool constrained, float tikhonov, const std::string& mode,
                  const std::string& engine, int threads) {
  Params p;
  p.filtering = filter_params(sigma_s, sigma_r, sigma_b, mode);
  p.filtering.sigma_n = sigma_n;
  p.filtering.constrained = constrained;
  p.filtering.tikhonov = tikhonov;
  const FrameResult r = run(v, f, p, engine_options(engine, threads));
  return positions_array(r.positions, v);
}

pyb::array cluster(const pyb::handle& v, const pyb::handle& f, float sigma_d, float sigma_q, float theta,
                   const std::string& method, float sigma_s, float sigma_r, float sigma_b,
                   const std::string& engine, int threads) {
  Params p;
  p.filter = false;
  p.cluster = true;
  p.filtering = filter_params(sigma_s, sigma_r, sigma_b, "qf");
  p.clustering.sigma_d = sigma_d;
  p.clustering.sigma_q = sigma_q;
  p.clustering.theta = theta;
  if (method == "quadric")
    p.clustering.method = ClusterMethod::kQuadric;
  else if (method == "euclidean")
    p.clustering.method = ClusterMethod::kEuclidean;
  else
    throw pyb::value_error("method must be 'quadric' or 'euclidean', got '" + method + "'");
  return labels_array(run(v, f, p, engine_options(engine, threads)).labels);
}

}  // namespace

void bind_engine_functions(pyb::module_& m) {
  const FilterParams df;  // defaults come from fq::Params, as for fqfilter
  const ClusterParams dc;
  m.def("filter", &filter, "V"_a, "F"_a, pyb::kw_only(), "sigma_s"_a = df.sigma_s, "sigma_r"_a = df.sigma_r,
        "sigma_b"_a = df.sigma_b, "sigma_n"_a = df.sigma_n, "constrained"_a = df.constrained,
        "tikhonov"_a = df.tikhonov, "mode"_a = "qf", "engine"_a = "auto", "threads"_a = 0,
        "Smoothed vertex positions (n, 3) of the mesh (V, F); every sigma in mean edge lengths. "
        "mode 'qf' (filtered quadrics) or 'bf' (bilateral); engine 'auto', 'cpu' or 'cuda'.");
  m.def("cluster", &cluster, "V"_a, "F"_a, pyb::kw_only(), "sigma_d"_a = dc.sigma_d, "sigma_q"_a = dc.sigma_q,
        "theta"_a = dc.theta, "method"_a = "quadric", "sigma_s"_a = df.sigma_s, "sigma_r"_a = df.sigma_r,
        "sigma_b"_a = df.sigma_b, "engine"_a = "auto", "threads"_a = 0,
        "One cluster label per vertex (uint32, 0..k-1) of the mesh (V, F); positions are not moved.");
  m.def(
      "engine_name",
      [](const std::string& engine, int threads) {
        const EngineOptions o = engine_options(engine, threads);
        StatusOr<std::unique_ptr<Engine>> e = make_engine(o);
        throw_if_error(e.status());
        return (*e)->name();
      },
      "engine"_a = "auto", "threads"_a = 0, "The engine `engine` selects here: 'cpu' or 'cuda:<device>'.");
}

}  // namespace fq::py
