#include "clients/common/override_options.h"

#include <optional>

#include "kernels/params.h"

namespace fq::client {

void add_override_options(CLI::App& app, OverrideArgs& a) {
  const std::string g = "Parameter overrides (sigmas in mean edge lengths; unset = the stream's)";
  app.add_option("--sigma-s", a.sigma_s, "spatial extent of the quadric diffusion")->group(g);
  app.add_option("--sigma-r", a.sigma_r, "range extent (feature threshold)")->group(g);
  app.add_option("--sigma-b", a.sigma_b, "finest detail of Q' (0 = sigma_s / 2)")->group(g);
  app.add_option("--sigma-n", a.sigma_n, "normal smoothing of the constrained update")->group(g);
  app.add_option("--constrained", a.constrained, "normal-constrained update (true/false)")->group(g);
  app.add_option("--tikhonov", a.tikhonov, "pull toward the current position")->group(g);
  app.add_option("--mode", a.mode, "filter: " + join_names(method_names<FilterMethod>(), " | "))->group(g);
  app.add_option("--sigma-d", a.sigma_d, "clustering spatial extent")->group(g);
  app.add_option("--sigma-q", a.sigma_q, "clustering range extent")->group(g);
  app.add_option("--theta", a.theta, "clustering threshold in (0, 1]")->group(g);
  app.add_option("--cluster-method", a.cluster_method, join_names(method_names<ClusterMethod>(), " | "))
      ->group(g);
  app.add_option("--target-clusters", a.target_clusters, "cluster count to aim for, theta found per frame (0 = theta)")
      ->group(g);
  app.add_option("--cluster-geometry", a.cluster_geometry, "auto | input | filtered")->group(g);
  app.add_option("--min-cluster-size", a.min_cluster_size, "connected clusters, small parts merged (0 = off)")
      ->group(g);
  app.add_option("--track-ids", a.track_ids, "stable cluster ids across frames (true/false)")->group(g);
  app.add_option("--sticky-rings", a.sticky_rings, "rings a cluster border may move back (0 = none)")->group(g);
  app.add_option("--compute", a.compute, "filter | cluster | filter_and_cluster")->group(g);
}

Status to_wire(const OverrideArgs& a, wire::ParamOverrides& o, wire::Compute& compute) {
  o.Clear();
  if (a.sigma_s) o.set_sigma_s(*a.sigma_s);
  if (a.sigma_r) o.set_sigma_r(*a.sigma_r);
  if (a.sigma_b) o.set_sigma_b(*a.sigma_b);
  if (a.sigma_n) o.set_sigma_n(*a.sigma_n);
  if (a.constrained) o.set_constrained(*a.constrained);
  if (a.tikhonov) o.set_tikhonov(*a.tikhonov);
  if (a.sigma_d) o.set_sigma_d(*a.sigma_d);
  if (a.sigma_q) o.set_sigma_q(*a.sigma_q);
  if (a.theta) o.set_theta(*a.theta);
  if (a.target_clusters) o.set_target_clusters(*a.target_clusters);
  if (a.min_cluster_size) o.set_min_cluster_size(*a.min_cluster_size);
  if (a.track_ids) o.set_track_ids(*a.track_ids);
  if (a.sticky_rings) o.set_sticky_rings(*a.sticky_rings);
  if (a.cluster_geometry == "auto")
    o.set_cluster_geometry(wire::GEOMETRY_AUTO);
  else if (a.cluster_geometry == "input")
    o.set_cluster_geometry(wire::GEOMETRY_INPUT);
  else if (a.cluster_geometry == "filtered")
    o.set_cluster_geometry(wire::GEOMETRY_FILTERED);
  else if (!a.cluster_geometry.empty())
    return invalid_argument("--cluster-geometry must be auto, input or filtered (got " + a.cluster_geometry + ")");
  if (!a.mode.empty()) {
    const std::optional<FilterMethod> m = parse_method<FilterMethod>(a.mode);
    if (!m)
      return invalid_argument("--mode must be " + join_names(method_names<FilterMethod>()) + " (got " +
                              a.mode + ")");
    o.set_mode(*m == FilterMethod::kQuadric ? wire::QF : *m == FilterMethod::kBilateral ? wire::BF : wire::QF_PLUS);
  }
  if (!a.cluster_method.empty()) {
    const std::optional<ClusterMethod> m = parse_method<ClusterMethod>(a.cluster_method);
    if (!m)
      return invalid_argument("--cluster-method must be " + join_names(method_names<ClusterMethod>()) +
                              " (got " + a.cluster_method + ")");
    o.set_cluster_method(*m == ClusterMethod::kQuadric ? wire::QUADRIC : wire::EUCLIDEAN);
  }
  compute = wire::COMPUTE_DEFAULT;
  if (a.compute == "filter")
    compute = wire::FILTER;
  else if (a.compute == "cluster")
    compute = wire::CLUSTER;
  else if (a.compute == "filter_and_cluster")
    compute = wire::FILTER_AND_CLUSTER;
  else if (!a.compute.empty())
    return invalid_argument("--compute must be filter, cluster or filter_and_cluster (got " + a.compute +
                            ")");
  return {};
}

}  // namespace fq::client
