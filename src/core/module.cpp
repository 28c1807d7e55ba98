#include "effigi/core/module.hpp"

#include <cstdlib>
#include <dlfcn.h>
#include <sstream>

#ifndef EFFIGI_VERSION
#define EFFIGI_VERSION "0.0.0"
#endif

namespace effigi {

std::filesystem::path libraryDirectory() {
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&libraryDirectory), &info) && info.dli_fname)
        return std::filesystem::canonical(info.dli_fname).parent_path();
    return std::filesystem::current_path();
}

std::vector<std::filesystem::path> moduleDirectories() {
    std::vector<std::filesystem::path> dirs{libraryDirectory() / "effigi" / "modules"};
    if (const char* extra = std::getenv("EFFIGI_PLUGIN_PATH")) {
        std::stringstream ss(extra);
        std::string dir;
        while (std::getline(ss, dir, ':'))
            if (!dir.empty()) dirs.emplace_back(dir);
    }
    return dirs;
}

std::filesystem::path dataDirectory() {
    if (const char* dir = std::getenv("EFFIGI_DATA_DIR"); dir && *dir) return dir;
    // <prefix>/lib beside <prefix>/share: the build tree and an install with libdir lib.
    std::filesystem::path dir = libraryDirectory().parent_path() / "share" / "effigi";
#ifdef EFFIGI_DATA_FROM_LIBDIR
    // An install whose libdir is deeper (lib/<multiarch>): the path CMake computed for it.
    if (!std::filesystem::is_directory(dir)) return (libraryDirectory() / EFFIGI_DATA_FROM_LIBDIR).lexically_normal();
#endif
    return dir;
}

const char* version() { return EFFIGI_VERSION; }

} // namespace effigi
