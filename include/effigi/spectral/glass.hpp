#pragma once
// Indices of refraction by name, for the `int_ior` / `ext_ior` parameters of dielectrics.
//
// Dispersive glasses follow the Sellmeier equation, n²(λ) = 1 + Σ_i B_i λ² / (λ² − C_i)
// with λ in µm, with the coefficients published for them:
//   "bk7"          Schott N-BK7, Schott optical glass data sheet (catalogue 2017)
//   "sf11"         Schott N-SF11, a dense flint (Abbe number 25.7, four times the
//                  dispersion of BK7), Schott optical glass data sheet (catalogue 2017)
//   "fused-silica" I. H. Malitson, "Interspecimen comparison of the refractive index of
//                  fused silica", J. Opt. Soc. Am. 55(10), 1205–1209 (1965)
//   "diamond"      F. Peter, "Über Brechungsindizes und Absorptionskonstanten des Diamanten
//                  zwischen 644 und 226 mμ", Z. Phys. 15, 358–368 (1923) (two-term form)
// The other names are Mitsuba 3's constant indices ("vacuum", "air", "water", "acrylic
// glass", ...), so scenes written for Mitsuba load unchanged; where a name is in both lists
// ("bk7", "diamond") effigi's is the dispersive one.
#include "effigi/core/error.hpp"
#include "effigi/spectral/spectrum.hpp"

#include <optional>
#include <string>
#include <vector>

namespace effigi {

/// A glass described by a three-term Sellmeier equation (λ in µm, C_i in µm²).
struct SellmeierGlass {
    const char* name;
    double B[3];
    double C[3];
    const char* source;

    /// Refractive index at λ [nm].
    double index(double lambdaNm) const;
};

/// The dispersive glass of that name, or null.
const SellmeierGlass* findSellmeierGlass(const std::string& name);

/// The index of refraction of a named material as a spectrum of λ: a 1 nm table over
/// [LambdaMin, LambdaMax] from the Sellmeier equation for a dispersive glass (linear
/// interpolation error < 1e-6), a constant for Mitsuba's names; nullopt if unknown.
std::optional<Spectrum> namedIOR(const std::string& name);
/// True if the name is known and its index varies with wavelength.
bool isDispersiveIOR(const std::string& name);
/// Every name namedIOR knows, sorted.
std::vector<std::string> namedIORNames();
/// namedIOR, or an effigi::Error at `where` naming the parameter and the closest names.
Spectrum iorByName(const std::string& name, const SourceLocation& where, const std::string& param);

} // namespace effigi
