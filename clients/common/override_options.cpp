#include "clients/common/override_options.h"

#include <optional>

#include "core/params.h"
#include "wire/header_codec.h"

namespace fq::client {

namespace {

/// Registers `flag` in `group`: given on the command line, its value goes into `o` through
/// the field's setter, so only the given options are set.
template <class T>
void add_field(CLI::App& app, const std::string& group, const std::string& flag,
               void (wire::ParamOverrides::*set)(T), wire::ParamOverrides& o, const std::string& help) {
  app.add_option_function<T>(flag, [&o, set](const T& v) { (o.*set)(v); }, help)->group(group);
}

}  // namespace

void add_override_options(CLI::App& app, OverrideArgs& a) {
  using P = wire::ParamOverrides;
  wire::ParamOverrides& o = a.fields;
  const std::string g = "Parameter overrides (sigmas in mean edge lengths; unset = the stream's)";
  add_field(app, g, "--sigma-s", &P::set_sigma_s, o, "spatial extent of the quadric diffusion");
  add_field(app, g, "--sigma-r", &P::set_sigma_r, o, "range extent (feature threshold)");
  add_field(app, g, "--sigma-b", &P::set_sigma_b, o, "finest detail of Q' (0 = sigma_s / 2)");
  add_field(app, g, "--sigma-n", &P::set_sigma_n, o, "normal smoothing of the constrained update");
  add_field(app, g, "--constrained", &P::set_constrained, o, "normal-constrained update (true/false)");
  add_field(app, g, "--tikhonov", &P::set_tikhonov, o, "pull toward the current position");
  add_field(app, g, "--known-noise", &P::set_known_noise, o, "qf+: noise to filter for, mean edges (0 = estimated)");
  add_field(app, g, "--strength", &P::set_strength, o, "qf+: factor on the noise the strengths come from");
  add_field(app, g, "--temporal", &P::set_temporal, o, "qf+: pull towards the stream's last result, [0, 1]");
  app.add_option("--mode", a.mode, "filter: " + join_names(method_names<FilterMethod>(), " | "))->group(g);
  add_field(app, g, "--sigma-d", &P::set_sigma_d, o, "clustering spatial extent");
  add_field(app, g, "--sigma-q", &P::set_sigma_q, o, "clustering range extent");
  add_field(app, g, "--theta", &P::set_theta, o, "clustering threshold in (0, 1]");
  app.add_option("--cluster-method", a.cluster_method, join_names(method_names<ClusterMethod>(), " | "))
      ->group(g);
  add_field(app, g, "--target-clusters", &P::set_target_clusters, o,
            "cluster count to aim for, theta found per frame (0 = theta)");
  app.add_option("--cluster-geometry", a.cluster_geometry, "auto | input | filtered")->group(g);
  add_field(app, g, "--min-cluster-size", &P::set_min_cluster_size, o,
            "connected clusters, small parts merged (0 = off)");
  add_field(app, g, "--track-ids", &P::set_track_ids, o, "stable cluster ids across frames (true/false)");
  add_field(app, g, "--sticky-rings", &P::set_sticky_rings, o,
            "rings a cluster border may move back (0 = none)");
  app.add_option("--compute", a.compute, "filter | cluster | filter_and_cluster")->group(g);
}

Status to_wire(const OverrideArgs& a, wire::ParamOverrides& o, wire::Compute& compute) {
  o = a.fields;
  if (!a.cluster_geometry.empty()) {
    ClusterGeometry g{};
    if (!parse_cluster_geometry(a.cluster_geometry, g))
      return invalid_argument("--cluster-geometry must be auto, input or filtered (got " +
                              a.cluster_geometry + ")");
    o.set_cluster_geometry(wire::to_wire(g));
  }
  if (!a.mode.empty()) {
    const std::optional<FilterMethod> m = parse_method<FilterMethod>(a.mode);
    if (!m)
      return invalid_argument("--mode must be " + join_names(method_names<FilterMethod>()) + " (got " +
                              a.mode + ")");
    o.set_mode(wire::to_wire(*m));
  }
  if (!a.cluster_method.empty()) {
    const std::optional<ClusterMethod> m = parse_method<ClusterMethod>(a.cluster_method);
    if (!m)
      return invalid_argument("--cluster-method must be " + join_names(method_names<ClusterMethod>()) +
                              " (got " + a.cluster_method + ")");
    o.set_cluster_method(wire::to_wire(*m));
  }
  compute = wire::COMPUTE_DEFAULT;
  if (!a.compute.empty()) {
    const std::optional<wire::Compute> c = wire::compute_from_name(a.compute);
    if (!c)
      return invalid_argument("--compute must be filter, cluster or filter_and_cluster (got " + a.compute +
                              ")");
    compute = *c;
  }
  return {};
}

}  // namespace fq::client
