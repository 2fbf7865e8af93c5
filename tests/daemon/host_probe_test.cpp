// fqstreambench's host probe (clients/fqstreambench/host_probe.h): /proc/stat's CPU line read
// as the kernel writes it, and a probe that counts its wake-ups and how late they came.
#include "clients/fqstreambench/host_probe.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

namespace fq::bench {
namespace {

TEST(HostProbe, ReadsTheCpuLineOfProcStat) {
  // user nice system idle iowait irq softirq steal guest guest_nice
  const auto t = parse_cpu_line("cpu  4705 356 584 3699 23 23 0 7 11 0");
  ASSERT_TRUE(t.has_value());
  EXPECT_EQ(t->total, 4705u + 356 + 584 + 3699 + 23 + 23 + 0 + 7);  // guest is inside user
  EXPECT_EQ(t->steal, 7u);
  EXPECT_FALSE(parse_cpu_line("cpu0 1 2 3 4 5 6 7 8").has_value());  // one CPU, not the total
  EXPECT_FALSE(parse_cpu_line("intr 1 2 3 4 5 6 7 8").has_value());
  EXPECT_FALSE(parse_cpu_line("cpu 1 2 3 4 5 6").has_value());  // a kernel without steal
  EXPECT_FALSE(parse_cpu_line("").has_value());
}

TEST(HostProbe, CountsItsWakeupsAndHowLateTheyCame) {
  HostProbe probe;
  probe.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  const HostQuiet q = probe.stop();
  // At most one wake-up per millisecond asked for; a loaded machine may give far fewer.
  EXPECT_GE(q.wakeups, 5u);
  EXPECT_LE(q.wakeups, 201u);
  EXPECT_GE(q.late_p50_ms, 0.0);
  EXPECT_LE(q.late_p50_ms, q.late_p99_ms);
  EXPECT_LE(q.late_p99_ms, q.late_max_ms);
  EXPECT_LE(q.late_over_5ms, q.wakeups);
  EXPECT_GE(q.steal_share, 0.0);  // this machine has /proc/stat
  EXPECT_LE(q.steal_share, 1.0);
  // A second run starts afresh.
  probe.start();
  const HostQuiet again = probe.stop();
  EXPECT_LE(again.wakeups, 2u);
}

}  // namespace
}  // namespace fq::bench
