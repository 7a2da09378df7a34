#include "renderer/scene/mipmap_queue.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <future>
#include <random>
#include <vector>

#include "renderer/scene/image_mipmaps.h"

namespace omnishadow::mipmap_queue_test {
namespace {

Image noise(int width, int height, std::uint32_t seed) {
  Image image;
  image.name = "noise";
  image.width = width;
  image.height = height;
  image.rgba.resize(static_cast<std::size_t>(width) * height * 4);
  std::mt19937 random(seed);
  for (std::uint8_t& byte : image.rgba) byte = static_cast<std::uint8_t>(random() & 0xffu);
  return image;
}

void expectSameChain(const std::vector<Image>& actual, const std::vector<Image>& expected) {
  ASSERT_EQ(actual.size(), expected.size());
  for (std::size_t level = 0; level < actual.size(); ++level) {
    EXPECT_EQ(actual[level].width, expected[level].width);
    EXPECT_EQ(actual[level].height, expected[level].height);
    EXPECT_TRUE(actual[level].rgba == expected[level].rgba) << "level " << level + 1;
  }
}

// Even and odd sides, one large enough for level 1 on two threads, sRGB and linear.
struct Case {
  int width, height;
  bool srgb;
};
const Case kCases[] = {{1024, 512, true}, {37, 5, false}, {64, 64, false},
                       {513, 1, true},    {1, 1, true},   {600, 600, false}};

TEST(MipmapQueue, ChainsComeOutAsMipmapChainMakesThemWhicheverThreadMakesThem) {
  std::vector<Image> images;
  for (std::size_t i = 0; i < std::size(kCases); ++i)
    images.push_back(noise(kCases[i].width, kCases[i].height, static_cast<std::uint32_t>(i)));
  for (const bool ownThread : {true, false}) {
    SCOPED_TRACE(ownThread ? "own thread" : "caller's thread");
    MipmapQueue queue(ownThread);
    std::vector<std::future<std::vector<Image>>> chains;
    for (std::size_t i = 0; i < images.size(); ++i)
      chains.push_back(queue.add(images[i], kCases[i].srgb));
    for (std::size_t i = 0; i < images.size(); ++i) {
      SCOPED_TRACE(i);
      expectSameChain(chains[i].get(), mipmapChain(images[i], kCases[i].srgb));
    }
  }
}

TEST(MipmapQueue, WithoutAThreadOfItsOwnEachChainIsMadeBeforeAddReturns) {
  const Image image = noise(256, 256, 7);
  MipmapQueue queue(false);
  std::future<std::vector<Image>> chain = queue.add(image, true);
  EXPECT_EQ(chain.wait_for(std::chrono::seconds(0)), std::future_status::ready);
  EXPECT_EQ(chain.get().size(), 8u);
}

TEST(MipmapQueue, ALeftQueueFinishesTheChainItIsMakingAndDropsTheRest) {
  // A renderer whose upload throws leaves its queue with chains nobody will take: the queue
  // must neither hang nor make them, and what it made must be whole.
  std::vector<Image> images;
  for (std::uint32_t i = 0; i < 12; ++i) images.push_back(noise(1024, 1024, i));
  std::vector<std::future<std::vector<Image>>> chains;
  {
    MipmapQueue queue;
    for (const Image& image : images) chains.push_back(queue.add(image, false));
  }
  int made = 0, dropped = 0;
  for (std::size_t i = 0; i < chains.size(); ++i) {
    try {
      const std::vector<Image> chain = chains[i].get();
      ++made;
      expectSameChain(chain, mipmapChain(images[i], false));
    } catch (const std::future_error& error) {
      EXPECT_EQ(error.code(), std::future_errc::broken_promise);
      ++dropped;
    }
  }
  EXPECT_EQ(made + dropped, 12);
}

}  // namespace
}  // namespace omnishadow::mipmap_queue_test
