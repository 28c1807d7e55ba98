#pragma once
// Helpers shared by the XML tests (test_xml, test_xml_errors, test_loader): the test
// data directory and catching an effigi::Error's message.
#include "effigi/core/error.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <functional>
#include <string>

namespace effigi::test {

inline const std::filesystem::path kData = std::filesystem::path(EFFIGI_SOURCE_DIR) / "tests/data/xml";

/// The message of the effigi::Error that f throws; fails the test if it throws none.
inline std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    FAIL("no effigi::Error was thrown");
    return {};
}

} // namespace effigi::test
