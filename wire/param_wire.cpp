// ParamOverrides / Compute <-> fq::Params.
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>

#include "common/pair_table.h"
#include "wire/header_codec.h"

namespace fq::wire {
namespace {

constexpr std::pair<FilterMode, fq::FilterMethod> kModes[] = {{QF, fq::FilterMethod::kQuadric},
                                                              {BF, fq::FilterMethod::kBilateral},
                                                              {QF_PLUS, fq::FilterMethod::kQuadricRefined}};
constexpr std::pair<ClusterMethodWire, fq::ClusterMethod> kMethods[] = {
    {QUADRIC, fq::ClusterMethod::kQuadric}, {EUCLIDEAN, fq::ClusterMethod::kEuclidean}};
constexpr std::pair<ClusterGeometryWire, fq::ClusterGeometry> kGeometries[] = {
    {GEOMETRY_AUTO, fq::ClusterGeometry::kAuto},
    {GEOMETRY_INPUT, fq::ClusterGeometry::kInput},
    {GEOMETRY_FILTERED, fq::ClusterGeometry::kFiltered}};
/// Params::filter and Params::cluster of each compute mode.
constexpr std::pair<Compute, std::pair<bool, bool>> kComputes[] = {
    {FILTER, {true, false}}, {CLUSTER, {false, true}}, {FILTER_AND_CLUSTER, {true, true}}};
constexpr std::pair<Compute, const char*> kComputeNames[] = {
    {FILTER, "filter"}, {CLUSTER, "cluster"}, {FILTER_AND_CLUSTER, "filter_and_cluster"}};

/// Sets `out` to what `w` stands for in `table`; the enum's DEFAULT (0) keeps `out`.
/// kInvalidArgument, naming `what`, for a value outside the wire enum.
template <class Wire, class Native, size_t N>
fq::Status set_from_wire(const std::pair<Wire, Native> (&table)[N], Wire w, const char* what, Native& out) {
  if (w == Wire{}) return {};
  const std::optional<Native> native = second_of(table, w);
  if (!native)
    return invalid_argument(std::string(what) + " " + std::to_string(w) + " is not a " +
                            google::protobuf::GetEnumDescriptor<Wire>()->name());
  out = *native;
  return {};
}

}  // namespace

FilterMode to_wire(fq::FilterMethod m) { return first_of(kModes, m).value_or(QF); }
ClusterMethodWire to_wire(fq::ClusterMethod m) { return first_of(kMethods, m).value_or(QUADRIC); }
ClusterGeometryWire to_wire(fq::ClusterGeometry g) {
  return first_of(kGeometries, g).value_or(GEOMETRY_AUTO);
}

fq::Status apply_overrides(const ParamOverrides& o, fq::Params& inout) {
  fq::Params p = inout;  // all or nothing: a bad enum leaves `inout` untouched
  if (o.has_sigma_s()) p.filtering.sigma_s = o.sigma_s();
  if (o.has_sigma_r()) p.filtering.sigma_r = o.sigma_r();
  if (o.has_sigma_b()) p.filtering.sigma_b = o.sigma_b();
  if (o.has_sigma_n()) p.filtering.sigma_n = o.sigma_n();
  if (o.has_constrained()) p.filtering.constrained = o.constrained();
  if (o.has_tikhonov()) p.filtering.tikhonov = o.tikhonov();
  if (o.has_known_noise()) p.filtering.refine.known_noise = o.known_noise();
  if (o.has_strength()) p.filtering.refine.strength = o.strength();
  if (o.has_temporal()) p.filtering.temporal = o.temporal();
  if (o.has_mode()) FQ_RETURN_IF_ERROR(set_from_wire(kModes, o.mode(), "filter mode", p.filtering.method));
  if (o.has_sigma_d()) p.clustering.sigma_d = o.sigma_d();
  if (o.has_sigma_q()) p.clustering.sigma_q = o.sigma_q();
  if (o.has_theta()) p.clustering.theta = o.theta();
  if (o.has_cluster_method())
    FQ_RETURN_IF_ERROR(set_from_wire(kMethods, o.cluster_method(), "cluster method", p.clustering.method));
  if (o.has_target_clusters()) p.clustering.target_clusters = o.target_clusters();
  if (o.has_cluster_geometry())
    FQ_RETURN_IF_ERROR(
        set_from_wire(kGeometries, o.cluster_geometry(), "cluster geometry", p.clustering.geometry));
  if (o.has_min_cluster_size()) p.clustering.min_cluster_size = o.min_cluster_size();
  if (o.has_track_ids()) p.clustering.track_ids = o.track_ids();
  if (o.has_sticky_rings()) p.clustering.sticky_rings = o.sticky_rings();
  inout = p;
  return {};
}

fq::Status apply_compute(Compute c, fq::Params& inout) {
  std::pair<bool, bool> flags{inout.filter, inout.cluster};
  FQ_RETURN_IF_ERROR(set_from_wire(kComputes, c, "compute", flags));
  std::tie(inout.filter, inout.cluster) = flags;
  return {};
}

Compute compute_of(const fq::Params& p) {
  return first_of(kComputes, std::pair{p.filter, p.cluster}).value_or(FILTER);
}

const char* compute_name(Compute c) { return second_of(kComputeNames, c).value_or("filter"); }

std::optional<Compute> compute_from_name(std::string_view name) { return first_of(kComputeNames, name); }

void params_to_wire(const fq::Params& p, ParamOverrides& out) {
  out.set_sigma_s(p.filtering.sigma_s);
  out.set_sigma_r(p.filtering.sigma_r);
  out.set_sigma_b(p.filtering.sigma_b);
  out.set_sigma_n(p.filtering.sigma_n);
  out.set_constrained(p.filtering.constrained);
  out.set_tikhonov(p.filtering.tikhonov);
  out.set_known_noise(p.filtering.refine.known_noise);
  out.set_strength(p.filtering.refine.strength);
  out.set_temporal(p.filtering.temporal);
  out.set_mode(to_wire(p.filtering.method));
  out.set_sigma_d(p.clustering.sigma_d);
  out.set_sigma_q(p.clustering.sigma_q);
  out.set_theta(p.clustering.theta);
  out.set_cluster_method(to_wire(p.clustering.method));
  out.set_target_clusters(p.clustering.target_clusters);
  out.set_cluster_geometry(to_wire(p.clustering.geometry));
  out.set_min_cluster_size(p.clustering.min_cluster_size);
  out.set_track_ids(p.clustering.track_ids);
  out.set_sticky_rings(p.clustering.sticky_rings);
}

}  // namespace fq::wire
