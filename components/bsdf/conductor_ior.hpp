#pragma once
// The `material` / `eta` / `k` parameters shared by the conductor BSDFs (conductor,
// roughconductor), as Mitsuba 3 has them: a measured material by name (data/spectra/
// <name>-eta.csv and <name>-k.csv: Mitsuba's preset names, data from refractiveindex.info,
// see data/README.md), or an explicit complex index η + ik, or "none" — a 100 % mirror
// (η = 0, k = 1).
#include "effigi/core/input.hpp"
#include "effigi/core/properties.hpp"
#include "effigi/core/schema.hpp"
#include "effigi/interfaces/itexture.hpp"
#include "effigi/render/constant_texture.hpp"
#include "effigi/spectral/named.hpp"

#include <fmt/ranges.h>

#include <algorithm>
#include <iterator>
#include <string_view>

namespace effigi {

/// Metals with both <name>-eta and <name>-k among the named spectra.
inline std::vector<std::string> measuredMetals() {
    std::vector<std::string> names = namedSpectrumNames(), metals;
    const std::string suffix = "-eta";
    for (const std::string& n : names) {
        if (n.size() <= suffix.size() || n.compare(n.size() - suffix.size(), suffix.size(), suffix) != 0) continue;
        std::string metal = n.substr(0, n.size() - suffix.size());
        if (std::binary_search(names.begin(), names.end(), metal + "-k")) metals.push_back(metal);
    }
    return metals;
}

/// Mitsuba 3 presets for which refractiveindex.info has no usable 360-830 nm data, so effigi
/// ships none (data/generate_ior.py, MISSING; data/README.md says why for each): named in the
/// error so that a scene author knows the name is right but the data is absent, rather than
/// misspelt.
inline constexpr std::string_view kMissingPresets[] = {"Cu2O", "Cu2O_palik", "CuO", "CuO_palik", "HgTe",
                                                       "HgTe_palik", "Se", "Se_palik", "SnTe", "SnTe_palik"};

inline void declareConductorIOR(Schema& s) {
    s.string("material", "none",
             "Measured material: a Mitsuba 3 preset name (Au, Ag, Cu, Al, a-C, TiN, Hg, ..., see data/README.md), or none: a 100 % mirror (η = 0, k = 1)");
    ParamSpec& eta = s.optional("eta", ParamType::Texture, "Real part η of the complex IOR (default 0), instead of material");
    eta.spectrumKind = SpectrumKind::Unbounded;
    eta.componentTag = "texture";
    eta.atLeast(0.0);
    ParamSpec& k = s.optional("k", ParamType::Texture, "Extinction coefficient k of the complex IOR (default 1), instead of material");
    k.spectrumKind = SpectrumKind::Unbounded;
    k.componentTag = "texture";
    k.atLeast(0.0);
}

/// The complex index η + ik relative to the outside, as textures.
struct ConductorIOR {
    Ref<ITexture> eta, k;
};

inline ConductorIOR readConductorIOR(const Properties& p) {
    const std::string& material = p.getString("material");
    if (material == "none") {
        return {p.has("eta") ? p.getTexture("eta", SpectrumKind::Unbounded) : std::make_shared<ConstantTexture>(Spectrum(0.f)),
                p.has("k") ? p.getTexture("k", SpectrumKind::Unbounded) : std::make_shared<ConstantTexture>(Spectrum(1.f))};
    }
    if (p.has("eta") || p.has("k"))
        failAt(p.whereOf(p.has("eta") ? "eta" : "k"),
               "{}: give either 'material' or 'eta' and 'k', not both (material = '{}')", p.describe(),
               excerpt(material));
    std::vector<std::string> metals = measuredMetals();
    if (std::find(metals.begin(), metals.end(), material) == metals.end()) {
        if (std::find(std::begin(kMissingPresets), std::end(kMissingPresets), material) != std::end(kMissingPresets))
            failAt(p.whereOf("material"),
                   "{}: parameter 'material' = '{}' is a Mitsuba preset that effigi has no data for "
                   "(refractiveindex.info has no usable 360-830 nm measurement, see data/README.md); "
                   "give 'eta' and 'k' instead",
                   p.describe(), excerpt(material));
        std::vector<std::string> choices = metals;
        choices.push_back("none");
        std::string hint = didYouMean(material, choices);
        failAt(p.whereOf("material"), "{}: parameter 'material' = '{}' has no measured data{} (available: {})",
               p.describe(), excerpt(material), hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint),
               fmt::join(choices, ", "));
    }
    return {std::make_shared<ConstantTexture>(namedSpectrum(material + "-eta")),
            std::make_shared<ConstantTexture>(namedSpectrum(material + "-k"))};
}

} // namespace effigi
