#include <cstdint>
#include <random>

#include "renderer/scene/scene.h"

namespace omnishadow {

std::uint64_t newSceneRevision() {
  // A generator per thread, seeded from the system: loaders on several threads share nothing,
  // and two of 2^64 values collide with a chance no renderer meets.
  thread_local std::mt19937_64 generator{[] {
    std::random_device device;
    return (static_cast<std::uint64_t>(device()) << 32) ^ device();
  }()};
  std::uint64_t revision = 0;
  while (revision == 0) revision = generator();
  return revision;
}

}  // namespace omnishadow
