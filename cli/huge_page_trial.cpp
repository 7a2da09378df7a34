#include "cli/huge_page_trial.h"

#include <algorithm>

namespace omnishadow::cli {

HugePageTrial::HugePageTrial(std::uintptr_t hugeBegin, std::uintptr_t hugeEnd)
    : hugeBegin_(hugeBegin), hugeEnd_(hugeEnd) {}

bool HugePageTrial::asks(std::uintptr_t spanBegin, std::uintptr_t spanEnd) const {
  return !givenUp_ && smallBytes_ >= kCalibrationBytes && spanBegin >= hugeBegin_ &&
         spanEnd <= hugeEnd_ && spanEnd - spanBegin == kHugePage;
}

double HugePageTrial::slowMilliseconds() const {
  if (smallBytes_ == 0) return kSlowMilliseconds;
  const double perHugePage =
      smallMilliseconds_ * static_cast<double>(kHugePage) / static_cast<double>(smallBytes_);
  return std::max(kSlowMilliseconds, perHugePage);
}

double HugePageTrial::smallPageMicroseconds() const {
  if (smallBytes_ < kCalibrationBytes) return 0.0;
  constexpr double kSmallPage = 4096.0;
  return smallMilliseconds_ * 1e3 * kSmallPage / static_cast<double>(smallBytes_);
}

void HugePageTrial::touched(std::uintptr_t spanBegin, bool huge, std::uintptr_t touchedBytes,
                            double cpuMilliseconds) {
  if (touchedBytes == 0) return;
  if (huge) {
    askedSpan_ = spanBegin;
    if (cpuMilliseconds > slowMilliseconds()) givenUp_ = true;
    return;
  }
  if (spanBegin == askedSpan_) return;
  smallBytes_ += touchedBytes;
  smallMilliseconds_ += cpuMilliseconds;
}

}  // namespace omnishadow::cli
