// The renderer's ways of spreading per-item work over threads: each item made once, whatever the
// threads, and made before the caller is told it is ready.
#include "renderer/core/in_parts.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

namespace in_parts_test {

using namespace omnishadow;

TEST(InParts, EveryItemIsMadeOnceHoweverManyParts) {
  for (const std::size_t count : {0, 1, 5, 16, 100, 257}) {
    for (const std::size_t parts : {1, 2, 3, 7, 16}) {
      std::vector<int> made(count, 0);
      inParts(count, parts, [&](std::size_t, std::size_t first, std::size_t end) {
        for (std::size_t i = first; i < end; ++i) ++made[i];
      });
      EXPECT_EQ(made, std::vector<int>(count, 1)) << count << " items in " << parts << " parts";
    }
  }
}

TEST(InParts, PartsForSpreadsOnlyWhereThereIsWorkEnough) {
  EXPECT_EQ(partsFor(0), 1u);
  EXPECT_EQ(partsFor(15), 1u);
  for (const std::size_t count : {16, 64, 256, 10000}) {
    EXPECT_GE(partsFor(count), 1u);
    EXPECT_LE(partsFor(count), 16u);
    EXPECT_LE(partsFor(count), count / 8);
  }
}

TEST(InOrderAhead, EachItemIsMadeOnceAndBeforeReadySaysSo) {
  for (const std::size_t count : {1, 5, 16, 100, 257}) {
    for (const std::size_t threads : {1, 2, 3, 16}) {
      std::vector<std::atomic<int>> made(count);
      {
        InOrderAhead ahead(count, threads, [&](std::size_t first, std::size_t end) {
          for (std::size_t i = first; i < end; ++i) {
            // Later items take longer, so that a ready() that did not wait would be seen.
            std::this_thread::sleep_for(std::chrono::microseconds(i % 7 * 20));
            made[i].fetch_add(1);
          }
        });
        for (std::size_t i = 0; i < count; ++i) {
          ahead.ready(i);
          ASSERT_EQ(made[i].load(), 1)
              << "item " << i << " of " << count << ", " << threads << " threads";
        }
      }
      for (std::size_t i = 0; i < count; ++i) EXPECT_EQ(made[i].load(), 1);
    }
  }
}

TEST(InOrderAhead, OneThreadMakesTheItemsInOrder) {
  std::vector<std::size_t> order;
  {
    InOrderAhead ahead(50, 1, [&](std::size_t first, std::size_t end) {
      for (std::size_t i = first; i < end; ++i) order.push_back(i);
    });
    ahead.ready(49);
  }
  ASSERT_EQ(order.size(), 50u);
  for (std::size_t i = 0; i < order.size(); ++i) EXPECT_EQ(order[i], i);
}

TEST(InOrderAhead, WhatARangeThrowsComesOutOfReadyForItsItems) {
  InOrderAhead ahead(100, 4, [&](std::size_t first, std::size_t end) {
    for (std::size_t i = first; i < end; ++i)
      if (i == 60) throw std::runtime_error("item 60");
  });
  for (std::size_t i = 0; i < 50; ++i) ahead.ready(i);  // ranges before item 60's: made
  try {
    for (std::size_t i = 50; i < 100; ++i) ahead.ready(i);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "item 60");
  }
}

TEST(InOrderAhead, LeavingEarlyStopsTheRangesNotBegun) {
  std::atomic<std::size_t> made{0};
  const std::size_t count = 400;
  {
    // Two threads, 400 items of 5 ms: a second if nothing stopped them; ready(0) comes after one
    // range (a 64th of the items), so half of them left is a wide margin on a loaded machine.
    InOrderAhead ahead(count, 2, [&](std::size_t first, std::size_t end) {
      for (std::size_t i = first; i < end; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        made.fetch_add(1);
      }
    });
    ahead.ready(0);
  }  // the caller is done (an error thrown while drawing): its work must not go on
  const std::size_t atExit = made.load();
  EXPECT_LT(atExit, count / 2);
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  EXPECT_EQ(made.load(), atExit) << "a range ran after the destructor returned";
}

}  // namespace in_parts_test
