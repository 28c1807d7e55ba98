#pragma once
// Where the library finds its modules and data: relative to libeffigi.so itself, so
// the build tree and an installed tree work alike (lib/effigi/modules, share/effigi).
#include <filesystem>
#include <string>
#include <vector>

namespace effigi {

/// Directory holding libeffigi.so.
std::filesystem::path libraryDirectory();
/// Built-in module directory followed by those in EFFIGI_PLUGIN_PATH.
std::vector<std::filesystem::path> moduleDirectories();
/// share/effigi (or EFFIGI_DATA_DIR when set).
std::filesystem::path dataDirectory();
/// The effigi version string.
const char* version();

} // namespace effigi
