// Readiness for systemd's Type=notify (packaging/fqd.service): fqd says READY=1 once its
// sockets are bound and every thread runs, RELOADING=1 / READY=1 around a SIGHUP reload and
// STOPPING=1 when it drains. The protocol is one datagram on the unix socket named by
// $NOTIFY_SOCKET (sd_notify(3)); systemd documents it as stable and meant to be spoken
// without libsystemd, which would otherwise be one more library in every image (containers
// have no systemd) for these few lines.
#pragma once

#include <string>

namespace fq::daemon {

/// Sends `state` ("READY=1\nSTATUS=...") to $NOTIFY_SOCKET: a filesystem path, or a name
/// starting with '@' for an abstract socket. False when the variable is unset or the send
/// fails (fqd runs the same without a service manager).
bool notify_service_manager(const std::string& state);

}  // namespace fq::daemon
