#pragma once
// Spectral OpenEXR files (A. Fichet, R. Pacanowski, A. Wilkie, "An OpenEXR Layout for
// Spectral Images", JCGT 10(3), 2021), written by hdrfilm and read by `effigi convert`.
//
// Layout as effigi writes it: one FLOAT channel per bin named "S0.<centre>nm" (centre with
// six decimals and a comma, e.g. "S0.367,343750nm"), plus "R","G","B" of the film's colour
// space for viewers (with its chromaticities), and the string attributes
//   spectralLayoutVersion = "1.0"
//   emissiveUnits         = "W.m^-2.sr^-1"  (the only emissive unit the layout defines;
//                           the values are spectral radiance per nm, as the layout's
//                           reference reader integrates them against the CMFs, and
//                           effigi/spectralQuantity says so explicitly)
//   effigi/spectralBins, effigi/spectralRange ("<min>,<max>" nm), effigi/spectralQuantity
// and the render's metadata (effigi/scene, effigi/spp, effigi/seconds, effigi/version...).
// Bins are equal and abut, so the layout's default box response (bands meet halfway
// between centres) is exactly the bins.
#include "hdrfilm_io.hpp"

#include "effigi/render/spectral_bins.hpp"

#include <ImfInputFile.h>

#include <algorithm>
#include <map>

namespace effigi::spectral_exr {

namespace fs = std::filesystem;

/// out.exr -> out.spectral.exr (any extension is replaced; none gets one).
inline fs::path spectralPath(fs::path main) {
    main.replace_extension();
    main += ".spectral.exr";
    return main;
}

/// Writes `img` ("R","G","B" of `cs`, then the bin channels) as a spectral EXR.
inline void writeFile(const fs::path& path, const Image& img, const RGBColorSpace& cs, const SpectralBinning& bins,
                      const FilmMetadata& meta) {
    FilmMetadata m = meta;
    m["spectralLayoutVersion"] = "1.0";
    m["emissiveUnits"] = "W.m^-2.sr^-1";
    m["effigi/spectralBins"] = std::to_string(bins.count());
    m["effigi/spectralRange"] = fmt::format("{},{}", bins.lambdaMin(), bins.lambdaMax());
    m["effigi/spectralQuantity"] = "bin average of spectral radiance, W.m^-2.sr^-1.nm^-1";
    hdrfilm_io::writeExr(path, img, /*half=*/false, &cs, m);
}

/// An emissive spectral image: `centers.size()` values per pixel, bands sorted by
/// wavelength, pixels row-major from the top.
struct SpectralImage {
    int width = 0, height = 0;
    std::vector<double> centers;  // nm
    std::vector<float> values;
    std::map<std::string, std::string> attributes;  // the string attributes

    std::size_t bands() const { return centers.size(); }
    const float* pixel(int x, int y) const {
        return values.data() + (std::size_t(y) * std::size_t(width) + std::size_t(x)) * bands();
    }
};

/// Reads the S0 channels (any unit the layout allows) and the string attributes.
/// Throws effigi::Error "cannot read <path>: <reason>".
inline SpectralImage readFile(const fs::path& path) {
    auto cannotRead = [&](const std::string& why) { fail("cannot read {}: {}", path.string(), why); };
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) cannotRead("no such file");
    SpectralImage img;
    try {
        Imf::InputFile file(path.c_str());
        const Imf::Header& header = file.header();
        const Imath::Box2i dw = header.dataWindow();
        img.width = dw.max.x - dw.min.x + 1;
        img.height = dw.max.y - dw.min.y + 1;
        std::vector<std::pair<double, std::string>> channels;
        for (auto it = header.channels().begin(); it != header.channels().end(); ++it)
            if (std::optional<double> l = parseChannelName(it.name())) channels.emplace_back(*l, it.name());
        if (channels.empty())
            cannotRead("no spectral channels (S0.<wavelength>nm, Fichet et al. 2021): not a spectral EXR");
        std::sort(channels.begin(), channels.end());
        for (std::size_t i = 1; i < channels.size(); ++i)
            if (channels[i].first == channels[i - 1].first)
                cannotRead(fmt::format("channels '{}' and '{}' have the same wavelength", channels[i - 1].second,
                                       channels[i].second));
        for (const auto& c : channels) img.centers.push_back(c.first);
        for (auto it = header.begin(); it != header.end(); ++it)
            if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
                img.attributes[it.name()] = s->value();

        const std::size_t n = channels.size();
        img.values.assign(std::size_t(img.width) * std::size_t(img.height) * n, 0.f);
        Imf::FrameBuffer fb;
        for (std::size_t c = 0; c < n; ++c)
            fb.insert(channels[c].second, Imf::Slice::Make(Imf::FLOAT, img.values.data() + c, dw, sizeof(float) * n,
                                                           sizeof(float) * n * std::size_t(img.width)));
        file.setFrameBuffer(fb);
        file.readPixels(dw.min.y, dw.max.y);
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        std::string why = e.what();
        std::replace(why.begin(), why.end(), '\n', ' ');
        cannotRead(why);
    }
    return img;
}

} // namespace effigi::spectral_exr
