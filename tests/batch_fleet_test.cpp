// End-to-end tests of what spreads a batch over devices and machines: `--shard auto` from the
// Slurm and Kubernetes variables, `report merge`, `--gpus`, `devices`. Renders are tiny (64x48,
// 32-texel shadow maps).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tests/support/cli_fixture.h"

namespace omnishadow::batch_fleet_test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test_support::contains;
using test_support::filesIn;
using test_support::readFile;
using test_support::sameBytes;
using test_support::writeBoxScene;
using Names = std::vector<std::string>;

class BatchFleetTest : public test_support::CliFixture {
 protected:
  BatchFleetTest() : CliFixture("omnishadow-fleet") {
    for (int i = 0; i < 4; ++i)
      writeBoxScene(input(std::string("s/") + char('a' + i) + ".gltf"),
                    {.boxX = -0.6f + 0.4f * static_cast<float>(i)});
  }

  // `omnishadow batch in/s --out out/<folder> --report <root>/<folder>.json` plus `args`.
  Run batch(const std::string& folder, std::vector<std::string> args,
            const std::vector<std::string>& environment = {}) {
    std::vector<std::string> all = {"batch",    in("s"),       "--out",    output(folder).string(),
                                    "--width",  "64",          "--height", "48",
                                    "--report", report(folder)};
    all.insert(all.end(), args.begin(), args.end());
    return run(all, environment);
  }
  std::string report(const std::string& folder) const {
    return (root_ / (folder + ".json")).string();
  }
  json readJson(const std::string& path) const { return json::parse(readFile(path)); }
};

TEST_F(BatchFleetTest, ShardAutoFromSlurmOrKubernetesAndMergedReports) {
  const Run task1 =
      batch("slurm", {"--shard", "auto"},
            {"SLURM_ARRAY_TASK_ID=2", "SLURM_ARRAY_TASK_MIN=1", "SLURM_ARRAY_TASK_MAX=2"});
  ASSERT_EQ(task1.status, 0) << task1.err;
  EXPECT_EQ(filesIn(output("slurm")), (Names{"b.png", "d.png"}));
  EXPECT_EQ(readJson(report("slurm"))["shard"], "1/2");

  const Run index0 =
      batch("k8s", {"--shard", "auto", "--shard-count", "2"}, {"JOB_COMPLETION_INDEX=0"});
  ASSERT_EQ(index0.status, 0) << index0.err;
  EXPECT_EQ(filesIn(output("k8s")), (Names{"a.png", "c.png"}));
  EXPECT_EQ(readJson(report("k8s"))["shard"], "0/2");

  const Run merged =
      run({"report", "merge", report("slurm"), report("k8s"), "-o", (root_ / "all.json").string()});
  ASSERT_EQ(merged.status, 0) << merged.err;
  const json all = readJson((root_ / "all.json").string());
  EXPECT_EQ(all["shard"], nullptr);
  EXPECT_EQ(all["summary"]["jobs"], 4);
  EXPECT_EQ(all["summary"]["rendered"], 4);
  EXPECT_EQ(all["summary"]["failed"], 0);
  Names order;
  for (const json& job : all["jobs"]) order.push_back(job["name"]);
  EXPECT_EQ(order, (Names{"a.gltf", "b.gltf", "c.gltf", "d.gltf"}));

  // A shard given twice, and a file that is no report.
  const Run twice = run({"report", "merge", report("k8s"), report("k8s"), "-o", "x.json"});
  EXPECT_EQ(twice.status, 2);
  EXPECT_EQ(twice.err,
            "omnishadow: " + report("k8s") + " and " + report("k8s") + " are both shard 0/2\n");
  const Run notReport = run({"report", "merge", in("s/a.gltf"), "-o", "x.json"});
  EXPECT_EQ(notReport.status, 2);
  EXPECT_TRUE(contains(notReport.err, in("s/a.gltf") + ": ")) << notReport.err;
  EXPECT_FALSE(fs::exists(output("x.json")));
}

TEST_F(BatchFleetTest, ShardAutoWithoutSchedulerVariablesIsAUsageError) {
  const Run none = batch("none", {"--shard", "auto"});
  EXPECT_EQ(none.status, 2);
  EXPECT_EQ(none.err,
            "omnishadow: --shard auto: no scheduler variable is set (SLURM_ARRAY_TASK_ID for a "
            "Slurm job array, JOB_COMPLETION_INDEX for a Kubernetes indexed Job); pass --shard "
            "K/N\n");
  const Run k8s = batch("none", {"--shard", "auto"}, {"JOB_COMPLETION_INDEX=1"});
  EXPECT_EQ(k8s.status, 2);
  EXPECT_TRUE(contains(k8s.err, "pass --shard-count N")) << k8s.err;
  EXPECT_FALSE(fs::exists(output("none")));
}

TEST_F(BatchFleetTest, TwoWorkersFromOneQueueRenderWhatOneDoes) {
  const Run one = batch("one", {});
  ASSERT_EQ(one.status, 0) << one.err;
  // Two workers on the first device (the only one CI may have).
  const Run two = batch("two", {"--gpus", "0,0"});
  ASSERT_EQ(two.status, 0) << two.err;
  const Names files = {"a.png", "b.png", "c.png", "d.png"};
  ASSERT_EQ(filesIn(output("two")), files);
  for (const std::string& file : files)
    EXPECT_TRUE(sameBytes(output("one") / file, output("two") / file)) << file;
  const json jobs = readJson(report("two"))["jobs"];
  ASSERT_EQ(jobs.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(jobs[i]["name"], files[i].substr(0, 1) + ".gltf");

  const Run missing = batch("missing", {"--gpus", "0,99"});
  EXPECT_EQ(missing.status, 2);
  EXPECT_TRUE(missing.err.starts_with("omnishadow: --gpu 99: there are only ")) << missing.err;
  EXPECT_FALSE(fs::exists(output("missing")));
}

TEST_F(BatchFleetTest, InProcessRendersWhatTheWorkerDoes) {
  ASSERT_EQ(batch("worker", {}).status, 0);
  const Run inProcess = batch("in-process", {"--in-process"});
  ASSERT_EQ(inProcess.status, 0) << inProcess.err;
  for (const std::string file : {"a.png", "b.png", "c.png", "d.png"})
    EXPECT_TRUE(sameBytes(output("worker") / file, output("in-process") / file)) << file;

  // A worker's own usage error (a device that is not there) is the batch's, before any job.
  const Run noDevice = batch("no-device", {"--gpu", "99"});
  EXPECT_EQ(noDevice.status, 2);
  EXPECT_TRUE(noDevice.err.starts_with("omnishadow: --gpu 99: there are only ")) << noDevice.err;
  EXPECT_EQ(std::count(noDevice.err.begin(), noDevice.err.end(), '\n'), 1) << noDevice.err;
  EXPECT_FALSE(fs::exists(output("no-device")));

  const std::pair<std::vector<std::string>, std::string> usage[] = {
      {{"--in-process", "--job-timeout", "5"},
       "omnishadow: --job-timeout: needs a worker process; leave out --in-process\n"},
      {{"--in-process", "--gpus", "all"},
       "omnishadow: --gpus: needs worker processes; leave out --in-process\n"},
      {{"--gpus", "0", "--gpu", "0"},
       "omnishadow: --gpus: chooses the devices itself; leave out --gpu\n"},
      {{"--gpu", "first"},
       "omnishadow: --gpu first: expected auto, an EGL device index (0, 1, ...) or cuda:N\n"}};
  for (const auto& [args, message] : usage) {
    const Run r = batch("usage", args);
    EXPECT_EQ(r.status, 2) << args.front();
    EXPECT_EQ(r.err, message);
    EXPECT_FALSE(fs::exists(output("usage")));
  }
}

TEST_F(BatchFleetTest, DevicesListsWhatGpuChoosesFrom) {
  const Run r = run({"devices", "--json"});
  ASSERT_EQ(r.status, 0) << r.err;
  const json doc = json::parse(r.out);
  ASSERT_TRUE(doc["devices"].is_array()) << r.out;
  for (std::size_t i = 0; i < doc["devices"].size(); ++i) {
    const json& device = doc["devices"][i];
    EXPECT_EQ(device["index"], i);
    EXPECT_TRUE(device["software"].is_boolean());
    // The software device has no DRM node; a GPU has one.
    if (device["software"] == true) {
      EXPECT_EQ(device["drmNode"], nullptr) << device.dump();
    }
  }
  EXPECT_TRUE(doc.contains("cudaVisibleDevices"));
  EXPECT_TRUE(doc.contains("auto"));

  // Every listed index is a --gpu that renders; the next one is a usage error naming them.
  const std::string next = std::to_string(doc["devices"].size());
  const Run missing =
      run({"render", "--gpu", next, "-o", "a.png", "--width", "16", "--height", "16"});
  EXPECT_EQ(missing.status, 2);
  EXPECT_FALSE(fs::exists(output("a.png")));
  const Run bad = run({"render", "--gpu", "cuda:x", "-o", "a.png"});
  EXPECT_EQ(bad.status, 2);
  EXPECT_EQ(bad.err,
            "omnishadow: --gpu cuda:x: expected auto, an EGL device index (0, 1, ...) or cuda:N\n");
}

}  // namespace
}  // namespace omnishadow::batch_fleet_test
