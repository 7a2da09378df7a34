// Where the memory warm-up asks for transparent huge pages (cli/huge_page_trial.h): span by
// span while they fault quickly, never again after a slow one, never for part of a span or
// outside the block's aligned spans.
#include "cli/huge_page_trial.h"

#include <gtest/gtest.h>

namespace omnishadow::cli {
namespace {

constexpr std::uintptr_t kSpan = HugePageTrial::kHugePage;
constexpr std::uintptr_t kBegin = 64 * kSpan;
constexpr double kQuick = 0.3;  // ms: a huge page the host still backs
constexpr double kSlow = 5.0;   // ms: one the host must back again

TEST(HugePageTrial, AsksSpanBySpanWhileHugePagesFaultQuickly) {
  HugePageTrial trial(kBegin, kBegin + 8 * kSpan);
  for (int i = 0; i < 8; ++i) {
    const std::uintptr_t span = kBegin + i * kSpan;
    ASSERT_TRUE(trial.asks(span, span + kSpan)) << "span " << i;
    trial.touched(span, span + kSpan, kQuick);
  }
  EXPECT_FALSE(trial.givenUp());
}

TEST(HugePageTrial, GivesUpAtTheFirstSlowHugePageForTheRestOfTheBlock) {
  HugePageTrial trial(kBegin, kBegin + 8 * kSpan);
  trial.touched(kBegin, kBegin + kSpan, kQuick);
  trial.touched(kBegin + kSpan, kBegin + 2 * kSpan, kSlow);
  EXPECT_TRUE(trial.givenUp());
  for (int i = 2; i < 8; ++i)
    EXPECT_FALSE(trial.asks(kBegin + i * kSpan, kBegin + (i + 1) * kSpan)) << "span " << i;
  // Quick spans after it do not bring huge pages back.
  trial.touched(kBegin + 2 * kSpan, kBegin + 3 * kSpan, kQuick);
  EXPECT_FALSE(trial.asks(kBegin + 3 * kSpan, kBegin + 4 * kSpan));
}

TEST(HugePageTrial, TheThresholdIsTwoMilliseconds) {
  HugePageTrial quick(kBegin, kBegin + 2 * kSpan);
  quick.touched(kBegin, kBegin + kSpan, HugePageTrial::kSlowMilliseconds);
  EXPECT_FALSE(quick.givenUp());
  HugePageTrial slow(kBegin, kBegin + 2 * kSpan);
  slow.touched(kBegin, kBegin + kSpan, HugePageTrial::kSlowMilliseconds + 0.01);
  EXPECT_TRUE(slow.givenUp());
}

// 4 KiB pages that take long (the block's unaligned head and tail, where no huge page was
// asked for) say nothing about huge pages.
TEST(HugePageTrial, SlowSpansItDidNotAskForDoNotCount) {
  HugePageTrial trial(kBegin, kBegin + 4 * kSpan);
  trial.touched(kBegin - kSpan + 4096, kBegin, kSlow);           // the head
  trial.touched(kBegin + 4 * kSpan, kBegin + 5 * kSpan, kSlow);  // past the end
  EXPECT_FALSE(trial.givenUp());
  EXPECT_TRUE(trial.asks(kBegin, kBegin + kSpan));
}

TEST(HugePageTrial, NeverAsksForPartOfASpanOrOutsideTheAlignedSpans) {
  HugePageTrial trial(kBegin, kBegin + 4 * kSpan);
  EXPECT_FALSE(trial.asks(kBegin - kSpan, kBegin));
  EXPECT_FALSE(trial.asks(kBegin + 4 * kSpan, kBegin + 5 * kSpan));
  EXPECT_FALSE(trial.asks(kBegin, kBegin + kSpan / 2));
  EXPECT_FALSE(trial.asks(kBegin + 3 * kSpan, kBegin + 5 * kSpan));
  HugePageTrial none(kBegin, kBegin);  // a block smaller than one aligned span
  EXPECT_FALSE(none.asks(kBegin, kBegin + kSpan));
}

}  // namespace
}  // namespace omnishadow::cli
