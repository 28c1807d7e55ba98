#pragma once
// Image files for the app's own use (references, reports) through OpenImageIO.
#include "effigi/interfaces/ifilm.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace effigi::app {

/// R, G, B of an image file (EXR or any format OpenImageIO reads), as linear floats;
/// throws effigi::Error naming the file when it cannot.
Image readRGB(const std::filesystem::path& path);

/// An 8-bit sRGB-encoded PNG of linear RGB values (3 floats per pixel, clamped to [0,1]).
void writePNG(const std::filesystem::path& path, int width, int height, const std::vector<float>& rgb);

/// A perceptually ordered false-colour map of values in [0, 1] (dark blue -> yellow),
/// for error images.
std::vector<float> falseColour(const std::vector<float>& values, float maxValue);

/// String value of an EXR header attribute, empty if absent.
std::string readAttribute(const std::filesystem::path& path, const std::string& name);

} // namespace effigi::app
