#pragma once

#include <stdexcept>
#include <string>

namespace omnishadow {

// The user's input is wrong (a file, a field, an option). The CLI prints the message on one
// line and exits with status 2. Messages name the file and the field, e.g.
// "lights.json: lights[2].position: expected an array of 3 finite numbers".
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Anything else that failed while rendering or writing (no GL context, GL error, disk full).
// The CLI prints the message and exits with status 1.
class RenderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace omnishadow
