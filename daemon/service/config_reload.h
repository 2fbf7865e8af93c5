// What SIGHUP may change in a running fqd, and what only a restart can. A reload applies the
// whole file or nothing: a file that changes a restart-only setting is refused, naming it.
//   live:    [defaults], [streams.*], log_level, caps.allowed_streams, caps.max_vertices,
//            caps.stream_idle_s, caps.metric_series_idle_s, caps.max_neighbour_work, caps.pool_idle_s,
//            caps.engine_time_limit_s, caps.stop_grace_s, caps.max_queued_frames,
//            caps.max_queued_bytes, caps.memory_budget_mb, security.client_keys_file and
//            security.control_keys_file (the keys they list, revoked ones losing their connections; whether
//            control_keys_file is set at all is restart-only), http.token_file, http.allowed_hosts
//   restart: everything else (sockets, threads, engines, listeners and their bounds).
#pragma once

#include <string>
#include <vector>

#include "daemon/config/config.h"

namespace fq::daemon {

/// The restart-only settings (dotted names) whose value in `fresh` differs from `running`'s;
/// empty when a reload can apply all of `fresh`. `running` has its thread counts resolved.
std::vector<std::string> restart_only_changes(const DaemonConfig& running, DaemonConfig fresh);

}  // namespace fq::daemon
