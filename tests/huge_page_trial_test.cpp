// Where the memory warm-up asks for transparent huge pages (cli/huge_page_trial.h): span by
// span once it has measured 4 KiB pages, while huge pages fault more quickly than the larger of
// 2 ms and the same bytes in 4 KiB pages, never again after a slow one, never for part of a
// span or outside the block's aligned spans.
#include "cli/huge_page_trial.h"

#include <gtest/gtest.h>

namespace omnishadow::cli {
namespace {

constexpr std::uintptr_t kSpan = HugePageTrial::kHugePage;
constexpr std::uintptr_t kBegin = 64 * kSpan;
constexpr std::uintptr_t kCalibration = HugePageTrial::kCalibrationBytes;
constexpr double kQuick = 0.3;  // ms: a huge page the host still backs
constexpr double kSlow = 5.0;   // ms: one the host must back again
// ms for kCalibrationBytes of 4 KiB pages at 1.8 us a page (0.9 ms per 2 MiB), as on the
// machines the 2 ms bound was measured on, and at 10.6 us (5.4 ms per 2 MiB).
constexpr double kQuickSmallPages = 256 * 0.0018;
constexpr double kSlowSmallPages = 256 * 0.0106;

HugePageTrial calibrated(std::uintptr_t spans, double smallPagesMilliseconds = kQuickSmallPages) {
  HugePageTrial trial(kBegin, kBegin + spans * kSpan);
  trial.touched(false, kCalibration, smallPagesMilliseconds);
  return trial;
}

TEST(HugePageTrial, AsksForNoHugePageBeforeItHasMeasuredAMegabyteOf4KPages) {
  HugePageTrial trial(kBegin, kBegin + 8 * kSpan);
  EXPECT_FALSE(trial.asks(kBegin, kBegin + kSpan));
  trial.touched(false, kCalibration - 4096, kQuickSmallPages);
  EXPECT_FALSE(trial.asks(kBegin, kBegin + kSpan));
  trial.touched(false, 0, 100.0);  // nothing touched: nothing learnt
  EXPECT_FALSE(trial.asks(kBegin, kBegin + kSpan));
  trial.touched(false, 4096, 0.002);
  EXPECT_TRUE(trial.asks(kBegin, kBegin + kSpan));
}

TEST(HugePageTrial, AsksSpanBySpanWhileHugePagesFaultQuickly) {
  HugePageTrial trial = calibrated(8);
  for (int i = 0; i < 8; ++i) {
    const std::uintptr_t span = kBegin + i * kSpan;
    ASSERT_TRUE(trial.asks(span, span + kSpan)) << "span " << i;
    trial.touched(true, kSpan, kQuick);
  }
  EXPECT_FALSE(trial.givenUp());
}

TEST(HugePageTrial, GivesUpAtTheFirstSlowHugePageForTheRestOfTheBlock) {
  HugePageTrial trial = calibrated(8);
  trial.touched(true, kSpan, kQuick);
  trial.touched(true, kSpan, kSlow);
  EXPECT_TRUE(trial.givenUp());
  for (int i = 2; i < 8; ++i)
    EXPECT_FALSE(trial.asks(kBegin + i * kSpan, kBegin + (i + 1) * kSpan)) << "span " << i;
  // Quick spans after it do not bring huge pages back.
  trial.touched(true, kSpan, kQuick);
  trial.touched(false, kSpan, 0.1);
  EXPECT_FALSE(trial.asks(kBegin + 3 * kSpan, kBegin + 4 * kSpan));
}

// Where 4 KiB pages fault quickly the bound is 2 ms, whatever they took.
TEST(HugePageTrial, WhereSmallPagesAreQuickTheBoundIsTwoMilliseconds) {
  for (const double small : {0.0, kQuickSmallPages}) {
    HugePageTrial quick = calibrated(2, small);
    EXPECT_EQ(quick.slowMilliseconds(), HugePageTrial::kSlowMilliseconds);
    quick.touched(true, kSpan, HugePageTrial::kSlowMilliseconds);
    EXPECT_FALSE(quick.givenUp());
    HugePageTrial slow = calibrated(2, small);
    slow.touched(true, kSpan, HugePageTrial::kSlowMilliseconds + 0.01);
    EXPECT_TRUE(slow.givenUp());
  }
}

// Where every 4 KiB fault is expensive, a huge page the host must back again (2.3-3.7 ms) is
// still cheaper than the same 2 MiB in 4 KiB pages (5.4 ms): kept. Slower than those, given up.
TEST(HugePageTrial, WhereSmallPagesAreSlowHugePagesFasterThanThemAreKept) {
  HugePageTrial trial = calibrated(8, kSlowSmallPages);
  EXPECT_NEAR(trial.slowMilliseconds(), 512 * 0.0106, 1e-9);
  trial.touched(true, kSpan, 3.7);
  trial.touched(true, kSpan, 0.12);
  EXPECT_FALSE(trial.givenUp());
  EXPECT_TRUE(trial.asks(kBegin + 2 * kSpan, kBegin + 3 * kSpan));
  trial.touched(true, kSpan, 512 * 0.0106 + 0.01);
  EXPECT_TRUE(trial.givenUp());
}

// The bound follows every span touched in 4 KiB pages, by the bytes touched: the unaligned
// head, spans cut short, spans after huge pages were given up.
TEST(HugePageTrial, TheBoundIsTheMeanOfAllSmallPagesTouched) {
  HugePageTrial trial(kBegin, kBegin + 4 * kSpan);
  trial.touched(false, kSpan / 2, 0.5 * 512 * 0.004);  // 4 us a page
  trial.touched(false, kSpan / 2, 0.5 * 512 * 0.012);  // 12 us a page
  EXPECT_NEAR(trial.slowMilliseconds(), 512 * 0.008, 1e-9);
}

TEST(HugePageTrial, NeverAsksForPartOfASpanOrOutsideTheAlignedSpans) {
  const HugePageTrial trial = calibrated(4);
  EXPECT_TRUE(trial.asks(kBegin, kBegin + kSpan));
  EXPECT_FALSE(trial.asks(kBegin - kSpan, kBegin));
  EXPECT_FALSE(trial.asks(kBegin + 4 * kSpan, kBegin + 5 * kSpan));
  EXPECT_FALSE(trial.asks(kBegin, kBegin + kSpan / 2));
  EXPECT_FALSE(trial.asks(kBegin + 3 * kSpan, kBegin + 5 * kSpan));
  HugePageTrial none(kBegin, kBegin);  // a block smaller than one aligned span
  none.touched(false, kCalibration, kQuickSmallPages);
  EXPECT_FALSE(none.asks(kBegin, kBegin + kSpan));
}

}  // namespace
}  // namespace omnishadow::cli
