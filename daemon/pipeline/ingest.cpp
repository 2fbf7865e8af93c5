#include "daemon/pipeline/ingest.h"

#include <malloc.h>
#include <spdlog/spdlog.h>

#include <zmq_addon.hpp>

#include "daemon/pipeline/daemon_threads.h"
#include "wire/frame_codec.h"
#include "wire/header_codec.h"

namespace fq::daemon {
namespace {

// Bytes and parts are bounded as the message is received (ingest_one).
Status check_framing(const std::vector<zmq::message_t>& parts) {
  if (parts.size() < 3)
    return invalid_input("expected [stream id][FrameHeader][draco chunk]..., got " +
                         std::to_string(parts.size()) + " part(s)");
  return {};
}

Status check_header(const wire::FrameHeader& h, const std::string& topic, size_t chunk_parts,
                    const Caps& caps) {
  if (h.stream_id() != topic)
    return invalid_input("header stream id '" + printable_id(h.stream_id()) + "' does not match the topic '" +
                         printable_id(topic) + "'");
  if (h.chunk_count() != chunk_parts)
    return invalid_input("header says " + std::to_string(h.chunk_count()) + " chunk(s), message has " +
                         std::to_string(chunk_parts));
  if (h.vertex_count() > caps.max_vertices)
    return invalid_input("frame has " + std::to_string(h.vertex_count()) + " vertices, over the cap of " +
                         std::to_string(caps.max_vertices));
  return {};
}

}  // namespace

// Freed buffers go back to the allocator's arenas, which keep the pages. They are handed
// back to the system (malloc_trim, at most every 5 s) when it pays: after a pool freed a
// buffer far larger than its frame needed (a small frame after a huge one), or once frames
// stopped for 5 s. Not on a timer while frames flow: each trim made the next frames fault
// their pages in again (tens of MB for a 4M-triangle frame).
void Ingest::hand_back_free_pages(int64_t now) {
  constexpr int64_t kPeriod = 5'000'000'000;
  if (next_arrival_ != arrival_seen_) {
    arrival_seen_ = next_arrival_;
    arrival_seen_ns_ = now;
  }
  if (now - last_malloc_trim_ns_ < kPeriod) return;
  const uint64_t oversized = p_.results.oversized_freed() + p_.meshes.oversized_freed();
  const bool shrank = oversized != oversized_at_trim_;
  const bool went_idle = next_arrival_ != arrival_at_trim_ && now - arrival_seen_ns_ >= kPeriod;
  if (!shrank && !went_idle) return;
  last_malloc_trim_ns_ = now;
  oversized_at_trim_ = oversized;
  arrival_at_trim_ = next_arrival_;
  malloc_trim(0);
}

// Streams without frames for caps.stream_idle_s give their slot back (at most one sweep
// a second; the ingest socket's receive timeout wakes the thread when nothing arrives).
void Ingest::expire_idle_streams() {
  const int64_t now = wall_ns();
  if (now - last_sweep_ns_ < 1'000'000'000) return;
  last_sweep_ns_ = now;
  const std::shared_ptr<const Caps> caps = p_.caps.get();
  const auto idle_ns = static_cast<int64_t>(caps->pool_idle_s * 1e9);
  p_.results.trim(now, idle_ns);
  p_.meshes.trim(now, idle_ns);
  hand_back_free_pages(now);
  // The codec's buffers (kept per use, not per thread) go back once frames have stopped as
  // long; their pages at the next trim.
  if (now - arrival_seen_ns_ >= idle_ns) wire::release_memory();
  // One erase each: what the pipeline keeps for a stream lives in its Stream, freed with the
  // last of its frames still in flight.
  for (const std::string& id : p_.registry.expire_idle(now, caps->stream_idle_s)) {
    p_.expiry_log.log(spdlog::level::info, "stream '{}' expired after {} s without frames", id,
                      caps->stream_idle_s);
  }
}

namespace {

// A message refused before any stream state exists for it: counted by reason, logged at a
// bounded rate, and answered with an error result under the (escaped) topic so that the
// producer's operator can see why.
FramePtr refuse(FramePtr f, Refusal why, Status message, Pipeline& p) {
  p.registry.refusals().add(why);
  p.refusal_log.log(spdlog::level::warn, "refused a frame for stream '{}' ({}): {}", f->stream_id,
                    refusal_name(why), message.message());
  f->error = std::move(message);
  f->refused = true;
  return f;
}

// Junk from a producer without CURVE (a malformed or oversized message, an undecodable frame):
// counted by reason and logged at a bounded rate, but neither published nor counted as any
// stream's error, since whoever can connect could otherwise put errors on every stream.
FramePtr drop_junk(const FrameJob& f, Refusal why, const Status& message, Pipeline& p) {
  p.registry.refusals().add(why);
  p.refusal_log.log(spdlog::level::warn,
                    "dropped a message for stream '{}' from a producer without CURVE ({}): {}",
                    printable_id(f.stream_id), refusal_name(why), message.message());
  return nullptr;
}

// Hands an admitted job on: refusals and errors to the publisher, frames to the decoders
// (null: nothing).
void queue_admitted(FramePtr f, Pipeline& p) {
  if (!f) return;  // junk dropped unanswered (counted and logged)
  if (f->refused) {
    p.publish_queue.push(std::move(f));  // logged (rate-limited) and counted at refusal
  } else if (!f->error.ok()) {
    const Status why = f->error;
    p.fail(std::move(f), why);
  } else {
    // An older frame of the stream still waiting gives its place up; a full queue sheds the
    // newest place of the connection holding most (decode_queue.h). Only a frame over the
    // byte bound waits here (for an empty queue): then ZeroMQ's marks hold the producers back.
    // A frame that does not fit the memory budget once idle /latest copies and other streams'
    // histories are gone is dropped here, counted (memory_account.h).
    if (!charge_frame(*f)) {
      p.drop_log.log(spdlog::level::warn, "stream '{}' frame {}: dropped, over caps.memory_budget_mb",
                     f->stream_id, f->header.sequence());
      return;
    }
    std::vector<FramePtr> dropped;
    p.decode_queue.push(std::move(f), dropped);
    for (const FramePtr& d : dropped) {
      d->stream->count(&StreamCounters::superseded);
      p.drop_log.log(spdlog::level::debug, "stream '{}' frame {}: superseded before decode", d->stream_id,
                     d->header.sequence());
    }
  }
}

}  // namespace

FramePtr Ingest::reject(FramePtr f, const std::string& topic, Refusal why, Status s) {
  if (!f->authenticated) return drop_junk(*f, why, s, p_);
  if ((f->stream = p_.registry.find(topic))) {
    f->settings = f->stream->settings();
    f->stream->count(&StreamCounters::frames_in);
    f->arrival = next_arrival_++;
    f->error = std::move(s);
    return f;
  }
  return refuse(std::move(f), why, std::move(s), p_);
}

FramePtr Ingest::admit_message(std::vector<zmq::message_t>& parts) {
  auto f = std::make_unique<FrameJob>();
  f->receive_ns = wall_ns();
  f->authenticated = p_.keys != nullptr;  // admit_sender let only allowed keys through
  const std::shared_ptr<const Caps> live = p_.caps.get();
  const Caps& caps = *live;
  const std::string topic = parts.empty() ? std::string() : parts[0].to_string();
  f->stream_id = printable_id(topic, caps.max_stream_id_bytes);
  Refusal why = Refusal::kBadStreamId;
  if (Status s = check_stream_id(topic, caps, &why); !s.ok())
    return refuse(std::move(f), why, std::move(s), p_);
  f->stream_id = topic;
  // Only a well-formed frame can make a stream: junk never takes a slot.
  Status s = check_framing(parts);
  if (s.ok())
    s = wire::parse_frame_header(std::string_view(parts[1].data<char>(), parts[1].size()), f->header);
  if (s.ok()) s = check_header(f->header, f->stream_id, parts.size() - 2, caps);
  if (!s.ok()) return reject(std::move(f), topic, Refusal::kMalformed, std::move(s));
  f->stream = p_.registry.admit(topic, f->receive_ns);
  if (!f->stream)
    return refuse(
        std::move(f), Refusal::kTooManyStreams,
        invalid_input("too many streams (caps.max_streams = " + std::to_string(caps.max_streams) + ")"), p_);
  f->settings = f->stream->settings();
  f->arrival = next_arrival_++;
  f->stream->count(&StreamCounters::frames_in);
  for (size_t i = 2; i < parts.size(); ++i) f->chunks.push_back(std::move(parts[i]));
  return f;
}

// Its parts past the bounds were already dropped; refused under its (escaped) topic when the
// topic is no valid stream id.
FramePtr Ingest::refuse_oversized(const std::vector<zmq::message_t>& parts, Received why) {
  auto f = std::make_unique<FrameJob>();
  f->receive_ns = wall_ns();
  f->authenticated = p_.keys != nullptr;
  const std::string topic = parts[0].to_string();
  const bool valid = check_stream_id(topic, *p_.caps.get()).ok();
  f->stream_id = valid ? topic : printable_id(topic);
  const std::string what =
      why == Received::kTooManyParts
          ? "more than " + std::to_string(2 + wire::kMaxChunks) + " parts"
          : "more than caps.max_frame_bytes = " + std::to_string(p_.config.caps.max_frame_bytes) + " bytes";
  Status s = invalid_input("message of " + what);
  if (!valid) return refuse(std::move(f), Refusal::kOversized, std::move(s), p_);
  return reject(std::move(f), topic, Refusal::kOversized, std::move(s));
}

bool Ingest::ingest_one(zmq::socket_t& socket, zmq::recv_flags flags, const std::set<std::string>* assigned) {
  std::vector<zmq::message_t> parts;
  const MessageBounds bounds{2 + wire::kMaxChunks, p_.config.caps.max_frame_bytes};
  const Received got = receive_bounded(socket, parts, bounds, flags);
  if (got == Received::kNothing) return false;
  if (!admit_sender(parts[0], p_.keys, p_.registry.refusals()))
    return true;  // a key revoked since it connected
  // Another fqd's stream (a SUB topic matches by prefix): not ours to count.
  if (assigned && !assigned->empty() && !assigned->count(parts[0].to_string())) return true;
  // The connection, for the decode queue's turns; read before the parts move into the frame.
  const int connection = zmq_msg_get(parts[0].handle(), ZMQ_SRCFD);
  FramePtr f = got == Received::kMessage ? admit_message(parts) : refuse_oversized(parts, got);
  if (f) f->connection = connection;  // null: junk dropped unanswered
  queue_admitted(std::move(f), p_);
  return true;
}

Ingest::Ingest(zmq::socket_t pull, Pipeline& p, std::unique_ptr<SubProducers> producers,
               std::set<std::string> assigned)
    : pull_(std::move(pull)), p_(p), producers_(std::move(producers)), assigned_(std::move(assigned)) {}

Ingest::~Ingest() { join(); }

void Ingest::start() {
  thread_ = std::thread([this] {
    name_this_thread("ingest");
    if (producers_)
      run_with_producers();
    else
      run_pull();
  });
}

void Ingest::join() {
  if (thread_.joinable()) thread_.join();
}

void Ingest::run_pull() {
  for (;;) {
    // Per message, so the account stays current; a blocked receive costs no CPU time.
    const CpuScope cpu(p_.stage_cpu[CpuStage::kIngest]);
    expire_idle_streams();
    try {
      ingest_one(pull_, zmq::recv_flags::none);  // nothing after the receive timeout
    } catch (const zmq::error_t& e) {
      if (e.num() == ETERM) break;
      errors_.log(spdlog::level::err, "ingest: {}", e.what());
    }
  }
  pull_.close();
}

}  // namespace fq::daemon
