#pragma once
// effigi.Scene: a loaded scene and its renders as NumPy arrays. Loading is the CLI's
// (xml::parseFile/parseString with $-defaults, then loadScene), rendering is the CLI's
// (the renderer's render(), or renderProgressive for a sample count), so an image equals
// `effigi render` for the same seed and sample count.
#include "effigi/render/scene.hpp"
#include "effigi/spectral/colorspace.hpp"
#include "effigi/xml/parser.hpp"

#include "spectral_exr.hpp"  // components/film: hdrfilm's spectral EXR reader

#include <pybind11/pybind11.h>

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace effigi::python {

namespace py = pybind11;

/// Pixels (height × width × `channels` floats, row-major) handed to NumPy without a copy:
/// an H×W×`used` float32 array showing the first `used` channels of each pixel.
py::object handOver(std::vector<float>&& pixels, int height, int width, int channels, int used);

class PyScene {
public:
    /// `defines`: the CLI's -D name=value. `spectralBins`: sets spectral_bins on the film.
    static PyScene fromFile(const std::string& path, const std::map<std::string, std::string>& defines,
                            std::optional<int> spectralBins);
    static PyScene fromString(const std::string& xml, const std::map<std::string, std::string>& defines,
                              std::optional<int> spectralBins);

    /// Renders and returns H×W×3 float32 in `space` (default: the film's colour space), or
    /// with `spectral` the tuple (H×W×N bin averages, N bin centres in nm).
    py::object render(std::optional<std::uint64_t> spp, std::uint64_t seed, int threads,
                      const std::optional<std::string>& space, bool spectral, bool progress);

    py::tuple size() const;
    std::string rendererName() const { return m_scene->renderer().typeName(); }
    int spectralBins() const;
    const std::string& colorSpace() const { return m_colorSpace; }
    const std::string& source() const { return m_source; }
    py::dict stats() const;
    std::string repr() const;

private:
    PyScene(std::unique_ptr<xml::Node> root, std::optional<int> spectralBins);
    /// The colour space of render(space=...); null for XYZ. Throws for an unknown name.
    static const RGBColorSpace* outputSpace(const std::string& name);
    /// The film's image in `target` (null: XYZ), its AOVs after the three colour channels.
    Image developColour(const RGBColorSpace* target) const;
    /// The film's spectral bins, through hdrfilm's spectral EXR.
    spectral_exr::SpectralImage developSpectral() const;

    std::unique_ptr<Scene> m_scene;
    std::string m_source;      // the scene file, or "<string>"
    std::string m_colorSpace;  // the film's `colorspace` (its EXR's primaries)
    std::optional<RenderStats> m_stats;
    std::unique_ptr<std::mutex> m_rendering = std::make_unique<std::mutex>();
};

} // namespace effigi::python
