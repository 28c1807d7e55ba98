// Mitsuba's file resolver for the XML parser (see resolver.hpp).
#include "resolver.hpp"

namespace effigi::xml::detail {

namespace fs = std::filesystem;

fs::path FileResolver::find(const Path& rel, const Path& first, bool folder, std::vector<Path>& tried) const {
    if (rel.is_absolute()) {
        tried.push_back(rel);
        return rel;
    }
    tried.push_back(first / rel);
    for (const auto& dir : m_dirs) tried.push_back(dir / rel);
    std::error_code ec;
    for (const auto& t : tried)
        if (folder ? fs::is_directory(t, ec) : fs::is_regular_file(t, ec)) return t;
    return tried.front();
}

std::string FileResolver::resolveName(const std::string& name, const Path& fileDir) const {
    Path rel(name);
    if (name.empty() || rel.is_absolute()) return name;
    std::error_code ec;
    for (const auto& dir : m_dirs) {
        Path p = dir / rel;
        if (!fs::exists(p, ec)) continue;
        Path own = fileDir / rel;
        if (fs::exists(own, ec) && fs::equivalent(p, own, ec)) return name;
        Path abs = fs::absolute(p, ec);
        return (ec ? p : abs).lexically_normal().string();
    }
    return name;
}

std::string joinPaths(const std::vector<fs::path>& paths) {
    std::string s;
    for (const auto& p : paths) s += (s.empty() ? "" : ", ") + p.string();
    return s;
}

} // namespace effigi::xml::detail
