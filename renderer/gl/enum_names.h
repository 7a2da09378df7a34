#pragma once

#include <cstddef>

namespace omnishadow::gl {

// A GL or EGL enum value and its name in the headers, for messages.
template <typename T>
struct EnumName {
  T value;
  const char* name;
};

// {GL_OUT_OF_MEMORY, "GL_OUT_OF_MEMORY"}: each name written once, so it cannot drift from its
// value.
#define OMNISHADOW_ENUM_NAME(value) \
  { value, #value }

// The name of `value` in `names`; `fallback` when it is not there.
template <typename T, std::size_t N>
const char* nameOf(T value, const EnumName<T> (&names)[N], const char* fallback) {
  for (const EnumName<T>& entry : names)
    if (entry.value == value) return entry.name;
  return fallback;
}

}  // namespace omnishadow::gl
