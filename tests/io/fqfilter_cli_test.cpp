// The built fqfilter binary, run as a user would: exit codes, error lines, JSON, folders.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/param_table.h"
#include "io/mesh_io.h"
#include "tests/io/fqfilter_run.h"
#include "tests/io/io_test_util.h"
#include "tests/support/mesh_dir.h"

namespace {

namespace fs = std::filesystem;
using fq::test::run_fqfilter;
using fq::test::RunResult;

const std::string kFandisk = std::string(FQ_DATA_DIR) + "/fandisk.ply";

size_t count_lines(const std::string& s) { return std::count(s.begin(), s.end(), '\n'); }

/// Every number anywhere in `j` is finite (NaN would be serialized as null, not a number).
void expect_finite_numbers(const nlohmann::json& j, const std::string& where = "") {
  if (j.is_number()) {
    EXPECT_TRUE(std::isfinite(j.get<double>())) << where;
  } else if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) expect_finite_numbers(it.value(), where + "." + it.key());
  } else if (j.is_array()) {
    for (size_t i = 0; i < j.size(); ++i) expect_finite_numbers(j[i], where + "[" + std::to_string(i) + "]");
  }
}

TEST(FqfilterCli, BadOptionIsOneErrorLine) {
  fq::test::ScratchDir dir;
  const RunResult r = run_fqfilter({kFandisk, "--no-such-option"}, dir);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--no-such-option"), std::string::npos) << r.err;
  EXPECT_EQ(count_lines(r.err), 1u) << r.err;
}

// fqfilter's parameter options come from the parameter table: every fqfilter row is an
// option of --help, with its default, and each takes its value (the --json report echoes it).
TEST(FqfilterCli, HelpListsEveryTableRow) {
  fq::test::ScratchDir dir;
  const RunResult help = run_fqfilter({"--help"}, dir);
  ASSERT_EQ(help.exit_code, 0) << help.err;
  for (const fq::ParamRow& row : fq::param_table()) {
    if (!row.on(fq::kFqfilter)) continue;
    EXPECT_NE(help.out.find("  " + row.flag() + " "), std::string::npos)
        << row.flag() << " missing from --help";
  }
  EXPECT_NE(help.out.find("--mode TEXT:{qf+,qf,bf}=qf+"), std::string::npos)
      << "the default mode is shown as configs spell it";
  const RunResult r = run_fqfilter({kFandisk, "--json", "--mode", "qf", "--cluster", "--cluster-geometry",
                                    "input", "--sigma-b", "0.5", "--min-cluster-size", "3", "--constrained"},
                                   dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json p = nlohmann::json::parse(r.out).at("params");
  EXPECT_EQ(p.at("mode"), "qf");
  EXPECT_EQ(p.at("cluster"), true);
  EXPECT_EQ(p.at("cluster_geometry"), "input");
  EXPECT_EQ(p.at("sigma_b"), 0.5);
  EXPECT_EQ(p.at("sigma_n"), 0.75) << "0 = sigma_s / 2, resolved";
  EXPECT_EQ(p.at("min_cluster_size"), 3);
  EXPECT_EQ(p.at("constrained"), true);
  EXPECT_EQ(p.at("refine"), nullptr) << "qf has no noise parameters";
}

TEST(FqfilterCli, BadValuesAreRejected) {
  fq::test::ScratchDir dir;
  const std::vector<std::vector<std::string>> cases = {{"--sigma-s", "-1"},
                                                       {"--theta", "1.5", "--cluster"},
                                                       {"--mode", "xx"},
                                                       {"--repeat", "0"},
                                                       {"--threads", "abc"},
                                                       {"--cluster-geometry", "mesh", "--cluster"},
                                                       {"--target-clusters", "-3", "--cluster"},
                                                       {"--sticky-rings", "2"},  // fqd only
                                                       {"--strength", "11"}};
  for (const auto& opt : cases) {
    std::vector<std::string> args = {kFandisk};
    args.insert(args.end(), opt.begin(), opt.end());
    const RunResult r = run_fqfilter(args, dir);
    EXPECT_NE(r.exit_code, 0) << opt[0];
    EXPECT_EQ(count_lines(r.err), 1u) << opt[0] << ": " << r.err;
  }
}

TEST(FqfilterCli, MissingInputFails) {
  fq::test::ScratchDir dir;
  const RunResult r = run_fqfilter({dir.file("missing.ply")}, dir);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("missing.ply"), std::string::npos) << r.err;
  EXPECT_EQ(count_lines(r.err), 1u) << r.err;
}

TEST(FqfilterCli, JsonOnFandisk) {
  fq::test::ScratchDir dir;
  const RunResult r = run_fqfilter(
      {kFandisk, "--engine", "cpu", "--threads", "2", "--noise", "0.2", "--seed", "5", "--cluster", "--json"},
      dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);  // throws (fails the test) if not JSON
  EXPECT_EQ(j.at("vertices").get<uint32_t>(), 6475u);
  EXPECT_EQ(j.at("triangles").get<uint32_t>(), 12946u);
  EXPECT_EQ(j.at("engine").get<std::string>(), "cpu");
  EXPECT_GT(j.at("mean_edge").get<double>(), 0.0);
  EXPECT_GE(j.at("clusters").get<uint32_t>(), 1u);
  EXPECT_GT(j.at("timings_ms").at("total").get<double>(), 0.0);
  EXPECT_FALSE(j.at("timings_ms").at("passes").empty());
  const nlohmann::json& m = j.at("metrics");
  EXPECT_GT(m.at("input").at("rmse_over_diagonal").get<double>(), 0.0);
  // Noise of 0.2 edges tilts faces by many degrees; filtering must bring them back.
  EXPECT_LT(m.at("output").at("mfne_rad").get<double>(), m.at("input").at("mfne_rad").get<double>());
  // ... and bring vertices back toward the clean surface (vertex RMSE need not drop: the
  // quadric filter slides vertices along the surface by design).
  EXPECT_LT(m.at("output").at("surface_rms_over_diagonal").get<double>(),
            m.at("input").at("surface_rms_over_diagonal").get<double>());
  expect_finite_numbers(j);
}

// The default method is qf+; with normal noise it beats the paper's filter (fandisk at
// noise 0.3 along the normals, seed 7: measured 0.090 rad against qf's 0.152), and
// --noisy-out writes exactly the mesh that was filtered.
TEST(FqfilterCli, DefaultRefinementAndNormalNoise) {
  fq::test::ScratchDir dir;
  const std::string noisy = dir.file("noisy.ply");
  const std::vector<std::string> base = {kFandisk, "--engine",          "cpu",    "--threads", "2", "--noise",
                                         "0.3",    "--noise-direction", "normal", "--seed",    "7", "--json"};
  std::vector<std::string> with_out = base;
  with_out.insert(with_out.end(), {"--noisy-out", noisy});
  std::vector<std::string> paper = base;
  paper.insert(paper.end(), {"--mode", "qf"});
  const RunResult plus = run_fqfilter(with_out, dir), qf = run_fqfilter(paper, dir);
  ASSERT_EQ(plus.exit_code, 0) << plus.err;
  ASSERT_EQ(qf.exit_code, 0) << qf.err;
  const nlohmann::json a = nlohmann::json::parse(plus.out), b = nlohmann::json::parse(qf.out);
  EXPECT_EQ(a.at("params").at("mode").get<std::string>(), "qf+");
  EXPECT_EQ(a.at("params").at("refine").at("strength").get<double>(), 1.0);
  EXPECT_EQ(a.at("params").at("refine").at("known_noise").get<double>(), 0.0);
  EXPECT_TRUE(b.at("params").at("refine").is_null());
  EXPECT_EQ(a.at("noise").at("direction").get<std::string>(), "normal");
  EXPECT_LT(a.at("metrics").at("output").at("mfne_rad").get<double>(),
            0.8 * b.at("metrics").at("output").at("mfne_rad").get<double>());
  // The noisy file, measured against the clean one, has the input error fqfilter reported.
  const RunResult again = run_fqfilter(
      {noisy, "--engine", "cpu", "--threads", "2", "--reference", kFandisk, "--mode", "qf", "--json"}, dir);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  const nlohmann::json c = nlohmann::json::parse(again.out);
  EXPECT_NEAR(c.at("metrics").at("input").at("mfne_rad").get<double>(),
              a.at("metrics").at("input").at("mfne_rad").get<double>(), 1e-6);
}

// --noise 0 with --noisy-out writes the input as the "noisy" file (a sweep starting at 0
// finds every file it asked for), the same vertices in the same order.
TEST(FqfilterCli, NoisyOutAtNoiseZeroIsTheInput) {
  fq::test::ScratchDir dir;
  const std::string noisy = dir.file("zero.ply");
  const RunResult r = run_fqfilter({kFandisk, "--noise", "0", "--noisy-out", noisy, "--quiet"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  fq::Mesh in, out;
  ASSERT_TRUE(fq::io::read_mesh(kFandisk, in).ok());
  ASSERT_TRUE(fq::io::read_mesh(noisy, out).ok()) << "nothing written at noise 0";
  EXPECT_EQ(out.positions, in.positions);
  EXPECT_EQ(out.triangles, in.triangles);
}

// The default filter on CAD input: fandisk at isotropic noise 0.2 (seed 7) well under the best
// setting of the other smoothers on the same row (0.144 rad, docs/QUALITY.md; measured 0.095),
// with the noise it estimated reported.
TEST(FqfilterCli, FandiskAtNoiseTwoTenthsBeatsThePeers) {
  fq::test::ScratchDir dir;
  const RunResult r = run_fqfilter(
      {kFandisk, "--engine", "cpu", "--threads", "2", "--noise", "0.2", "--seed", "7", "--json"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_LE(j.at("metrics").at("output").at("mfne_rad").get<double>(), 0.11);
  const nlohmann::json& noise = j.at("noise_estimate");
  EXPECT_GT(noise.at("estimated").get<double>(), 0.1);
  EXPECT_LT(noise.at("estimated").get<double>(), 0.3);
  EXPECT_EQ(noise.at("filtered_for").get<double>(), noise.at("estimated").get<double>());
  EXPECT_FALSE(noise.at("looks_clean").get<bool>());
  EXPECT_GT(noise.at("rounds").get<double>(), 1.0);
}

// A clean input is said to be clean, in one line that names the option for a full filter; it
// is filtered lightly (not returned untouched: no switch), and --known-noise filters it fully.
TEST(FqfilterCli, CleanInputIsSaidToBeClean) {
  fq::test::ScratchDir dir;
  const std::vector<std::string> base = {kFandisk, "--reference", kFandisk, "--engine",
                                         "cpu",    "--threads",   "2"};
  const RunResult human = run_fqfilter(base, dir);
  ASSERT_EQ(human.exit_code, 0) << human.err;
  EXPECT_NE(human.out.find("input looks clean"), std::string::npos) << human.out;
  EXPECT_NE(human.out.find("--known-noise"), std::string::npos);
  auto json_of = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = base;
    args.insert(args.end(), extra.begin(), extra.end());
    args.push_back("--json");
    const RunResult r = run_fqfilter(args, dir);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(r.out);
  };
  const nlohmann::json light = json_of({}), full = json_of({"--known-noise", "0.2"});
  EXPECT_TRUE(light.at("noise_estimate").at("looks_clean").get<bool>());
  EXPECT_LT(light.at("metrics").at("output").at("mfne_rad").get<double>(), 0.02);
  EXPECT_EQ(full.at("noise_estimate").at("filtered_for").get<double>(), 0.2f);
  EXPECT_GT(full.at("metrics").at("output").at("mfne_rad").get<double>(),
            light.at("metrics").at("output").at("mfne_rad").get<double>());
  // Strength 0: the normals keep their directions and no vertex moves by more than float
  // round-off over the passes (fandisk's diagonal is 70 mean edges: 1e-5 of it is 0.0007 edges).
  const nlohmann::json none = json_of({"--strength", "0"});
  EXPECT_LT(none.at("metrics").at("output").at("rmse_over_diagonal").get<double>(), 1e-5);
  EXPECT_LT(none.at("metrics").at("output").at("mfne_rad").get<double>(), 1e-3);
}

// Noise along one direction (a range scanner's depth noise): the report names it and says it was
// filtered for and its slides undone, unless --known-noise gave the noise, which is filtered as white
// noise (refine_plan.h): then the report says it was not used.
TEST(FqfilterCli, DirectionalNoiseIsReportedAsUsedOnlyWhenEstimated) {
  fq::test::ScratchDir dir;
  const std::vector<std::string> base = {kFandisk, "--noise",   "0.2", "--noise-kind", "depth", "--engine",
                                         "cpu",    "--threads", "2"};
  const RunResult estimated = run_fqfilter(base, dir);
  ASSERT_EQ(estimated.exit_code, 0) << estimated.err;
  EXPECT_NE(estimated.out.find("directional noise: "), std::string::npos) << estimated.out;
  EXPECT_NE(estimated.out.find("filtered for; its slides within the surface undone"), std::string::npos)
      << estimated.out;
  std::vector<std::string> given = base;
  given.insert(given.end(), {"--known-noise", "0.2"});
  const RunResult known = run_fqfilter(given, dir);
  ASSERT_EQ(known.exit_code, 0) << known.err;
  EXPECT_NE(known.out.find("directional noise: "), std::string::npos) << known.out;
  EXPECT_EQ(known.out.find("slides within the surface undone"), std::string::npos) << known.out;
  EXPECT_NE(known.out.find("not used: --known-noise"), std::string::npos) << known.out;
}

TEST(FqfilterCli, TargetClustersReportsThetaAndSharpEdgeRecall) {
  fq::test::ScratchDir dir;
  const RunResult r = run_fqfilter({kFandisk, "--engine", "cpu", "--threads", "2", "--no-filter",
                                    "--target-clusters", "30", "--reference", kFandisk, "--json"},
                                   dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j.at("clusters").get<double>(), 30.0, 3.0);
  EXPECT_EQ(j.at("params").at("target_clusters").get<uint32_t>(), 30u);
  const double theta = j.at("theta_used").get<double>();
  EXPECT_GT(theta, 0.0);
  EXPECT_LE(theta, 1.0);
  const nlohmann::json& recall = j.at("metrics").at("sharp_edge_recall");
  EXPECT_GT(recall.at("sharp_edges").get<uint32_t>(), 0u);  // fandisk has creases
  EXPECT_GE(recall.at("recall").get<double>(), 0.0);
  EXPECT_LE(recall.at("recall").get<double>(), 1.0);
  expect_finite_numbers(j);
}

TEST(FqfilterCli, WritesLabelledPly) {
  fq::test::ScratchDir dir;
  const std::string out = dir.file("out.ply");
  const RunResult r = run_fqfilter({kFandisk, out, "--engine", "cpu", "--threads", "2", "--no-filter"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(fq::test::read_bytes(out).find("property uint label"), std::string::npos);
  fq::Mesh in, back;
  ASSERT_TRUE(fq::io::read_mesh(kFandisk, in).ok());
  ASSERT_TRUE(fq::io::read_mesh(out, back).ok());
  EXPECT_EQ(back.positions, in.positions) << "--no-filter keeps the positions";
  EXPECT_NE(r.out.find("clusters:"), std::string::npos) << r.out;
}

TEST(FqfilterCli, RepeatAndDracoOutput) {
  fq::test::ScratchDir dir;
  const std::string out = dir.file("out.drc");
  const RunResult r = run_fqfilter(
      {kFandisk, out, "--engine", "cpu", "--threads", "2", "--repeat", "3", "--cluster", "--json"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("repeat").get<int>(), 3);
  EXPECT_EQ(j.at("output").get<std::string>(), out);
  EXPECT_TRUE(j.at("metrics").is_null());
  fq::Mesh back;
  ASSERT_TRUE(fq::io::read_mesh(out, back).ok());
  EXPECT_EQ(back.num_triangles(), 12946u);
}

TEST(FqfilterCli, MismatchedReferenceFails) {
  fq::test::ScratchDir dir;
  fq::Mesh tri;
  tri.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  tri.triangles = {0, 1, 2};
  ASSERT_TRUE(fq::io::write_mesh(dir.file("tri.ply"), tri.view(), nullptr, 0).ok());
  const RunResult r = run_fqfilter({kFandisk, "--reference", dir.file("tri.ply")}, dir);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("vertex counts differ"), std::string::npos) << r.err;
}

TEST(FqfilterCli, FolderWithOneBadFile) {
  fq::test::ScratchDir dir;
  const fs::path in = dir.path() / "in", out = dir.path() / "out";
  fs::create_directories(in);
  fs::copy_file(kFandisk, in / "a_fandisk.ply");
  fq::test::write_bytes((in / "b_garbage.ply").string(), "this is not a mesh");
  fq::test::write_bytes((in / "notes.txt").string(), "ignored");
  const RunResult r = run_fqfilter({in.string(), out.string(), "--engine", "cpu", "--threads", "2"}, dir);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("[1/2] a_fandisk.ply: 6475 V"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("[2/2] b_garbage.ply: FAILED"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("1 of 2 files done, 1 failed"), std::string::npos) << r.err;
  fq::Mesh written;
  ASSERT_TRUE(fq::io::read_mesh((out / "a_fandisk.ply").string(), written).ok());
  EXPECT_EQ(written.num_vertices(), 6475u);
  EXPECT_FALSE(fs::exists(out / "b_garbage.ply"));
}

TEST(FqfilterCli, FolderOutputMustNotBeTheInput) {
  fq::test::ScratchDir dir;
  fs::copy_file(kFandisk, dir.path() / "fandisk.ply");
  const RunResult r = run_fqfilter({dir.path().string(), dir.path().string()}, dir);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("OUT must differ from IN"), std::string::npos) << r.err;
}

// A still part seen four times with fresh noise: one stream with --sequence, against each frame
// alone (--temporal 0) on the same noisy frames.
TEST(FqfilterCli, SequenceFiltersAcrossFramesAndReportsFlicker) {
  fq::test::ScratchDir dir;
  const fs::path in = dir.path() / "frames";
  fs::create_directories(in);
  for (int i = 0; i < 4; ++i) fs::copy_file(kFandisk, in / ("f" + std::to_string(i) + ".ply"));
  const auto run = [&](const char* temporal) {
    const RunResult r = run_fqfilter({in.string(), "--sequence", "--noise", "0.2", "--temporal", temporal,
                                      "--json", "--quiet", "--engine", "cpu", "--threads", "2"},
                                     dir);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    std::vector<nlohmann::json> frames;
    for (size_t at = 0, end; (end = r.out.find('\n', at)) != std::string::npos; at = end + 1)
      frames.push_back(nlohmann::json::parse(r.out.substr(at, end - at)));
    EXPECT_NE(r.err.find("sequence: 0 scene cuts, mean MFNE"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(", mean SF "), std::string::npos) << r.err;
    return frames;
  };
  const std::vector<nlohmann::json> stream = run("0.75"), alone = run("0");
  ASSERT_EQ(stream.size(), 4u);
  ASSERT_EQ(alone.size(), 4u);
  double stream_mfne = 0, alone_mfne = 0, stream_sf = 0, alone_sf = 0;
  for (size_t i = 0; i < 4; ++i) {
    const nlohmann::json& t = stream[i].at("temporal");
    EXPECT_GT(t.at("height_rms").get<double>(), 0.0);
    EXPECT_GT(t.at("smooth_normal_error_rad").get<double>(), 0.0);
    EXPECT_EQ(stream[i].at("noise").at("seed").get<int>(), int(1 + i)) << "fresh noise every frame";
    EXPECT_EQ(stream[i].at("params").at("temporal").get<double>(), 0.75);
    EXPECT_FALSE(t.at("history_reset").get<bool>());
    if (i == 0) {
      EXPECT_EQ(t.at("prior_coverage").get<double>(), 0.0);
      EXPECT_TRUE(t.at("flicker").is_null());
      EXPECT_TRUE(t.at("surface_flicker").is_null()) << "no frame before the first";
    } else {
      EXPECT_GT(t.at("prior_coverage").get<double>(), 0.9);
      EXPECT_GT(t.at("prior_share").get<double>(), 0.1);
      EXPECT_GT(t.at("flicker").get<double>(), 0.0);
      // The split adds up: flicker² = normal² + tangential².
      const double n = t.at("flicker_normal").get<double>(), g = t.at("flicker_tangential").get<double>();
      EXPECT_NEAR(n * n + g * g, std::pow(t.at("flicker").get<double>(), 2), 1e-9);
      EXPECT_GT(t.at("surface_flicker").get<double>(), 0.0);
      EXPECT_GT(t.at("shading_flicker").get<double>(), 0.0);
    }
    if (i > 0)
      EXPECT_GT(alone[i].at("temporal").at("flicker").get<double>(), 0.0) << "the baseline's flicker";
    if (i >= 2) {
      stream_mfne += stream[i].at("metrics").at("output").at("mfne_rad").get<double>();
      alone_mfne += alone[i].at("metrics").at("output").at("mfne_rad").get<double>();
      stream_sf += stream[i].at("temporal").at("surface_flicker").get<double>();
      alone_sf += alone[i].at("temporal").at("surface_flicker").get<double>();
    }
  }
  EXPECT_LT(stream_mfne, alone_mfne) << "the history helps a part that did not move";
  EXPECT_LT(stream_sf, alone_sf) << "and its surface holds stiller";
}

TEST(FqfilterCli, SequenceOptionsAreChecked) {
  fq::test::ScratchDir dir;
  fs::copy_file(kFandisk, dir.path() / "a.ply");
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{kFandisk, "--sequence"}, "folder of frames"},
      {{dir.path().string(), "--temporal", "0.5"}, "--temporal needs --sequence"},
      {{dir.path().string(), "--sequence", "--mode", "qf"}, "qf+ only"},
      {{dir.path().string(), "--sequence", "--repeat", "2"}, "--repeat"},
      {{dir.path().string(), "--sequence", "--temporal", "1.5"}, "--temporal"}};
  for (const auto& [args, says] : cases) {
    const RunResult r = run_fqfilter(args, dir);
    EXPECT_EQ(r.exit_code, 2) << args[1];
    EXPECT_NE(r.err.find(says), std::string::npos) << r.err;
    EXPECT_EQ(count_lines(r.err), 1u) << r.err;
  }
}

}  // namespace
