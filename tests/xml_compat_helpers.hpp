#pragma once
// Helpers shared by the Mitsuba-compatibility tests of the XML reader (test_xml_compat,
// test_xml_compat_legacy): their data folder, a top-level object by id, and a typed
// property value.
#include "effigi/xml/parser.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <string>
#include <variant>

namespace effigi::test {

inline const std::filesystem::path kCompat = std::filesystem::path(EFFIGI_SOURCE_DIR) / "tests/data/xml_compat";

inline const xml::Node& byId(const xml::Node& root, const std::string& id) {
    for (const xml::Child& c : root.children)
        if (c.node && c.node->id == id) return *c.node;
    FAIL("no top-level object with id " << id);
    return root;
}

template <typename T> inline const T& value(const xml::Node& n, const std::string& name) {
    const Properties::Entry* e = n.props.find(name);
    INFO("property " << name);
    REQUIRE(e != nullptr);
    REQUIRE(std::holds_alternative<T>(e->value));
    return std::get<T>(e->value);
}

} // namespace effigi::test
