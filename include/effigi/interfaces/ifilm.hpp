#pragma once
// IFilm — accumulates filtered samples and writes the image. Renderers declare their
// channels: "X","Y","Z" (spectral radiance as CIE XYZ, converted to the output colour
// space when written) or raw AOV channels written as they are.
//
// Crop windows. A film of fullSize() pixels may render and write only the crop window
// [cropOffset(), cropOffset() + size()). Everything a renderer touches is in the crop's
// frame: it renders pixels [0, size()), creates blocks there and splats at crop-relative
// positions p. The camera, which projects over the full film, receives
// CameraSample::pFilm = p + cropOffset(). Films without a crop window keep the
// defaults (cropOffset() = 0, fullSize() = size()).
//
// Spectral bins. A film with spectralBins() = N > 0 also wants the per-bin averages of
// spectral radiance over N equal bins of spectralRange() (nm): renderers that can
// (path) add the channels SpectralBinning(N, range).channelNames() to their channel list
// and splat SpectralBinning::estimate() values into them (effigi/render/spectral_bins.hpp).
// Renderers that cannot simply leave them out; the film then writes no spectral image.
#include "effigi/core/component.hpp"
#include "effigi/render/image_block.hpp"

#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace effigi {

class IFilter;

/// A developed image: `channels` floats per pixel, row-major, top row first.
struct Image {
    int width = 0, height = 0;
    std::vector<std::string> channelNames;
    std::vector<float> pixels;

    int channels() const { return int(channelNames.size()); }
    float at(int x, int y, int c) const { return pixels[(std::size_t(y) * width + x) * channels() + c]; }
};

/// Key-value pairs written into the image header (spp, time, scene, version).
using FilmMetadata = std::map<std::string, std::string>;

class IFilm : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IFilm");
    static constexpr const char* Tag = "film";

    /// Size of the rendered (crop) window in pixels: renderers render [0, size()).
    virtual Vector2i size() const = 0;
    /// Size of the whole film; cameras use it for their projection (aspect, fov).
    virtual Vector2i fullSize() const { return size(); }
    /// Top-left pixel of the crop window within the full film; add it to crop-relative
    /// film positions before handing them to the camera.
    virtual Point2i cropOffset() const { return Point2i(0); }
    virtual const IFilter& filter() const = 0;
    /// Number of spectral bins the film records (0: none).
    virtual int spectralBins() const { return 0; }
    /// Wavelength range [min, max] in nm covered by the spectral bins.
    virtual std::pair<float, float> spectralRange() const { return {360.f, 830.f}; }

    /// Allocate storage for these channels and clear it.
    virtual void prepare(const std::vector<std::string>& channels) = 0;
    /// A block for the crop-frame pixel rectangle [offset, offset + size), with a filter
    /// border, holding the channels given to prepare().
    virtual ImageBlock createBlock(Point2i offset, Vector2i size) const = 0;
    /// Merge a block, border included, clipped to the crop window (thread-safe).
    virtual void put(const ImageBlock& block) = 0;

    /// The weighted-average image of the crop window: XYZ channels become linear sRGB
    /// "R","G","B" (or as the film's pixel format says); other channels are copied.
    virtual Image develop() const = 0;
    /// Write the image; the extension picks the format (.exr; .png also written beside
    /// an .exr when the film asks for it). Returns the files written. Throws
    /// effigi::Error "cannot write <path>: <reason>"; missing directories are not created.
    virtual std::vector<std::filesystem::path> write(const std::filesystem::path& path,
                                                     const FilmMetadata& meta) const = 0;
};

} // namespace effigi
