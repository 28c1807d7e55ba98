#pragma once
// Helpers shared by the camera tests (test_camera, test_cameras_extra): an hdrfilm of a
// given size, a camera of any type built through the registry with that film, and the
// ray a camera generates for one film/lens sample.
#include "effigi/core/properties.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/icamera.hpp"
#include "effigi/interfaces/ifilm.hpp"

#include <catch2/catch.hpp>

#include <string>
#include <utility>
#include <vector>

namespace effigi::test {

/// Named parameters set in order on a component's Properties (a later one wins).
using Params = std::vector<std::pair<std::string, PropertyValue>>;

inline Ref<IFilm> makeFilm(int w, int h) {
    Properties p("film", "hdrfilm");
    p.set("width", std::int64_t(w));
    p.set("height", std::int64_t(h));
    Ref<IFilm> f = query<IFilm>(Registry::instance().create("film", "hdrfilm", p));
    REQUIRE(f);
    return f;
}

/// A camera of `type` with a w x h hdrfilm, then `params` on top.
inline Ref<ICamera> makeCamera(const std::string& type, int w, int h, const Params& params) {
    Properties p("camera", type);
    p.set("film", ComponentValue{"film", makeFilm(w, h)});
    for (auto& [k, v] : params) p.set(k, v);
    Ref<ICamera> c = query<ICamera>(Registry::instance().create("camera", type, p));
    REQUIRE(c);
    return c;
}

/// The ray through film position `film` (pixels) and lens sample `lens` at 550 nm; a
/// camera with no importance weighting must return a weight of exactly 1.
inline Ray rayAt(const ICamera& cam, Point2f film, Point2f lens = Point2f(0.5f)) {
    CameraSample s;
    s.pFilm = film;
    s.pLens = lens;
    SampledSpectrum w(0.f);
    Ray r = cam.generateRay(s, SampledWavelengths::constant(550.f), w);
    CHECK(w[0] == 1.f);
    return r;
}

}  // namespace effigi::test
