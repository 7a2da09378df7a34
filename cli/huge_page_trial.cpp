#include "cli/huge_page_trial.h"

namespace omnishadow::cli {

HugePageTrial::HugePageTrial(std::uintptr_t hugeBegin, std::uintptr_t hugeEnd)
    : hugeBegin_(hugeBegin), hugeEnd_(hugeEnd) {}

bool HugePageTrial::asks(std::uintptr_t spanBegin, std::uintptr_t spanEnd) const {
  return !givenUp_ && spanBegin >= hugeBegin_ && spanEnd <= hugeEnd_ &&
         spanEnd - spanBegin == kHugePage;
}

void HugePageTrial::touched(std::uintptr_t spanBegin, std::uintptr_t spanEnd,
                            double cpuMilliseconds) {
  if (asks(spanBegin, spanEnd) && cpuMilliseconds > kSlowMilliseconds) givenUp_ = true;
}

}  // namespace omnishadow::cli
