#pragma once

#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace omnishadow {

inline double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// How --stats names a stage's wait for the GPU ("GPU wait: lighting"): not "<stage> ...", so
// that a script reading the lines that begin with a stage's name does not take it for the stage.
constexpr const char* kGpuWaitPrefix = "GPU wait: ";

// Wall time of the named stages of one render, in the order they first ran (--stats). A stage
// that runs several times (lighting in several passes) is one row with its total.
class StageTimes {
 public:
  void add(const std::string& stage, double milliseconds) { addTo(stages_, stage, milliseconds); }
  const std::vector<std::pair<std::string, double>>& stages() const { return stages_; }
  // The part of a stage spent waiting for the GPU to finish what the stage submitted (glFinish):
  // a stage whose wait is most of it is bound by the GPU, one with little wait by the CPU (our
  // work and the driver's). Included in the stage's own time, not added to total().
  void addWait(const std::string& stage, double milliseconds) {
    addTo(waits_, stage, milliseconds);
  }
  const std::vector<std::pair<std::string, double>>& waits() const { return waits_; }
  double total() const {
    double sum = 0;
    for (const auto& stage : stages_) sum += stage.second;
    return sum;
  }

 private:
  using Rows = std::vector<std::pair<std::string, double>>;
  static void addTo(Rows& rows, const std::string& stage, double milliseconds) {
    for (auto& [name, total] : rows)
      if (name == stage) {
        total += milliseconds;
        return;
      }
    rows.emplace_back(stage, milliseconds);
  }
  std::vector<std::pair<std::string, double>> stages_;
  std::vector<std::pair<std::string, double>> waits_;
};

// Measures from construction to stop() (or destruction) and records it under `stage`.
class ScopedStage {
 public:
  ScopedStage(StageTimes& times, std::string stage) : times_(times), stage_(std::move(stage)) {}
  ~ScopedStage() { stop(); }
  void stop() {
    if (stopped_) return;
    stopped_ = true;
    const auto elapsed = std::chrono::steady_clock::now() - start_;
    times_.add(stage_, std::chrono::duration<double, std::milli>(elapsed).count());
  }
  ScopedStage(const ScopedStage&) = delete;
  ScopedStage& operator=(const ScopedStage&) = delete;

 private:
  StageTimes& times_;
  std::string stage_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  bool stopped_ = false;
};

}  // namespace omnishadow
