#include "cli/report_merge.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>

#include "cli/batch_jobs.h"
#include "renderer/core/errors.h"

namespace omnishadow::cli {
namespace {

using json = nlohmann::ordered_json;

struct ShardReport {
  std::string file;
  json report;
  std::optional<Shard> shard;
};

ShardReport readReport(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file + ": cannot read report");
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  ShardReport r{file, json::parse(text, nullptr, false), std::nullopt};
  if (r.report.is_discarded()) throw InputError(file + ": not JSON; expected a batch --report");
  if (!r.report.is_object() || !r.report.contains("jobs") || !r.report["jobs"].is_array() ||
      !r.report.contains("summary") || !r.report["summary"].is_object())
    throw InputError(file + ": expected a batch --report (an object with summary and jobs)");
  for (const char* key : {"jobs", "rendered", "skipped", "failed"})
    if (!r.report["summary"].contains(key) || !r.report["summary"][key].is_number_unsigned())
      throw InputError(file + ": summary." + key + ": expected a count");
  const json& shard = r.report.value("shard", json());
  if (shard.is_string()) {
    try {
      r.shard = parseShard(shard.get<std::string>());
    } catch (const InputError&) {
      throw InputError(file + ": shard \"" + shard.get<std::string>() + "\": expected K/N");
    }
  } else if (!shard.is_null()) {
    throw InputError(file + ": shard: expected \"K/N\" or null");
  }
  return r;
}

// The jobs back in the order of the whole batch: shard K's p-th job was job p*N+K.
std::optional<json> interleaved(const std::vector<ShardReport>& reports) {
  const int count = reports.front().shard ? reports.front().shard->count : 0;
  std::map<std::size_t, json> byPosition;
  for (const ShardReport& r : reports) {
    if (!r.shard || r.shard->count != count) return std::nullopt;
    const json& jobs = r.report["jobs"];
    for (std::size_t p = 0; p < jobs.size(); ++p)
      byPosition[p * static_cast<std::size_t>(count) + static_cast<std::size_t>(r.shard->index)] =
          jobs[p];
  }
  json jobs = json::array();
  for (auto& [position, job] : byPosition) jobs.push_back(std::move(job));
  return jobs;
}

}  // namespace

void addReportCommand(CLI::App& app, ReportMergeOptions& o) {
  CLI::App* report = app.add_subcommand("report", "Work with batch --report files");
  report->require_subcommand(1);
  CLI::App* merge =
      report->add_subcommand("merge", "Merge the reports of a batch's shards into one");
  merge->add_option("reports", o.reports, "The shards' --report files")->required();
  merge->add_option("-o,--out", o.out, "The merged report")->required();
}

int runReportMerge(const ReportMergeOptions& o) {
  std::vector<ShardReport> reports;
  for (const std::string& file : o.reports) reports.push_back(readReport(file));
  for (std::size_t i = 0; i < reports.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (reports[i].shard && reports[j].shard &&
          reports[i].shard->index == reports[j].shard->index &&
          reports[i].shard->count == reports[j].shard->count)
        throw InputError(reports[j].file + " and " + reports[i].file + " are both shard " +
                         reports[i].report["shard"].get<std::string>());

  json merged;
  std::uint64_t counts[4] = {0, 0, 0, 0};
  double seconds = 0.0;
  const char* keys[] = {"jobs", "rendered", "skipped", "failed"};
  for (const ShardReport& r : reports) {
    for (int k = 0; k < 4; ++k) counts[k] += r.report["summary"][keys[k]].get<std::uint64_t>();
    const json& s = r.report["summary"].value("seconds", json(0.0));
    if (s.is_number()) seconds = std::max(seconds, s.get<double>());
  }
  merged["summary"] = json::object();
  for (int k = 0; k < 4; ++k) merged["summary"][keys[k]] = counts[k];
  merged["summary"]["seconds"] = seconds;
  merged["shard"] = nullptr;
  if (std::optional<json> jobs = interleaved(reports)) {
    merged["jobs"] = std::move(*jobs);
  } else {
    merged["jobs"] = json::array();
    for (const ShardReport& r : reports)
      for (const json& job : r.report["jobs"]) merged["jobs"].push_back(job);
  }
  std::ofstream out(o.out);
  out << merged.dump(2) << "\n";
  if (!out.flush()) throw RenderError("cannot write " + o.out);
  return 0;
}

}  // namespace omnishadow::cli
