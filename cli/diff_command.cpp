#include "cli/diff_command.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "cli/common_options.h"
#include "cli/malloc_heap.h"
#include "cli/render_job.h"
#include "cli/text_table.h"
#include "renderer/core/errors.h"
#include "renderer/output/image_diff.h"
#include "renderer/output/image_writer.h"
#include "renderer/output/output_transaction.h"

namespace fs = std::filesystem;

namespace omnishadow::cli {
namespace {

using Json = nlohmann::ordered_json;

// ---------------------------------------------------------------------------------------------
// Options as the comparison uses them

// The tolerances in force: a tolerance that is not checked is empty. Without --max-abs and
// --max-failing-fraction both are 0 (the images must be identical); with one of them, only
// that one is checked.
struct Tolerance {
  std::optional<double> maxAbs, maxFailingFraction;
  bool defaulted = false;
};

Tolerance tolerance(const DiffCommandOptions& o) {
  Tolerance t;
  if (std::isnan(o.maxAbs) && std::isnan(o.maxFailingFraction)) {
    t.maxAbs = 0.0;
    t.maxFailingFraction = 0.0;
    t.defaulted = true;
    return t;
  }
  if (!std::isnan(o.maxAbs)) t.maxAbs = o.maxAbs;
  if (!std::isnan(o.maxFailingFraction)) t.maxFailingFraction = o.maxFailingFraction;
  return t;
}

// PNG and other integer formats are read normalized to 0..1, so their peak is 1; an EXR's is
// the maximum of the reference's values (0 asks compareImages to find it).
double peakFor(const DiffCommandOptions& o, const fs::path& reference) {
  if (!std::isnan(o.peak)) return o.peak;
  return lowerExtension(reference) == ".exr" ? 0.0 : 1.0;
}

DiffOptions diffOptions(const DiffCommandOptions& o, const fs::path& a, const fs::path& b) {
  DiffOptions options;
  options.channels = o.channels;
  options.threshold = o.threshold;
  options.peak = peakFor(o, a);
  options.perChannel = o.perChannel;
  options.labelA = a.string();
  options.labelB = b.string();
  return options;
}

double heatScale(const DiffCommandOptions& o, const DiffResult& result) {
  return std::isnan(o.heatScale) ? defaultHeatScale(result) : o.heatScale;
}

// ---------------------------------------------------------------------------------------------
// Verdicts

struct Verdict {
  bool pass = true;
  std::string reason;  // why not, when it fails
};

std::string readable(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", value);
  return buffer;
}

Verdict judge(const DiffStats& s, const Tolerance& t) {
  if (t.defaulted) {
    if (s.maxAbs > 0.0)
      return {false, "max abs " + readable(s.maxAbs) +
                         " > 0 (no tolerance given: the images must be identical)"};
    return {};
  }
  if (t.maxAbs && !(s.maxAbs <= *t.maxAbs))
    return {false, "max abs " + readable(s.maxAbs) + " > --max-abs " + readable(*t.maxAbs)};
  if (t.maxFailingFraction && !(s.failingFraction <= *t.maxFailingFraction))
    return {false, "failing fraction " + readable(s.failingFraction) +
                       " > --max-failing-fraction " + readable(*t.maxFailingFraction)};
  return {};
}

// ---------------------------------------------------------------------------------------------
// Usage checks

bool isPng(const fs::path& path) {
  return lowerExtension(path) == ".png";
}

bool isImage(const fs::path& path) {
  const std::string extension = lowerExtension(path);
  return extension == ".png" || extension == ".exr";
}

fs::path identity(const fs::path& path) {
  std::error_code ignored;
  fs::path canonical = fs::weakly_canonical(path, ignored);
  return (canonical.empty() ? fs::absolute(path) : canonical).lexically_normal();
}

// `inner` is `outer` or inside it.
bool within(const fs::path& inner, const fs::path& outer) {
  const fs::path i = identity(inner), o = identity(outer);
  auto [end, ignored] = std::mismatch(o.begin(), o.end(), i.begin(), i.end());
  return end == o.end();
}

void checkExists(const std::string& path) {
  std::error_code error;
  if (!fs::exists(path, error)) throw InputError(path + ": no such file or folder");
}

// ---------------------------------------------------------------------------------------------
// JSON

Json optionalNumber(const std::optional<double>& value) {
  return value ? jsonNumber(*value) : Json(nullptr);
}

Json toJson(const DiffStats& s) {
  Json j;
  j["channels"] = s.channels;
  j["maxAbs"] = jsonNumber(s.maxAbs);
  j["meanAbs"] = jsonNumber(s.meanAbs);
  j["rmse"] = jsonNumber(s.rmse);
  j["psnr"] = jsonNumber(s.psnr);
  j["failingPixels"] = s.failingPixels;
  j["failingFraction"] = jsonNumber(s.failingFraction);
  j["maxAt"] = s.maxX >= 0 ? Json::array({s.maxX, s.maxY}) : Json(nullptr);
  return j;
}

Json perChannelJson(const DiffResult& result) {
  Json channels = Json::array();
  for (const DiffStats& s : result.perChannel) channels.push_back(toJson(s));
  return channels;
}

Json toleranceJson(const Tolerance& t) {
  return {{"maxAbs", optionalNumber(t.maxAbs)},
          {"maxFailingFraction", optionalNumber(t.maxFailingFraction)}};
}

Json imageJson(const std::string& file, const FloatImage& image) {
  return {{"file", file},
          {"width", image.width},
          {"height", image.height},
          {"channels", image.channels}};
}

Json heatMapJson(const std::optional<fs::path>& file, double scale) {
  if (!file) return nullptr;
  return {{"file", file->string()}, {"scale", jsonNumber(scale)}};
}

void printJson(const Json& doc) {
  std::printf("%s\n", doc.dump(2, ' ', false, Json::error_handler_t::replace).c_str());
}

// ---------------------------------------------------------------------------------------------
// Text

void printDiffLine(const char* label, const std::string& value) {
  if (value.empty())
    std::printf("%s\n", label);
  else
    std::printf("%-10s %s\n", label, value.c_str());
}

std::string joined(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ",") + name;
  return text;
}

std::string readablePercent(double fraction) {
  return readable(fraction * 100.0) + "%";
}

std::vector<std::string> statsRow(const std::string& label, const DiffStats& s) {
  return {label,
          readable(s.maxAbs),
          readable(s.meanAbs),
          readable(s.rmse),
          readable(s.psnr),
          std::to_string(s.failingPixels) + " (" + readablePercent(s.failingFraction) + ")",
          s.maxX >= 0 ? std::to_string(s.maxX) + "," + std::to_string(s.maxY) : "-"};
}

std::string describe(const std::string& file, const FloatImage& image) {
  return file + "  " + std::to_string(image.width) + "x" + std::to_string(image.height) + "  " +
         joined(image.channels);
}

// ---------------------------------------------------------------------------------------------
// Two files

int diffFiles(const DiffCommandOptions& o) {
  std::optional<fs::path> out;
  if (!o.out.empty()) {
    out = fs::path(o.out);
    if (!isPng(*out))
      throw InputError(o.out + ": --out writes a PNG heat map; give it a .png name");
    if (identity(*out) == identity(o.a) || identity(*out) == identity(o.b))
      throw InputError(o.out + ": --out would overwrite an input image");
  }
  const FloatImage a = readImage(o.a);
  const FloatImage b = readImage(o.b);
  const DiffResult result = compareImages(a, b, diffOptions(o, o.a, o.b));
  const Tolerance t = tolerance(o);
  const Verdict verdict = judge(result.overall, t);

  const double scale = heatScale(o, result);
  if (out) {
    OutputTransaction transaction;
    writePng(transaction.stage(*out), result.width, result.height, 3, heatMap(result, scale));
    transaction.commit();
  }

  if (o.json) {
    Json doc;
    doc["mode"] = "files";
    doc["a"] = imageJson(o.a, a);
    doc["b"] = imageJson(o.b, b);
    doc["channels"] = result.overall.channels;
    doc["threshold"] = jsonNumber(o.threshold);
    doc["peak"] = jsonNumber(result.peak);
    doc["tolerance"] = toleranceJson(t);
    doc["overall"] = toJson(result.overall);
    doc["perChannel"] = perChannelJson(result);
    doc["heatMap"] = heatMapJson(out, scale);
    doc["pass"] = verdict.pass;
    printJson(doc);
  } else {
    printDiffLine("A", describe(o.a, a));
    printDiffLine("B", describe(o.b, b));
    printDiffLine("compared", joined(result.overall.channels) + "  (threshold " +
                                  readable(o.threshold) + ", PSNR peak " + readable(result.peak) +
                                  ")");
    TextTable rows = {
        {"channels", "max abs", "mean abs", "RMSE", "PSNR dB", "failing pixels", "max at"},
        statsRow("all", result.overall)};
    for (const DiffStats& s : result.perChannel) rows.push_back(statsRow(s.channels[0], s));
    printTable(rows);
    if (out) printDiffLine("heat map", out->string() + "  (scale " + readable(scale) + ")");
    printDiffLine(verdict.pass ? "PASS" : "FAIL", verdict.reason);
  }
  return verdict.pass ? 0 : 1;
}

// ---------------------------------------------------------------------------------------------
// Two folders

// The .png and .exr files under `root`, by path relative to it ('/'-separated), sorted.
std::vector<std::string> imagesUnder(const std::string& root) {
  std::vector<std::string> files;
  std::error_code error;
  fs::recursive_directory_iterator it(root, error), end;
  for (; !error && it != end; it.increment(error)) {
    std::error_code ignored;
    if (it->is_regular_file(ignored) && isImage(it->path()))
      files.push_back(it->path().lexically_relative(root).generic_string());
  }
  if (error) throw InputError(root + ": cannot list the folder: " + error.message());
  std::sort(files.begin(), files.end());
  return files;
}

// Where the heat map of the pair `relative` goes: the same relative path under --out, with
// ".png" appended unless it already ends in ".png" (b.exr -> b.exr.png).
fs::path heatMapPath(const fs::path& outDir, const std::string& relative) {
  return outDir / fs::path(isPng(relative) ? relative : relative + ".png");
}

struct Pair {
  std::string path;
  std::optional<DiffResult> result;  // empty when the pair could not be compared
  std::string error;
  Verdict verdict;
  double scale = 1.0;
  std::optional<fs::path> heatMap;
};

int diffFolders(const DiffCommandOptions& o) {
  std::optional<fs::path> outDir;
  if (!o.out.empty()) {
    outDir = fs::path(o.out);
    std::error_code error;
    if (fs::exists(*outDir, error) && !fs::is_directory(*outDir, error))
      throw InputError(o.out + ": --out must be a folder when comparing folders");
    if (within(*outDir, o.a) || within(*outDir, o.b) || within(o.a, *outDir) ||
        within(o.b, *outDir))
      throw InputError(o.out + ": --out must be outside the folders compared");
  }
  const std::vector<std::string> inA = imagesUnder(o.a), inB = imagesUnder(o.b);
  std::vector<std::string> common, onlyA, onlyB;
  std::set_intersection(inA.begin(), inA.end(), inB.begin(), inB.end(), std::back_inserter(common));
  std::set_difference(inA.begin(), inA.end(), inB.begin(), inB.end(), std::back_inserter(onlyA));
  std::set_difference(inB.begin(), inB.end(), inA.begin(), inA.end(), std::back_inserter(onlyB));

  const Tolerance t = tolerance(o);
  std::vector<Pair> pairs;
  std::vector<std::string> errors;
  for (const std::string& relative : common) {
    Pair pair;
    pair.path = relative;
    const fs::path a = fs::path(o.a) / relative, b = fs::path(o.b) / relative;
    try {
      pair.result = compareImages(readImage(a), readImage(b), diffOptions(o, a, b));
      pair.verdict = judge(pair.result->overall, t);
      pair.scale = heatScale(o, *pair.result);
    } catch (const InputError& e) {
      pair.error = e.what();
      pair.verdict = {false, pair.error};
      errors.push_back(pair.error);
    }
    pairs.push_back(std::move(pair));
  }

  // Heat maps only when every pair could be compared: a run that ends in status 2 writes
  // nothing, as a failed render does.
  if (outDir && errors.empty()) {
    OutputTransaction transaction;
    for (Pair& pair : pairs) {
      pair.heatMap = heatMapPath(*outDir, pair.path);
      const DiffResult& r = *pair.result;
      writePng(transaction.stage(*pair.heatMap), r.width, r.height, 3, heatMap(r, pair.scale));
    }
    transaction.commit();
  }

  std::size_t failed = 0;
  for (const Pair& pair : pairs)
    if (pair.result && !pair.verdict.pass) ++failed;
  const bool pass = failed == 0 && errors.empty() && onlyA.empty() && onlyB.empty();

  if (o.json) {
    Json list = Json::array();
    for (const Pair& pair : pairs) {
      const DiffResult* r = pair.result ? &*pair.result : nullptr;
      Json j;
      j["path"] = pair.path;
      j["result"] = !r ? "ERROR" : pair.verdict.pass ? "PASS" : "FAIL";
      j["error"] = r ? Json(nullptr) : Json(pair.error);
      j["width"] = r ? Json(r->width) : Json(nullptr);
      j["height"] = r ? Json(r->height) : Json(nullptr);
      j["channels"] = r ? Json(r->overall.channels) : Json(nullptr);
      j["peak"] = r ? jsonNumber(r->peak) : Json(nullptr);
      j["overall"] = r ? toJson(r->overall) : Json(nullptr);
      j["perChannel"] = r ? perChannelJson(*r) : Json::array();
      j["heatMap"] = heatMapJson(pair.heatMap, pair.scale);
      list.push_back(j);
    }
    Json doc;
    doc["mode"] = "folders";
    doc["a"] = o.a;
    doc["b"] = o.b;
    doc["threshold"] = jsonNumber(o.threshold);
    doc["tolerance"] = toleranceJson(t);
    doc["pairs"] = list;
    doc["onlyInA"] = onlyA;
    doc["onlyInB"] = onlyB;
    doc["heatMaps"] = outDir && errors.empty() ? Json(outDir->string()) : Json(nullptr);
    doc["pass"] = pass;
    printJson(doc);
  } else {
    TextTable rows = {{"path", "max abs", "mean abs", "failing", "result"}};
    for (const Pair& pair : pairs) {
      if (!pair.result) {
        rows.push_back({pair.path, "-", "-", "-", "ERROR"});
        continue;
      }
      const DiffStats& s = pair.result->overall;
      rows.push_back({pair.path, readable(s.maxAbs), readable(s.meanAbs),
                      readablePercent(s.failingFraction), pair.verdict.pass ? "PASS" : "FAIL"});
      for (const DiffStats& c : pair.result->perChannel)
        rows.push_back({"  " + c.channels[0], readable(c.maxAbs), readable(c.meanAbs),
                        readablePercent(c.failingFraction), ""});
    }
    if (pairs.empty())
      std::printf("no .png or .exr file in both folders\n");
    else
      printTable(rows);
    for (const std::string& path : onlyA) printDiffLine("only in A", path);
    for (const std::string& path : onlyB) printDiffLine("only in B", path);
    if (outDir && errors.empty())
      printDiffLine("heat maps",
                    outDir->string() + "  (" + std::to_string(pairs.size()) + " files)");
    std::string summary = std::to_string(pairs.size()) + " pairs, " + std::to_string(failed) +
                          " failed, " + std::to_string(errors.size()) + " unreadable; " +
                          std::to_string(onlyA.size()) + " only in A, " +
                          std::to_string(onlyB.size()) + " only in B";
    printDiffLine(pass ? "PASS" : "FAIL", summary);
  }
  for (const std::string& error : errors) std::fprintf(stderr, "omnishadow: %s\n", error.c_str());
  if (!errors.empty()) return 2;
  return pass ? 0 : 1;
}

}  // namespace

void addDiffCommand(CLI::App& app, DiffCommandOptions& o) {
  CLI::App* diff = app.add_subcommand(
      "diff", "Compare two images (PNG, EXR), or two folders of them, and report differences");
  diff->add_option("A", o.a, "Reference image, or folder of images")->required();
  diff->add_option("B", o.b, "Image (or folder) compared with A")->required();
  diff->add_option("--channels", o.channels,
                   "Compare only these channels, comma-separated (default: all shared by name)")
      ->delimiter(',');
  diff->add_flag("--per-channel", o.perChannel, "Also report each channel on its own");
  diff->add_option("--threshold", o.threshold,
                   "A pixel fails when its max abs difference is above this (default 0)")
      ->check(CLI::NonNegativeNumber);
  diff->add_option("--max-abs", o.maxAbs, "Tolerance: largest allowed abs difference")
      ->check(CLI::NonNegativeNumber);
  diff->add_option("--max-failing-fraction", o.maxFailingFraction,
                   "Tolerance: largest allowed fraction of failing pixels (0..1)")
      ->check(CLI::Range(0.0, 1.0));
  diff->add_option("--peak", o.peak, "PSNR peak (default: 1; for an EXR A, the max of A's values)")
      ->check(CLI::PositiveNumber);
  diff->add_option("--out", o.out,
                   "Write a heat map of the differences (.png; a folder when comparing folders)");
  diff->add_option("--heat-scale", o.heatScale,
                   "Difference shown at the top of the heat map (default: the max difference)")
      ->check(CLI::PositiveNumber);
  diff->add_option("--metric", o.metric, "abs (default); flip is not implemented")
      ->check(CLI::IsMember({"abs", "flip"}));
  diff->add_flag("--json", o.json, "Print one JSON object (schema in the README)");
}

int runDiff(const DiffCommandOptions& o) {
  if (o.metric == "flip")
    throw InputError(
        "--metric flip: not implemented (no validated LDR-FLIP implementation; see README)");
  checkExists(o.a);
  checkExists(o.b);
  std::error_code error;
  const bool folderA = fs::is_directory(o.a, error), folderB = fs::is_directory(o.b, error);
  if (folderA != folderB)
    throw InputError((folderA ? o.a : o.b) + ": is a folder but " + (folderA ? o.b : o.a) +
                     " is not; compare two files or two folders");
  // Decoded images are large blocks that malloc would map afresh each: the heap set up as for a
  // batch (cli/malloc_heap.h). Comparing two 1920x1080 PNGs took 0.25-0.28 s with malloc as the
  // system has it and 0.07-0.08 s so set up, two EXRs 0.34-0.35 s and 0.15-0.25 s.
  setUpMallocHeap();
  return folderA ? diffFolders(o) : diffFiles(o);
}

}  // namespace omnishadow::cli
