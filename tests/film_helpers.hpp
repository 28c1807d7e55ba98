#pragma once
// Helpers shared by the film tests (test_filters, test_film): creating a reconstruction
// filter through the registry.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ifilter.hpp"

#include <catch2/catch.hpp>

#include <string>

namespace effigi::test {

inline Ref<IFilter> makeFilter(const std::string& name) {
    Properties p("rfilter", name);
    Ref<IFilter> f = query<IFilter>(Registry::instance().create("rfilter", name, p));
    REQUIRE(f);
    return f;
}

} // namespace effigi::test
