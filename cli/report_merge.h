#pragma once

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace omnishadow::cli {

// Everything `omnishadow report merge` accepts.
struct ReportMergeOptions {
  std::vector<std::string> reports;
  std::string out;
};

// Adds `report` with its one subcommand, `merge`.
void addReportCommand(CLI::App& app, ReportMergeOptions& options);

// Merges the --report files of a batch's shards into one report of the same form: the jobs in
// the order of the unsharded batch when the inputs are shards K/N of one N (else in the order
// given), the summary's counts added up and its seconds the longest shard's. Throws InputError
// for unreadable or malformed reports and for a shard given twice. Returns 0.
int runReportMerge(const ReportMergeOptions& options);

}  // namespace omnishadow::cli
