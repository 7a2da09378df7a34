#pragma once

// What tests need to know about the GL fault library (gl_fault.cpp): a scene with a texture of
// this size makes the run meet the fault chosen by OMNISHADOW_GL_FAULT ("error", "reset", "crash"
// or "hang").
// The library's path is OMNISHADOW_GL_FAULT_LIBRARY in the tests that use it.

namespace omnishadow::test_support {

constexpr int kGlFaultMarkerWidth = 7;
constexpr int kGlFaultMarkerHeight = 3;

}  // namespace omnishadow::test_support
