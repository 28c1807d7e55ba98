#pragma once
// The contract between the app (image_io.cpp) and its OpenImageIO module
// (image_io_oiio.cpp, built as lib/effigi/image-oiio.so beside the component modules):
// one C entry point, looked up with dlsym, that never throws. Both sides are built
// together, so the C++ types in the signature are safe to pass.
#include "effigi/interfaces/ifilm.hpp"

#include <string>

namespace effigi::app::oiio {

/// File name of the module, in <libdir>/effigi.
inline constexpr const char* ModuleFile = "image-oiio.so";
/// Name of the entry point.
inline constexpr const char* ReadRGBSymbol = "effigiReadImageRGB";
/// Reads R, G, B of `path` into `out` as floats; on failure returns false with a
/// one-line message naming the file in `error`.
using ReadRGB = bool (*)(const char* path, Image& out, std::string& error) noexcept;

} // namespace effigi::app::oiio
