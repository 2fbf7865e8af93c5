// The three CPU/engine stages of the pipeline (see pipeline.h).
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <exception>

#include "common/thread_pool.h"
#include "core/mesh_checks.h"
#include "core/parallel_for.h"
#include "daemon/pipeline/label_tracks.h"
#include "daemon/pipeline/pipeline.h"
#include "daemon/pipeline/work_budget.h"
#include "daemon/stream/stream.h"
#include "daemon/stream/stream_history.h"
#include "wire/draco_budget.h"
#include "wire/frame_codec.h"
#include "wire/header_codec.h"

namespace fq::daemon {
namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// Runs one stage of one frame; a fault (exception) becomes that frame's error, so that
// the daemon keeps serving the next frames.
template <class Fn>
Status guarded(const char* stage, Fn&& fn) {
  try {
    return fn();
  } catch (const std::exception& e) {
    return {StatusCode::kInternal, std::string(stage) + " fault: " + e.what()};
  }
}

// Threads for one frame's chunks: every core. They come from the shared pool, which never
// runs more threads than the cores however many frames are in decode or encode at once (the
// decode and encode worker counts), so a lone 4M-triangle frame gets the whole host: on an
// H100 host (16 cores) igea_x16's decode took 63-68 ms on 8 threads and 33-40 ms on 16.
int frame_threads(size_t chunks) {
  return std::max(1, std::min<int>(hardware_threads(), static_cast<int>(chunks)));
}

// Chunks of a result. A number in the stream's settings is taken as it is. "same" (0) keeps
// the input's count; a POSITIONS result, whose chunks are only ranges of vertex ids that a
// consumer concatenates, is cut into more when that lets more cores encode it (at least
// kPositionsPerChunk vertices a chunk): a chunk is encoded on one thread, so on an H100 host
// (16 cores) the dragon's 8-chunk result took one chunk's time, 9 ms of a 20 ms frame.
constexpr uint32_t kPositionsPerChunk = 16384;
uint32_t result_chunks(const FrameJob& f, uint32_t vertices) {
  if (f.settings.output.chunks > 0) return f.settings.output.chunks;
  const uint32_t same = std::max(1u, f.header.chunk_count());
  if (f.settings.output.form == ResultForm::kMesh) return same;
  const auto cores = static_cast<uint32_t>(hardware_threads());
  return std::min(wire::kMaxChunks, std::max(same, std::min(cores, vertices / kPositionsPerChunk)));
}

// Whether a MESH result of `chunks` chunks can be cut as its input was: same count, and every
// input chunk held triangles (a plain Draco mesh or fq's own chunks always do).
bool same_cut(const std::vector<uint32_t>& chunk_triangles, uint32_t chunks) {
  return chunk_triangles.size() == chunks &&
         std::find(chunk_triangles.begin(), chunk_triangles.end(), 0u) == chunk_triangles.end();
}

// The stream's settings with the frame's own overrides and compute mode applied.
Status resolve_settings(FrameJob& f) {
  FQ_RETURN_IF_ERROR(wire::apply_overrides(f.header.params(), f.settings.params));
  FQ_RETURN_IF_ERROR(wire::apply_compute(f.header.compute(), f.settings.params));
  if (Status s = fq::validate(f.settings.params); !s.ok())
    return invalid_argument("invalid parameters: " + s.message());
  return {};
}

Status decode(FrameJob& f, const Caps& caps) {
  std::vector<std::string_view> views;
  for (const zmq::message_t& m : f.chunks) views.emplace_back(m.data<char>(), m.size());
  // Counts are checked before Draco sees the bytes: it allocates for what a chunk declares.
  const wire::ChunkBudget budget{caps.max_vertices};
  for (size_t i = 0; i < views.size(); ++i)
    if (Status s = wire::check_chunk_budget(views[i], budget); !s.ok())
      return invalid_input("chunk " + std::to_string(i) + ": " + s.message());
  wire::CodecOptions opt;
  opt.threads = frame_threads(views.size());
  FQ_RETURN_IF_ERROR(
      wire::decode_frame(views, f.header.vertex_count(), opt, f.mesh, nullptr, &f.chunk_triangles));
  f.chunks.clear();
  if (f.mesh.num_vertices() > caps.max_vertices)
    return invalid_input("frame has " + std::to_string(f.mesh.num_vertices()) +
                         " vertices, over the cap of " + std::to_string(caps.max_vertices));
  // decode_frame checked every index; Draco's positions may still be Inf or NaN (a forged
  // chunk's quantization, a plain mesh's raw floats), so only they are scanned again.
  FQ_RETURN_IF_ERROR(check_mesh_counts(f.mesh.view()));
  const uint64_t coordinates = 3 * uint64_t(f.mesh.num_vertices());
  const uint64_t bad = first_non_finite(f.mesh.positions.data(), coordinates);
  return mesh_faults(f.mesh.view(), bad == coordinates ? kNone : bad, kNone);
}

// One frame on `engine` under the time limit, the stop flag and the slots' yield request; a
// stopped frame's error says which of the three stopped it.
Status run_engine(Pipeline& p, Engine& engine, FrameJob& f, const YieldRequest& yield) {
  const double limit_s = p.caps.get()->engine_time_limit_s;
  const auto deadline =
      limit_s > 0 ? CancelToken::Clock::now() + std::chrono::duration_cast<CancelToken::Clock::duration>(
                                                    std::chrono::duration<double>(limit_s))
                  : CancelToken::Clock::time_point::max();
  f.deadline = deadline;
  const CancelToken token(&p.cancel_engines, deadline, &yield);
  engine.set_cancel_token(&token);
  Status s = with_history(*f.stream, f.arrival, f.settings.params, engine, [&] {
    return guarded("engine", [&] { return engine.process(f.mesh.view(), f.settings.params, f.result); });
  });
  engine.set_cancel_token(nullptr);
  if (s.ok() && f.result.history_reset) f.stream->count(&StreamCounters::temporal_resets);
  if (s.ok() && f.result.ids_refused) f.stream->count(&StreamCounters::ids_refused);
  if (s.code() != StatusCode::kCancelled) return s;
  if (token.stopped())
    return {StatusCode::kCancelled,
            "cancelled: fqd is stopping (caps.stop_grace_s passed before the frame finished)"};
  if (token.yield_due()) {
    f.stream->count(&StreamCounters::preempted);
    f.preempted = true;
    return {StatusCode::kCancelled,
            "preempted: the engine stopped the frame, which could not meet its budget, so that another "
            "stream's frame could meet its own (see fqd's preemption rule in docs/DAEMON.md)"};
  }
  f.stream->count(&StreamCounters::time_limited);
  return {StatusCode::kCancelled,
          fmt::format("time_limit: the engine stopped the frame after caps.engine_time_limit_s "
                      "= {} s (its parameters fit max_neighbour_work but it ran too long)",
                      limit_s)};
}

}  // namespace

void Pipeline::fail(FramePtr frame, Status why) {
  fail_log.log(spdlog::level::warn, "stream '{}' frame {}: {}", frame->stream_id, frame->header.sequence(),
               why.message());
  frame->error = std::move(why);
  publish_queue.push(std::move(frame));
}

namespace {

// A frame from a producer without CURVE that failed to decode: refused and dropped, as the
// ingest drops junk (ingest.cpp), counted under its stream (which the frame's well-formed
// header made) so that the stream's counters still add up.
void drop_undecodable(Pipeline& p, FramePtr f, const Status& why) {
  f->stream->count(&StreamCounters::refused);
  p.registry.refusals().add(Refusal::kUndecodable);
  p.refusal_log.log(spdlog::level::warn,
                    "dropped frame {} of stream '{}' from a producer without CURVE ({}): {}",
                    f->header.sequence(), f->stream_id, refusal_name(Refusal::kUndecodable), why.message());
  p.recycle(*f);
}

}  // namespace

void Pipeline::recycle(FrameJob& f) {
  results.release(std::move(f.result));
  meshes.release(std::move(f.mesh));
}

void run_decode_worker(Pipeline& p) {
  while (auto item = p.decode_queue.pop()) {
    const CpuScope cpu(p.stage_cpu[CpuStage::kDecode]);
    FramePtr f = std::move(*item);
    // Decoding a frame that is already too old would be wasted work under overload.
    if (is_stale(f->receive_ns, wall_ns(), f->settings.budget_ms)) {
      p.decode_queue.decoded(*f);
      f->stream->count(&StreamCounters::dropped_stale);
      p.drop_log.log(spdlog::level::debug, "stream '{}' frame {}: stale before decode", f->stream_id,
                     f->header.sequence());
      continue;
    }
    const auto t0 = std::chrono::steady_clock::now();
    f->mesh = p.meshes.acquire(wall_ns());
    const std::shared_ptr<const Caps> caps = p.caps.get();
    Status s = guarded("decode", [&] { return decode(*f, *caps); });
    p.decode_queue.decoded(*f);  // its decoder is free for the queue's next frame
    if (!s.ok() && !f->authenticated) {
      drop_undecodable(p, std::move(f), s);
      continue;
    }
    if (s.ok()) s = resolve_settings(*f);
    if (s.ok()) s = check_work_budget(f->settings.params, f->mesh.num_vertices(), caps->max_neighbour_work);
    f->timings.push_back({"decode", ms_since(t0)});
    if (!s.ok()) {
      p.fail(std::move(f), s);
      continue;
    }
    // Charged again for what decode made of it: the header's vertex count may have been low.
    if (!charge_frame(*f)) {
      p.drop_log.log(spdlog::level::warn,
                     "stream '{}' frame {}: dropped after decode, over caps.memory_budget_mb", f->stream_id,
                     f->header.sequence());
      p.recycle(*f);
      continue;
    }
    f->decoded_ns = wall_ns();
    if (FramePtr loser = p.slots.offer(std::move(f))) {
      loser->stream->count(&StreamCounters::superseded);
      p.recycle(*loser);
      p.drop_log.log(spdlog::level::debug, "stream '{}' frame {}: superseded", loser->stream_id,
                     loser->header.sequence());
    }
  }
}

void run_engine_worker(Pipeline& p, Engine& engine) {
  FramePtr f;
  std::vector<FramePtr> stale;
  int64_t last_frame_ns = wall_ns();
  bool holding = false;  // the engine keeps a frame's buffers
  YieldRequest yield;    // set by the slots while a frame of this worker's runs
  while (p.slots.take(f, stale, std::chrono::seconds(1), &yield)) {
    const CpuScope cpu(p.stage_cpu[CpuStage::kEngine]);
    // Idle as long as the pools: the engine's buffers (host or device) go back too.
    const auto idle_ns = static_cast<int64_t>(p.caps.get()->pool_idle_s * 1e9);
    if (!f && stale.empty() && holding && wall_ns() - last_frame_ns >= idle_ns) {
      engine.release_memory();
      holding = false;
    }
    for (FramePtr& s : stale) {
      s->stream->count(&StreamCounters::dropped_stale);
      p.recycle(*s);
      p.drop_log.log(spdlog::level::debug, "stream '{}' frame {}: dropped stale", s->stream_id,
                     s->header.sequence());
    }
    stale.clear();
    if (!f) continue;
    f->timings.push_back({"wait", ms_between(f->decoded_ns, wall_ns())});
    f->engine = engine.name();
    f->result = p.results.acquire(wall_ns());
    const auto t0 = std::chrono::steady_clock::now();
    const Status s = run_engine(p, engine, *f, yield);
    const double total = ms_since(t0);
    p.slots.finish(&yield, total * 1e-3, f->preempted);
    p.engine_busy.add(&engine, static_cast<uint64_t>(total * 1e6));
    last_frame_ns = wall_ns();
    holding = true;
    for (const PassTiming& t : f->result.timings) f->timings.push_back({"engine." + t.name, t.ms});
    f->timings.push_back({"engine", total});
    if (!s.ok())
      p.fail(std::move(f), s);
    else
      p.encode_queue.push(std::move(f));
  }
}

void run_encode_worker(Pipeline& p) {
  while (auto item = p.encode_queue.pop()) {
    const CpuScope cpu(p.stage_cpu[CpuStage::kEncode]);
    FramePtr f = std::move(*item);
    const MeshView view{f->result.positions.data(), f->mesh.num_vertices(), f->mesh.triangles.data(),
                        f->mesh.num_triangles()};
    const uint32_t chunks = result_chunks(*f, view.num_vertices);
    wire::CodecOptions opt;
    opt.position_bits = f->settings.output.position_bits;
    opt.encode_speed = f->settings.output.encode_speed;
    opt.decode_speed = f->settings.output.decode_speed;
    opt.threads = frame_threads(chunks);
    // Cluster ids are matched to the stream's previous frame here, on the encode pool, not
    // on the engine worker: the engine (a GPU) takes the next frame meanwhile. With 4 bunny
    // streams at 30 fps on an H100 host (16 cores), tracking (p50 11-16 ms a frame) on the
    // engine worker held the GPU engine and the streams fell to 6.6 fps; here they keep 29 fps.
    // Tracking reads and writes only the labels and the encoder only the positions (labels
    // travel in the ResultHeader), so both run at once when a pool thread is free.
    Status tracked, s;
    double track_ms = 0, encode_ms = 0;
    ThreadPool::shared().run(2, 2, [&](size_t begin, size_t end, size_t) {
      for (size_t job = begin; job < end; ++job) {
        const auto t0 = std::chrono::steady_clock::now();
        if (job == 0) {
          // Under the frame's own time limit and the stop: a frame whose tracking is cut is
          // published with the engine's numbering (its clusters are right, their ids are not
          // the previous frame's), counted `untracked`, rather than lost.
          const CpuScope track_cpu(p.stage_cpu[CpuStage::kTrackIds]);
          const CancelToken token(&p.cancel_engines, f->deadline);
          tracked = guarded("track_ids", [&] {
            if (Status cut = track_labels(*f, hardware_threads(), token); !cut.ok()) {
              f->stream->count(&StreamCounters::untracked);
              p.fail_log.log(spdlog::level::warn,
                             "stream '{}' frame {}: published with untracked cluster ids: {}", f->stream_id,
                             f->header.sequence(),
                             token.stopped() ? std::string("fqd is stopping")
                                             : "tracking passed caps.engine_time_limit_s");
            }
            return Status{};
          });
          track_ms = ms_since(t0);
          continue;
        }
        s = guarded("encode", [&] {
          if (f->settings.output.form == ResultForm::kMesh) {
            // Cut as the input was when the chunk counts agree: the result keeps the input's
            // connectivity, and decode laid its triangles out chunk after chunk.
            if (same_cut(f->chunk_triangles, chunks))
              return wire::encode_frame_as(view, nullptr, f->chunk_triangles, opt, f->out_chunks);
            return wire::encode_frame(view, nullptr, std::max(1u, chunks), opt, f->out_chunks);
          }
          return wire::encode_positions(view.positions, view.num_vertices, std::max(1u, chunks), opt,
                                        f->out_chunks);
        });
        encode_ms = ms_since(t0);
      }
    });
    if (s.ok()) s = tracked;
    p.slots.charge(*f->stream, track_ms * 1e-3);  // tracking is engine time of the stream too
    if (f->settings.params.cluster) f->timings.push_back({"track_ids", track_ms});
    f->timings.push_back({"encode", encode_ms});
    if (!s.ok())
      p.fail(std::move(f), s);
    else
      p.publish_queue.push(std::move(f));
  }
}

}  // namespace fq::daemon
