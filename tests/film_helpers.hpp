#pragma once
// Helpers shared by the film tests (test_filters, test_film, test_colorspace,
// test_spectral_exr, test_convert): a reconstruction filter and an hdrfilm with given
// parameters, created through the registry.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/ifilter.hpp"

#include <catch2/catch.hpp>

#include <string>
#include <utility>
#include <vector>

namespace effigi::test {

inline Ref<IFilter> makeFilter(const std::string& name) {
    Properties p("rfilter", name);
    Ref<IFilter> f = query<IFilter>(Registry::instance().create("rfilter", name, p));
    REQUIRE(f);
    return f;
}

/// hdrfilm with these parameters and the named reconstruction filter ("": the film's
/// default).
inline Ref<IFilm> makeFilm(const std::vector<std::pair<std::string, PropertyValue>>& params,
                           const std::string& filter = "") {
    Properties p("film", "hdrfilm");
    for (const auto& [k, v] : params) p.set(k, v);
    if (!filter.empty()) p.set("", ComponentValue{"rfilter", makeFilter(filter)});
    Ref<IFilm> film = query<IFilm>(Registry::instance().create("film", "hdrfilm", p));
    REQUIRE(film);
    return film;
}

} // namespace effigi::test
