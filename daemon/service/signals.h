// SIGINT/SIGTERM handling without async-signal-unsafe handlers: the signals are blocked in
// every thread (call block_stop_signals() before starting any), and the main thread waits
// for one synchronously, then stops the daemon in ordinary code.
#pragma once

namespace fq::daemon {

/// Blocks SIGINT, SIGTERM and SIGHUP in the calling thread and every thread it starts later.
void block_stop_signals();

/// Waits for SIGINT, SIGTERM or SIGHUP (blocked by block_stop_signals) and returns its
/// number; the caller reloads on SIGHUP and waits again.
int wait_for_stop_signal();

}  // namespace fq::daemon
