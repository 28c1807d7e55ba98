// Named indices of refraction (effigi/spectral/glass.hpp): Sellmeier glasses and
// Mitsuba 3's table of constant indices.
#include "effigi/spectral/glass.hpp"

#include "effigi/core/error.hpp"
#include "effigi/core/input.hpp"

#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>

namespace effigi {
namespace {

// Published Sellmeier coefficients (the numbers are facts of the publications named in
// glass.hpp). B dimensionless, C in µm².
constexpr SellmeierGlass Glasses[] = {
    {"bk7",
     {1.03961212, 0.231792344, 1.01046945},
     {0.00600069867, 0.0200179144, 103.560653},
     "Schott N-BK7 data sheet"},
    {"sf11",
     {1.73759695, 0.313747346, 1.89878101},
     {0.013188707, 0.0623068142, 155.23629},
     "Schott N-SF11 data sheet"},
    // Malitson gives the resonance wavelengths (0.0684043, 0.1162414, 9.896161 µm); C = their squares.
    {"fused-silica",
     {0.6961663, 0.4079426, 0.8974794},
     {0.0684043 * 0.0684043, 0.1162414 * 0.1162414, 9.896161 * 9.896161},
     "Malitson 1965, J. Opt. Soc. Am. 55, 1205"},
    // Peter 1923: two terms with resonances at 0.175 and 0.106 µm.
    {"diamond", {0.3306, 4.3356, 0.0}, {0.175 * 0.175, 0.106 * 0.106, 0.0}, "Peter 1923, Z. Phys. 15, 358"},
};

// Mitsuba 3's named constant indices, the values it gives (after E. Hecht, Optics, 4th ed.,
// measured at 0-20 °C near 589 nm); its "bk7" (1.5046) and "diamond" (2.419) are left out
// because effigi's are the dispersive glasses above.
struct ConstantIOR {
    const char* name;
    float value;
};
constexpr ConstantIOR Constants[] = {
    {"vacuum", 1.0f},          {"helium", 1.000036f},         {"hydrogen", 1.000132f},
    {"air", 1.000277f},         {"carbon dioxide", 1.00045f},  {"water", 1.3330f},
    {"acetone", 1.36f},        {"ethanol", 1.361f},           {"carbon tetrachloride", 1.461f},
    {"glycerol", 1.4729f},     {"benzene", 1.501f},           {"silicone oil", 1.52045f},
    {"bromine", 1.661f},       {"water ice", 1.31f},          {"fused quartz", 1.458f},
    {"pyrex", 1.470f},         {"acrylic glass", 1.49f},      {"polypropylene", 1.49f},
    {"sodium chloride", 1.544f}, {"amber", 1.55f},            {"pet", 1.5750f},
};

Spectrum tabulate(const SellmeierGlass& g) {
    std::vector<float> lambdas, values;
    for (int l = int(LambdaMin); l <= int(LambdaMax); ++l) {
        lambdas.push_back(float(l));
        values.push_back(float(g.index(l)));
    }
    return Spectrum::piecewiseLinear(std::move(lambdas), std::move(values));
}

} // namespace

double SellmeierGlass::index(double lambdaNm) const {
    double l2 = (lambdaNm * 1e-3) * (lambdaNm * 1e-3);
    double n2 = 1.0;
    for (int i = 0; i < 3; ++i)
        if (B[i] != 0.0) n2 += B[i] * l2 / (l2 - C[i]);
    return std::sqrt(n2);
}

const SellmeierGlass* findSellmeierGlass(const std::string& name) {
    for (const auto& g : Glasses)
        if (name == g.name) return &g;
    return nullptr;
}

std::optional<Spectrum> namedIOR(const std::string& name) {
    if (const SellmeierGlass* g = findSellmeierGlass(name)) {
        // Tabulated once per glass and shared (the table is immutable).
        static std::mutex mutex;
        static std::map<std::string, Spectrum> cache;
        std::lock_guard lock(mutex);
        auto it = cache.find(name);
        if (it == cache.end()) it = cache.emplace(name, tabulate(*g)).first;
        return it->second;
    }
    for (const auto& c : Constants)
        if (name == c.name) return Spectrum(c.value);
    return std::nullopt;
}

bool isDispersiveIOR(const std::string& name) { return findSellmeierGlass(name) != nullptr; }

std::vector<std::string> namedIORNames() {
    std::vector<std::string> names;
    for (const auto& g : Glasses) names.emplace_back(g.name);
    for (const auto& c : Constants) names.emplace_back(c.name);
    std::sort(names.begin(), names.end());
    return names;
}

Spectrum iorByName(const std::string& name, const SourceLocation& where, const std::string& param) {
    if (std::optional<Spectrum> s = namedIOR(name)) return *s;
    std::vector<std::string> names = namedIORNames();
    std::string hint = didYouMean(name, names);
    failAt(where, "parameter '{}': unknown material '{}'{} (known: {})", param, excerpt(name),
           hint.empty() ? "" : fmt::format(", did you mean '{}'?", hint), fmt::join(names, ", "));
}

} // namespace effigi
