// The glTF extensions the loader knows, and what it does with a file that lists them.
#pragma once

#include <span>
#include <string_view>

namespace omnishadow {

enum class ExtensionStatus {
  Supported,     // implemented: drawn as the extension means
  FallbackOnly,  // drawn through the file's core-glTF fallback (a PNG beside a KTX2 image);
                 // refused when required, since a file then need not have a fallback
  NotSupported,  // not implemented: refused when required, drawn without it when only used
};

struct KnownExtension {
  std::string_view name;
  ExtensionStatus status;
  // FallbackOnly and NotSupported: what a file that only uses the extension is drawn with.
  std::string_view drawnInstead;
};

// Every extension the loader has an answer for: the README's "Scene support" table in code.
std::span<const KnownExtension> knownExtensions();
// nullptr for an extension the table does not list (refused when required, else ignored).
const KnownExtension* findKnownExtension(std::string_view name);

}  // namespace omnishadow
