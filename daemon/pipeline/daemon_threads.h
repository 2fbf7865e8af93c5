// fqd's threads by name. Each thread fqd starts is "fqd-<role>", the shared pool's are
// "fq-pool" (common/thread_pool.cpp) and the ZeroMQ I/O threads of fqd's contexts start with
// kZmqThreadTag ("7/ZMQbg/IO/0"). perf, top -H and fqd itself tell them apart from the threads
// of a program that embeds fqd (fqstreambench, the tests): fq_cpu_seconds_total sums them.
#pragma once

#include <string_view>
#include <zmq.hpp>

namespace fq::daemon {

/// The ZeroMQ I/O thread prefix of fqd's contexts. libzmq 4.3 takes an integer only.
constexpr int kZmqThreadTag = 7;

/// Names the calling thread "fqd-<role>" (15 characters at most, Linux's limit).
void name_this_thread(const char* role);

/// Gives the ZeroMQ threads of `ctx` fqd's tag; before its first socket.
void tag_zmq_threads(zmq::context_t& ctx);

/// Whether a thread name (/proc/.../comm) is one of fqd's.
bool is_daemon_thread(std::string_view name);

/// CPU seconds of every live thread of this process that is one of fqd's.
double daemon_threads_cpu_seconds();

}  // namespace fq::daemon
