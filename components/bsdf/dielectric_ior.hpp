#pragma once
// The `int_ior` / `ext_ior` parameters shared by the dielectric BSDFs (dielectric,
// thindielectric): each is a float, a spectrum (dispersive if it varies with λ), or a
// material name (effigi/spectral/glass.hpp) written as <string name="int_ior" value="bk7"/>
// (Mitsuba's form) or <spectrum name="int_ior" value="bk7"/>.
#include "effigi/core/properties.hpp"
#include "effigi/core/schema.hpp"
#include "effigi/spectral/glass.hpp"
#include "effigi/spectral/named.hpp"

#include <algorithm>

namespace effigi {

/// Mitsuba 3's defaults, as constants: its "bk7" (1.5046) inside, its "air" outside. The
/// name "bk7" gives the dispersive Schott N-BK7 instead.
inline constexpr double DefaultIntIOR = 1.5046;
inline constexpr double DefaultExtIOR = 1.000277;

inline void declareIOR(Schema& s, const std::string& name, double def, const std::string& what) {
    s.spectrum(name, float(def), SpectrumKind::Unbounded,
               what + ": a float, a spectrum of λ (dispersive), or a name (bk7, sf11, fused-silica, diamond, water, ...)")
        .atLeast(1e-3)
        .orName();
}

/// Parameters and conformance configurations of a smooth dielectric BSDF: the two
/// indices, the reflected and transmitted factors, and ordinary and extreme indices
/// (index-matched, dense, dispersive).
inline void declareSmoothDielectric(Schema& s, const std::string& intDoc, const std::string& extDoc) {
    declareIOR(s, "int_ior", DefaultIntIOR, intDoc);
    declareIOR(s, "ext_ior", DefaultExtIOR, extDoc);
    s.texture("specular_reflectance", 1.f, SpectrumKind::Reflectance, "Factor on the reflected part").range(0.0, 1.0);
    s.texture("specular_transmittance", 1.f, SpectrumKind::Reflectance, "Factor on the transmitted part")
        .range(0.0, 1.0);
    s.addConformance({"default", {}});
    s.addConformance({"ior 1.0001", {{"int_ior", 1.0001}, {"ext_ior", 1.0}}});
    s.addConformance({"ior 4", {{"int_ior", 4.0}, {"ext_ior", 1.0}}});
    s.addConformance({"dispersive bk7", {{"int_ior", SpectrumValue{{}, {}, 0.f, 1.f, "bk7"}}}});
}

/// One index parameter as a spectrum; names resolve through namedIOR (then, for
/// <spectrum value="name">, the shipped named spectra). Every value must be finite and > 0.
inline Spectrum readIOR(const Properties& p, const std::string& name) {
    const Properties::Entry* e = p.find(name);
    SourceLocation where = p.whereOf(name);
    auto byName = [&](const std::string& material) {
        try {
            return iorByName(material, {}, name);
        } catch (const Error& err) {
            failAt(where, "{}: {}", p.describe(), err.what());
        }
    };
    Spectrum s;
    if (const auto* str = e ? std::get_if<std::string>(&e->value) : nullptr) {
        s = byName(*str);
    } else if (const auto* sv = e ? std::get_if<SpectrumValue>(&e->value) : nullptr; sv && !sv->name.empty()) {
        if (std::optional<Spectrum> ior = namedIOR(sv->name)) {
            s = ior->scaled(sv->scale);
        } else {
            // A shipped spectrum file works too; a name that is neither gets the IOR names as hints.
            std::vector<std::string> files = namedSpectrumNames();
            if (std::find(files.begin(), files.end(), sv->name) == files.end()) byName(sv->name);
            s = p.getSpectrum(name, SpectrumKind::Unbounded);
        }
    } else if (e && std::holds_alternative<RGBValue>(e->value)) {
        failAt(where, "{}: parameter '{}' is an index of refraction: give a float, a spectrum or a name, not rgb",
               p.describe(), name);
    } else {
        s = p.getSpectrum(name, SpectrumKind::Unbounded);
    }
    for (int l = int(LambdaMin); l <= int(LambdaMax); ++l) {
        float v = s(float(l));
        if (!(v > 0.f) || !std::isfinite(v))
            failAt(where, "{}: parameter '{}' must be a positive index of refraction, got {} at {} nm", p.describe(),
                   name, v, l);
    }
    return s;
}

/// η_int / η_ext at the path's wavelengths; a constant when neither varies with λ.
class RelativeIOR {
public:
    RelativeIOR(Spectrum in, Spectrum ext) : m_int(std::move(in)), m_ext(std::move(ext)) {
        m_constant = m_int.type() == Spectrum::Type::Constant && m_ext.type() == Spectrum::Type::Constant;
        if (m_constant) m_eta = m_int(550.f) / m_ext(550.f);
    }
    bool isConstant() const { return m_constant; }
    SampledSpectrum eval(const SampledWavelengths& lambda) const {
        if (m_constant) return SampledSpectrum(m_eta);
        SampledSpectrum e;
        for (int i = 0; i < NSpectrumSamples; ++i) e[i] = m_int(lambda[i]) / m_ext(lambda[i]);
        return e;
    }

private:
    Spectrum m_int, m_ext;
    bool m_constant = false;
    float m_eta = 1.f;
};

inline RelativeIOR relativeIOR(const Properties& p) { return {readIOR(p, "int_ior"), readIOR(p, "ext_ior")}; }

} // namespace effigi
