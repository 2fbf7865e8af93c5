// ParamOverrides / Compute <-> fq::Params.
#include <string>

#include "proto/header_codec.h"

namespace fq::wire {
namespace {

fq::Status set_mode(FilterMode m, fq::FilterParams& f) {
  switch (m) {
    case MODE_DEFAULT:
      return {};
    case QF:
      f.method = fq::FilterMethod::kQuadric;
      return {};
    case BF:
      f.method = fq::FilterMethod::kBilateral;
      return {};
    case QF_PLUS:
      f.method = fq::FilterMethod::kQuadricRefined;
      return {};
    default:
      return invalid_argument("filter mode " + std::to_string(m) + " is not a FilterMode");
  }
}

fq::Status set_method(ClusterMethodWire m, fq::ClusterParams& c) {
  switch (m) {
    case METHOD_DEFAULT:
      return {};
    case QUADRIC:
      c.method = fq::ClusterMethod::kQuadric;
      return {};
    case EUCLIDEAN:
      c.method = fq::ClusterMethod::kEuclidean;
      return {};
    default:
      return invalid_argument("cluster method " + std::to_string(m) + " is not a ClusterMethodWire");
  }
}

fq::Status set_geometry(ClusterGeometryWire g, fq::ClusterParams& c) {
  switch (g) {
    case GEOMETRY_DEFAULT:
      return {};
    case GEOMETRY_AUTO:
      c.geometry = fq::ClusterGeometry::kAuto;
      return {};
    case GEOMETRY_INPUT:
      c.geometry = fq::ClusterGeometry::kInput;
      return {};
    case GEOMETRY_FILTERED:
      c.geometry = fq::ClusterGeometry::kFiltered;
      return {};
    default:
      return invalid_argument("cluster geometry " + std::to_string(g) + " is not a ClusterGeometryWire");
  }
}

ClusterGeometryWire geometry_of(const fq::ClusterParams& c) {
  switch (c.geometry) {
    case fq::ClusterGeometry::kInput:
      return GEOMETRY_INPUT;
    case fq::ClusterGeometry::kFiltered:
      return GEOMETRY_FILTERED;
    default:
      return GEOMETRY_AUTO;
  }
}

FilterMode mode_of(const fq::FilterParams& f) {
  switch (f.method) {
    case fq::FilterMethod::kBilateral: return BF;
    case fq::FilterMethod::kQuadricRefined: return QF_PLUS;
    case fq::FilterMethod::kQuadric: break;
  }
  return QF;
}

ClusterMethodWire method_of(const fq::ClusterParams& c) {
  return c.method == fq::ClusterMethod::kEuclidean ? EUCLIDEAN : QUADRIC;
}

}  // namespace

fq::Status apply_overrides(const ParamOverrides& o, fq::Params& inout) {
  fq::Params p = inout;  // all or nothing: a bad enum leaves `inout` untouched
  if (o.has_sigma_s()) p.filtering.sigma_s = o.sigma_s();
  if (o.has_sigma_r()) p.filtering.sigma_r = o.sigma_r();
  if (o.has_sigma_b()) p.filtering.sigma_b = o.sigma_b();
  if (o.has_sigma_n()) p.filtering.sigma_n = o.sigma_n();
  if (o.has_constrained()) p.filtering.constrained = o.constrained();
  if (o.has_tikhonov()) p.filtering.tikhonov = o.tikhonov();
  if (o.has_mode()) {
    if (auto s = set_mode(o.mode(), p.filtering); !s.ok()) return s;
  }
  if (o.has_sigma_d()) p.clustering.sigma_d = o.sigma_d();
  if (o.has_sigma_q()) p.clustering.sigma_q = o.sigma_q();
  if (o.has_theta()) p.clustering.theta = o.theta();
  if (o.has_cluster_method()) {
    if (auto s = set_method(o.cluster_method(), p.clustering); !s.ok()) return s;
  }
  if (o.has_target_clusters()) p.clustering.target_clusters = o.target_clusters();
  if (o.has_cluster_geometry()) {
    if (auto s = set_geometry(o.cluster_geometry(), p.clustering); !s.ok()) return s;
  }
  if (o.has_min_cluster_size()) p.clustering.min_cluster_size = o.min_cluster_size();
  if (o.has_track_ids()) p.clustering.track_ids = o.track_ids();
  if (o.has_sticky_rings()) p.clustering.sticky_rings = o.sticky_rings();
  inout = p;
  return {};
}

fq::Status apply_compute(Compute c, fq::Params& inout) {
  switch (c) {
    case COMPUTE_DEFAULT:
      return {};
    case FILTER:
      inout.filter = true;
      inout.cluster = false;
      return {};
    case CLUSTER:
      inout.filter = false;
      inout.cluster = true;
      return {};
    case FILTER_AND_CLUSTER:
      inout.filter = true;
      inout.cluster = true;
      return {};
    default:
      return invalid_argument("compute " + std::to_string(c) + " is not a Compute");
  }
}

Compute compute_of(const fq::Params& p) {
  if (p.filter && p.cluster) return FILTER_AND_CLUSTER;
  return p.cluster ? CLUSTER : FILTER;
}

void params_to_wire(const fq::Params& p, ParamOverrides& out) {
  out.set_sigma_s(p.filtering.sigma_s);
  out.set_sigma_r(p.filtering.sigma_r);
  out.set_sigma_b(p.filtering.sigma_b);
  out.set_sigma_n(p.filtering.sigma_n);
  out.set_constrained(p.filtering.constrained);
  out.set_tikhonov(p.filtering.tikhonov);
  out.set_mode(mode_of(p.filtering));
  out.set_sigma_d(p.clustering.sigma_d);
  out.set_sigma_q(p.clustering.sigma_q);
  out.set_theta(p.clustering.theta);
  out.set_cluster_method(method_of(p.clustering));
  out.set_target_clusters(p.clustering.target_clusters);
  out.set_cluster_geometry(geometry_of(p.clustering));
  out.set_min_cluster_size(p.clustering.min_cluster_size);
  out.set_track_ids(p.clustering.track_ids);
  out.set_sticky_rings(p.clustering.sticky_rings);
}

}  // namespace fq::wire
