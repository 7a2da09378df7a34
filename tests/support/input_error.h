#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "renderer/core/errors.h"

namespace omnishadow::test_support {

// The message of the InputError that `load` throws, checked to be one line; fails the test if it
// throws none.
inline std::string inputError(const std::function<void()>& load) {
  try {
    load();
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << "not one line: " << message;
    return message;
  }
  ADD_FAILURE() << "no InputError thrown";
  return "";
}

}  // namespace omnishadow::test_support
