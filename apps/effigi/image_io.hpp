#pragma once
// Image files for the app's own use (references, reports). EXR is read with OpenEXR and
// PNG written with zlib (components/film/hdrfilm_png.hpp); only a reference in another
// format (PNG, JPEG, HDR, ...) needs OpenImageIO, which lives in a module of its own,
// lib/effigi/image-oiio.so (image_io_oiio.hpp), loaded on that first use. So `render`,
// `info`, `list`, `convert` and `converge` with an EXR reference load no OpenImageIO.
#include "effigi/interfaces/ifilm.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace effigi::app {

/// R, G, B of an image file (EXR, or any format OpenImageIO reads), as floats as stored
/// (an 8-bit file gives its code values / 255); throws effigi::Error naming the file
/// when it cannot.
Image readRGB(const std::filesystem::path& path);

/// An 8-bit sRGB-encoded PNG of linear RGB values (3 floats per pixel, clamped to [0,1]).
void writePNG(const std::filesystem::path& path, int width, int height, const std::vector<float>& rgb);

/// A perceptually ordered false-colour map of values in [0, 1] (dark blue -> yellow),
/// for error images.
std::vector<float> falseColour(const std::vector<float>& values, float maxValue);

} // namespace effigi::app
