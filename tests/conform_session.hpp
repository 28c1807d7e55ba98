#pragma once
// Reading a conformance session in the tests that run a suite on deliberately wrong
// components (test_conformance, test_accelerators, test_conformance_camera,
// test_conformance_emitter).
#include "conformance/conformance.hpp"

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include <filesystem>
#include <set>
#include <string>

namespace effigi::test {

/// Every row of the session, one line each (verdict, component, configuration, check,
/// figure, detail cut at 300 characters): what a failing test prints.
inline std::string sessionTable(const conform::Session& s) {
    std::string text;
    for (const conform::Row& r : s.rows())
        text += fmt::format("{} {} {} {}: {} | {}\n", conform::verdictName(r.verdict), r.component, r.config, r.check,
                            r.figure, r.detail.substr(0, 300));
    return text;
}

/// The verdict of the first row of `check` on `component` (there must be one).
inline conform::Verdict verdictOf(const conform::Session& s, const std::string& component, const std::string& check) {
    auto rows = s.find(component, check);
    REQUIRE(!rows.empty());
    return rows[0]->verdict;
}

/// The suite of `tag` run in quick mode on one component (a deliberately wrong one
/// registered by the test), its images written under outDir.
inline conform::Session runQuickSuite(const std::string& tag, const std::string& component,
                                      const std::filesystem::path& outDir) {
    conform::Options o;
    o.tag = tag;
    o.component = component;
    o.quick = true;
    o.outDir = outDir;
    conform::Session s(o);
    s.run();
    return s;
}

/// The checks that failed on any configuration.
inline std::set<std::string> failedChecks(const conform::Session& s) {
    std::set<std::string> out;
    for (const conform::Row& r : s.rows())
        if (r.verdict == conform::Verdict::Fail) out.insert(r.check);
    return out;
}

} // namespace effigi::test
