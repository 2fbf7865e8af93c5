// What the periodic [stats] log says beyond the counts: the late warning's hint names the lever
// that costs the most engine time (clustering: compute = "filter"), and each reason that lost a
// stream frames or results gets a [drops] line saying what it means and what to change.
#include <gtest/gtest.h>

#include <regex>

#include "daemon/control/drop_reasons.h"
#include "daemon/control/late_warning.h"
#include "daemon/control/stats_log.h"

namespace fq::daemon {
namespace {

// Stage medians as a frame's timings would give them.
std::map<std::string, Percentiles> medians(std::initializer_list<std::pair<const char*, double>> p50s) {
  std::map<std::string, Percentiles> stages;
  for (const auto& [name, ms] : p50s) stages[name].p50_ms = ms;
  return stages;
}

TEST(LateHint, ClusteringMostOfTheEngineTimeNamesComputeFilter) {
  // filter_and_cluster in one run: score, link and modes are 300 of the engine's 400 ms.
  const auto one_run = medians({{"engine", 400},
                                {"engine.grid", 20},
                                {"engine.diffusion", 60},
                                {"engine.update", 20},
                                {"engine.score", 150},
                                {"engine.link", 120},
                                {"engine.modes", 30},
                                {"wait", 1}});
  EXPECT_DOUBLE_EQ(clustering_p50_ms(one_run), 300);
  const std::string hint = late_hint(one_run, 100);
  EXPECT_NE(hint.find("compute = \"filter\""), std::string::npos) << hint;
  EXPECT_NE(hint.find("clustering is 300 of the engine's 400 ms a frame"), std::string::npos) << hint;
  // Clustering on the filtered mesh: the geometry and clustering runs and cluster control count whole.
  const auto added_runs = medians({{"engine", 500},
                                   {"engine.update", 100},
                                   {"engine.geometry.diffusion", 150},
                                   {"engine.cluster.score", 150},
                                   {"engine.cluster_control", 50}});
  EXPECT_DOUBLE_EQ(clustering_p50_ms(added_runs), 350);
  EXPECT_NE(late_hint(added_runs, 100).find("compute = \"filter\""), std::string::npos);
  // Waiting for an engine whose frames are mostly clustering: the same lever first.
  const auto waiting = medians({{"engine", 40}, {"engine.score", 30}, {"wait", 200}});
  EXPECT_NE(late_hint(waiting, 100)
                .find("frames wait for an engine, and clustering is 30 of the engine's 40 ms a frame"),
            std::string::npos)
      << late_hint(waiting, 100);
}

TEST(LateHint, OtherwiseTodaysLever) {
  // Filtering is most of the engine time: the budget, the sigmas or a GPU.
  const auto filtering = medians({{"engine", 400}, {"engine.diffusion", 300}, {"engine.score", 80}});
  EXPECT_EQ(
      late_hint(filtering, 100),
      "the engine alone takes longer than the budget: raise budget_ms, lower the sigmas or use a GPU engine");
  // Exactly half is not most.
  EXPECT_EQ(late_hint(medians({{"engine", 400}, {"engine.link", 200}}), 100).find("compute"),
            std::string::npos);
  EXPECT_EQ(late_hint(medians({{"engine", 40}, {"wait", 200}}), 100),
            "frames wait for an engine: more frames than the engines serve (lower the rate, or add engines)");
  // The engine within the budget and no wait: clustering is not what makes results late.
  EXPECT_EQ(late_hint(medians({{"engine", 40}, {"engine.score", 39}, {"wait", 1}}), 100),
            "decode, encode or publishing take the rest of the budget");
  // No timings at all (a stream of error results): no division by zero, today's wording.
  EXPECT_EQ(late_hint({}, 100), "decode, encode or publishing take the rest of the budget");
}

TEST(StatsLog, ADropsLinePerReasonThatCountedSayingWhatItMeansAndWhatToDo) {
  std::map<std::string, StreamCounters> previous;
  StreamSnapshot s;
  s.stream_id = "cam0";
  s.counters.frames_in = 10;
  previous["cam0"] = s.counters;
  s.counters.frames_in = 60;
  s.counters.frames_out = 10;
  s.counters.superseded = 41;
  s.counters.dropped_stale = 3;
  s.counters.errors = 6;
  s.counters.preempted = 2;
  s.counters.time_limited = 4;
  s.counters.subscriber_overflows = 1;
  const std::vector<std::string> lines = StatsLog::lines({s}, 10.0, previous);
  ASSERT_EQ(lines.size(), 6u);
  EXPECT_EQ(lines[0].rfind("[stats] stream=cam0 fps=1.0 ", 0), 0u) << lines[0];
  const char* reasons[] = {"superseded count=41", "stale count=3", "preempted count=2",
                           "time_limited count=4", "subscriber_overflow count=1"};
  for (size_t i = 0; i < 5; ++i) {
    // [drops] stream=ID reason=NAME count=N: what happened -> what to change
    const std::regex form(std::string("\\[drops\\] stream=cam0 reason=") + reasons[i] + ": [^>]+ -> \\S.+");
    EXPECT_TRUE(std::regex_match(lines[i + 1], form)) << lines[i + 1];
  }
  EXPECT_NE(lines[1].find("lower the rate"), std::string::npos) << lines[1];
  EXPECT_NE(lines[2].find("budget_ms"), std::string::npos) << lines[2];
  EXPECT_NE(lines[4].find("caps.engine_time_limit_s"), std::string::npos) << lines[4];
  EXPECT_NE(lines[5].find("caps.max_subscriber_results"), std::string::npos) << lines[5];
  // The next interval without drops: the [stats] line alone.
  s.counters.frames_in = 70;
  s.counters.frames_out = 20;
  EXPECT_EQ(StatsLog::lines({s}, 10.0, previous).size(), 1u);
}

TEST(DropReasons, EveryReasonSaysWhatAndWhatToDo) {
  for (const DropReason& r : drop_reasons()) {
    EXPECT_GT(std::string(r.meaning).size(), 20u) << r.name;
    EXPECT_GT(std::string(r.action).size(), 20u) << r.name;
    EXPECT_EQ(std::string(r.meaning).find("->"), std::string::npos) << r.name << ": the line's separator";
  }
}

}  // namespace
}  // namespace fq::daemon
