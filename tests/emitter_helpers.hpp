#pragma once
// Helpers shared by the emitter tests (test_emitters, test_emitters_extra,
// test_emitters_spot, test_emitters_envmap): creating an emitter through the registry,
// a flat spectrum, a fixed wavelength, and a temporary RGB image written as PFM.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iemitter.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <utility>
#include <vector>

namespace effigi::test {

/// A flat spectrum: a bare number given for an emission means a grey (scaled D65), as in
/// Mitsuba; these tests want the same value at every wavelength.
inline SpectrumValue flat(double v) {
    SpectrumValue s;
    s.values = {float(v)};
    return s;
}

using Params = std::vector<std::pair<std::string, PropertyValue>>;

inline Ref<IEmitter> makeEmitter(const std::string& name, const Params& params = {}) {
    Properties p("emitter", name);
    for (auto& [k, v] : params) p.set(k, v);
    Ref<IEmitter> e = query<IEmitter>(Registry::instance().create("emitter", name, p));
    REQUIRE(e);
    return e;
}

inline const SampledWavelengths Green = SampledWavelengths::constant(550.f);

/// A w × h RGB image as a PFM file (rows are stored bottom-up in PFM); removed with the
/// object. rgb(x, y) gives the texel, y = 0 the top row.
struct TempImage {
    std::filesystem::path path;
    template <typename F> TempImage(const std::string& name, int w, int h, F rgb) {
        path = std::filesystem::temp_directory_path() / ("effigi-" + std::to_string(getpid()) + "-" + name + ".pfm");
        std::ofstream f(path, std::ios::binary);
        f << "PF\n" << w << " " << h << "\n-1.0\n";
        for (int y = h - 1; y >= 0; --y)
            for (int x = 0; x < w; ++x) {
                Vector3f c = rgb(x, y);
                f.write(reinterpret_cast<const char*>(&c[0]), 3 * sizeof(float));
            }
    }
    ~TempImage() {
        std::error_code ec;
        std::filesystem::remove(path, ec);
    }
};

} // namespace effigi::test
