// Where the memory warm-up asks for transparent huge pages (cli/huge_page_trial.h): span by
// span once it has measured 4 KiB pages, while huge pages fault more quickly than the larger of
// 2 ms and the same bytes in 4 KiB pages, never again after a slow one, never for part of a
// span or outside the block's aligned spans.
#include "cli/huge_page_trial.h"

#include <gtest/gtest.h>

namespace omnishadow::cli::huge_page_trial_test {
namespace {

constexpr std::uintptr_t kSpan = HugePageTrial::kHugePage;
constexpr std::uintptr_t kBegin = 64 * kSpan;
constexpr std::uintptr_t kHead = kBegin - kSpan;  // the span holding the block's unaligned head
constexpr std::uintptr_t kCalibration = HugePageTrial::kCalibrationBytes;
constexpr double kQuick = 0.3;  // ms: a huge page the host still backs
constexpr double kSlow = 5.0;   // ms: one the host must back again
// ms for kCalibrationBytes of 4 KiB pages at 1.8 us a page (0.9 ms per 2 MiB), as on the
// machines the 2 ms bound was measured on, and at 10.6 us (5.4 ms per 2 MiB).
constexpr double kQuickSmallPages = 256 * 0.0018;
constexpr double kSlowSmallPages = 256 * 0.0106;

std::uintptr_t span(int i) {
  return kBegin + static_cast<std::uintptr_t>(i) * kSpan;
}

HugePageTrial calibrated(int spans, double smallPagesMilliseconds = kQuickSmallPages) {
  HugePageTrial trial(kBegin, span(spans));
  trial.touched(kHead, false, kCalibration, smallPagesMilliseconds);
  return trial;
}

TEST(HugePageTrial, AsksForNoHugePageBeforeItHasMeasuredAMegabyteOf4KPages) {
  HugePageTrial trial(kBegin, span(8));
  EXPECT_FALSE(trial.asks(span(0), span(1)));
  trial.touched(kHead, false, kCalibration - 4096, kQuickSmallPages);
  EXPECT_FALSE(trial.asks(span(0), span(1)));
  trial.touched(kHead, false, 0, 100.0);  // nothing touched: nothing learnt
  EXPECT_FALSE(trial.asks(span(0), span(1)));
  trial.touched(span(0), false, 4096, 0.002);
  EXPECT_TRUE(trial.asks(span(1), span(2)));
}

TEST(HugePageTrial, AsksSpanBySpanWhileHugePagesFaultQuickly) {
  HugePageTrial trial = calibrated(8);
  for (int i = 0; i < 8; ++i) {
    ASSERT_TRUE(trial.asks(span(i), span(i + 1))) << "span " << i;
    trial.touched(span(i), true, kSpan, kQuick);
  }
  EXPECT_FALSE(trial.givenUp());
}

TEST(HugePageTrial, GivesUpAtTheFirstSlowHugePageForTheRestOfTheBlock) {
  HugePageTrial trial = calibrated(8);
  trial.touched(span(0), true, kSpan, kQuick);
  trial.touched(span(1), true, kSpan, kSlow);
  EXPECT_TRUE(trial.givenUp());
  for (int i = 2; i < 8; ++i) EXPECT_FALSE(trial.asks(span(i), span(i + 1))) << "span " << i;
  // Quick spans after it do not bring huge pages back.
  trial.touched(span(2), false, kSpan, 0.1);
  EXPECT_FALSE(trial.asks(span(3), span(4)));
}

// Where 4 KiB pages fault quickly the bound is 2 ms, whatever they took.
TEST(HugePageTrial, WhereSmallPagesAreQuickTheBoundIsTwoMilliseconds) {
  for (const double small : {0.0, kQuickSmallPages}) {
    HugePageTrial quick = calibrated(2, small);
    EXPECT_EQ(quick.slowMilliseconds(), HugePageTrial::kSlowMilliseconds);
    quick.touched(span(0), true, kSpan, HugePageTrial::kSlowMilliseconds);
    EXPECT_FALSE(quick.givenUp());
    HugePageTrial slow = calibrated(2, small);
    slow.touched(span(0), true, kSpan, HugePageTrial::kSlowMilliseconds + 0.01);
    EXPECT_TRUE(slow.givenUp());
  }
}

// Where every 4 KiB fault is expensive, a huge page the host must back again (2.3-3.7 ms) is
// still cheaper than the same 2 MiB in 4 KiB pages (5.4 ms): kept. Slower than those, given up.
TEST(HugePageTrial, WhereSmallPagesAreSlowHugePagesFasterThanThemAreKept) {
  HugePageTrial trial = calibrated(8, kSlowSmallPages);
  EXPECT_NEAR(trial.slowMilliseconds(), 512 * 0.0106, 1e-9);
  trial.touched(span(0), true, kSpan, 3.7);
  trial.touched(span(1), true, kSpan, 0.12);
  EXPECT_FALSE(trial.givenUp());
  EXPECT_TRUE(trial.asks(span(2), span(3)));
  trial.touched(span(2), true, kSpan, 512 * 0.0106 + 0.01);
  EXPECT_TRUE(trial.givenUp());
}

// The bound follows every span touched in 4 KiB pages, by the bytes touched: the unaligned
// head, spans cut short, spans after huge pages were given up.
TEST(HugePageTrial, TheBoundIsTheMeanOfAllSmallPagesTouched) {
  HugePageTrial trial(kBegin, span(4));
  trial.touched(kHead, false, kSpan / 2, 0.5 * 512 * 0.004);    // 4 us a page
  trial.touched(span(0), false, kSpan / 2, 0.5 * 512 * 0.012);  // 12 us a page
  EXPECT_NEAR(trial.slowMilliseconds(), 512 * 0.008, 1e-9);
}

// What a 4 KiB page costs is known once the calibration's megabyte is measured (a render
// prepares nothing ahead of the frame where it is dear), and huge pages do not count in it.
TEST(HugePageTrial, Measures4KPagesOnceItHasTheCalibrationsMegabyte) {
  HugePageTrial trial(kBegin, span(4));
  trial.touched(kHead, false, kCalibration / 2, kSlowSmallPages / 2);
  EXPECT_EQ(trial.smallPageMicroseconds(), 0.0);
  trial.touched(kHead, false, kCalibration / 2, kSlowSmallPages / 2);
  EXPECT_NEAR(trial.smallPageMicroseconds(), 10.6, 1e-9);
  ASSERT_TRUE(trial.asks(span(0), span(1)));
  trial.touched(span(0), true, kSpan, 0.15);
  EXPECT_NEAR(trial.smallPageMicroseconds(), 10.6, 1e-9);
  trial.touched(span(1), false, kCalibration, kQuickSmallPages);
  EXPECT_NEAR(trial.smallPageMicroseconds(), (10.6 + 1.8) / 2, 1e-9);
}

// A span asked for and cut short after its first page (the block handed over) lies in its huge
// page: its rest, touched after the hand-over, faults nothing and is no measure of 4 KiB pages
// (a first version counted it, which brought the bound down to 2 ms and gave huge pages up).
TEST(HugePageTrial, TheRestOfASpanAskedForIsNotCountedAs4KPages) {
  HugePageTrial trial = calibrated(4, kSlowSmallPages);
  ASSERT_TRUE(trial.asks(span(0), span(1)));
  trial.touched(span(0), true, 4096, 3.6);
  trial.touched(span(0), false, kSpan - 4096, 0.012);
  EXPECT_NEAR(trial.slowMilliseconds(), 512 * 0.0106, 1e-9);
  trial.touched(span(1), true, kSpan, 3.8);
  EXPECT_FALSE(trial.givenUp());
  // Any other span touched in 4 KiB pages counts.
  trial.touched(span(2), false, kSpan, 0.5);
  EXPECT_LT(trial.slowMilliseconds(), 512 * 0.0106);
}

TEST(HugePageTrial, NeverAsksForPartOfASpanOrOutsideTheAlignedSpans) {
  const HugePageTrial trial = calibrated(4);
  EXPECT_TRUE(trial.asks(span(0), span(1)));
  EXPECT_FALSE(trial.asks(kHead, kBegin));
  EXPECT_FALSE(trial.asks(span(4), span(5)));
  EXPECT_FALSE(trial.asks(span(0), span(0) + kSpan / 2));
  EXPECT_FALSE(trial.asks(span(3), span(5)));
  HugePageTrial none(kBegin, kBegin);  // a block smaller than one aligned span
  none.touched(kHead, false, kCalibration, kQuickSmallPages);
  EXPECT_FALSE(none.asks(span(0), span(1)));
}

}  // namespace
}  // namespace omnishadow::cli::huge_page_trial_test
