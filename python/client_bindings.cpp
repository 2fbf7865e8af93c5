// The compiled parts of fq.Producer and fq.Consumer (wrapped and documented in fq/_client.py):
// a PUSH socket that sends frames as fqpub does and a SUB socket that receives results as fqsub
// does, through fq_client. Every blocking socket call runs without the GIL in short slices,
// so other Python threads run and Ctrl-C interrupts it (wait_interruptible).
#include <pybind11/stl.h>

#include <cerrno>
#include <optional>
#include <string>
#include <zmq.hpp>

#include "clients/common/curve_client.h"
#include "clients/common/frame_sender.h"
#include "clients/common/peer_monitor.h"
#include "python/bindings.h"
#include "python/client_frames.h"
#include "python/interruptible.h"
#include "python/py_errors.h"

namespace fq::py {

namespace {

namespace pyb = pybind11;
using namespace pybind11::literals;

// How long fqpub waits for queued frames at exit, and so does a closed Producer.
constexpr int kLingerMs = 5000;

// A signal (Ctrl-C) ends a blocking ZeroMQ call with EINTR: not an error, a missed attempt,
// after which wait_interruptible runs the signal's handler.
template <class Attempt>
bool unless_interrupted(Attempt attempt) {
  try {
    return attempt();
  } catch (const zmq::error_t& e) {
    if (e.num() != EINTR) throw;
    return false;
  }
}

void connect(zmq::socket_t& socket, const std::string& endpoint, const client::CurveClientOptions& curve) {
  throw_if_error(client::apply_curve_client(socket, curve));
  try {
    socket.connect(endpoint);
  } catch (const zmq::error_t& e) {
    throw pyb::value_error("cannot connect to '" + endpoint + "': " + e.what());
  }
}

class Producer {
 public:
  Producer(const std::string& endpoint, const client::FrameSpec& spec,
           const client::CurveClientOptions& curve)
      : spec_(spec), push_(ctx_, zmq::socket_type::push) {
    push_.set(zmq::sockopt::linger, kLingerMs);  // deliver queued frames before closing
    connect(push_, endpoint, curve);
  }

  uint64_t send(const pyb::handle& v, const pyb::handle& f, double timeout_s) {
    check_open();
    const std::vector<std::string> parts = build_parts(v, f, spec_, sequence_);
    // A PUSH socket blocks while no fqd is connected or its queue is full.
    const bool sent = wait_interruptible(
        [&](int ms) {
          push_.set(zmq::sockopt::sndtimeo, ms);
          return unless_interrupted([&] { return client::send_parts(push_, parts); });
        },
        timeout_s);
    if (!sent) {
      PyErr_SetString(PyExc_TimeoutError, "fqd took no frame within the timeout (is it running?)");
      throw pyb::error_already_set();
    }
    return sequence_++;
  }

  uint64_t sequence() const { return sequence_; }
  void close() { push_.close(); }

 private:
  void check_open() const {
    if (!push_) throw pyb::value_error("the producer is closed");
  }

  client::FrameSpec spec_;
  uint64_t sequence_ = 0;
  zmq::context_t ctx_{1};
  zmq::socket_t push_;
};

class Consumer {
 public:
  Consumer(const std::string& endpoint, const std::optional<std::string>& stream,
           const client::CurveClientOptions& curve, double connect_timeout_s)
      : stream_(stream.value_or("")), sub_(ctx_, zmq::socket_type::sub) {
    sub_.set(zmq::sockopt::rcvhwm, 100000);  // as fqsub: a slow reader queues, fqd never waits
    sub_.set(zmq::sockopt::subscribe, stream_);
    // Results published before the subscription reaches fqd are lost (PUB/SUB): wait for the
    // connection, so that results of frames sent next are seen.
    client::PeerMonitor monitor(sub_, "consumer");
    connect(sub_, endpoint, curve);
    if (connect_timeout_s > 0) {
      const pyb::gil_scoped_release unlocked;
      monitor.wait_for_peer(int(connect_timeout_s * 1e3));
    }
  }

  std::optional<pyb::dict> recv(double timeout_s) {
    if (!sub_) throw pyb::value_error("the consumer is closed");
    client::ReceivedResult r;
    Status bad;
    const bool got = wait_interruptible(
        [&](int ms) {
          sub_.set(zmq::sockopt::rcvtimeo, ms);
          return unless_interrupted([&] {
            const StatusOr<bool> received = client::receive_result(sub_, r);
            if (!received.ok()) bad = received.status();
            // Topics are prefixes: "cam1" also gets "cam10".
            return !received.ok() || (*received && (stream_.empty() || r.topic == stream_));
          });
        },
        timeout_s);
    throw_if_error(bad);
    if (!got) return std::nullopt;
    decode_checked(r);
    return result_dict(r);
  }

  void close() { sub_.close(); }

 private:
  std::string stream_;
  zmq::context_t ctx_{1};
  zmq::socket_t sub_;
};

client::CurveClientOptions curve_of(const std::string& server_key, const std::string& key_file) {
  client::CurveClientOptions c;
  c.server_key = server_key;
  c.key_file = key_file;
  return c;
}

}  // namespace

void bind_client(pyb::module_& m) {
  // Documented where fq/_client.py wraps them.
  pyb::class_<Producer>(m, "Producer")
      .def(pyb::init([](const std::string& endpoint, const std::string& stream, uint32_t chunks,
                        int position_bits, int encode_speed, const std::string& compute,
                        const pyb::dict& overrides, const std::string& server_key,
                        const std::string& key_file) {
             return new Producer(endpoint,
                                 frame_spec(stream, chunks, position_bits, encode_speed, compute, overrides),
                                 curve_of(server_key, key_file));
           }),
           "endpoint"_a, "stream"_a, "chunks"_a, "position_bits"_a, "encode_speed"_a, "compute"_a,
           "overrides"_a, "server_key"_a, "key_file"_a)
      .def("send", &Producer::send, "V"_a, "F"_a, "timeout_s"_a)
      .def_property_readonly("sequence", &Producer::sequence)
      .def("close", &Producer::close);
  pyb::class_<Consumer>(m, "Consumer")
      .def(
          pyb::init([](const std::string& endpoint, const std::optional<std::string>& stream,
                       const std::string& server_key, const std::string& key_file, double connect_timeout_s) {
            return new Consumer(endpoint, stream, curve_of(server_key, key_file), connect_timeout_s);
          }),
          "endpoint"_a, "stream"_a, "server_key"_a, "key_file"_a, "connect_timeout_s"_a)
      .def("recv", &Consumer::recv, "timeout_s"_a)
      .def("close", &Consumer::close);
}

}  // namespace fq::py
