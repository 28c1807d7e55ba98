#pragma once
// Internal to the XML parser: reading scene files written for Mitsuba 0.5/0.6 and 2.x
// (version < 3). Those used camelCase element and parameter names; most map
// mechanically (camelToSnake), the rest through a table of exceptions in upgrade.cpp.
#include "effigi/xml/parser.hpp"

#include <string>
#include <string_view>

namespace effigi::xml::detail {

/// Element name in a version < 3 file -> Mitsuba 3's ("lookAt" -> "lookat").
std::string upgradeTag(std::string_view tag);
/// Attribute of element `tag` in a version < 3 file -> Mitsuba 3's (blackbody's
/// "multiplier" -> "scale").
std::string upgradeAttribute(const std::string& tag, std::string_view attr);
/// Parameter or child name in a version < 3 file -> Mitsuba 3's: the table first
/// ("highQualityEdges" -> "sample_border"), then camelCase -> snake_case.
std::string upgradeName(const std::string& name);
/// The plugin-specific renames Mitsuba 3 applies to version < 2 files, on a finished
/// object: diffuse's diffuse_reflectance -> reflectance, and a texture's
/// uoffset/voffset/uscale/vscale folded into one to_uv transform.
void upgradeFromV1(Node& node);

} // namespace effigi::xml::detail
