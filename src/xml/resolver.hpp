#pragma once
// Internal to the XML parser: Mitsuba's file resolver. A relative file name is looked up
// in a list of folders, first match wins; the list starts with the main scene's folder
// and each <path value="dir"/> puts a folder in front of it.
#include <filesystem>
#include <string>
#include <vector>

namespace effigi::xml::detail {

class FileResolver {
public:
    using Path = std::filesystem::path;

    /// Forget every folder but `mainDir` (the folder of the main scene file).
    void reset(const Path& mainDir) { m_dirs = {mainDir}; }
    void prepend(const Path& dir) { m_dirs.insert(m_dirs.begin(), dir.lexically_normal()); }
    const std::vector<Path>& dirs() const { return m_dirs; }
    void setDirs(std::vector<Path> dirs) { m_dirs = std::move(dirs); }

    /// `rel` looked up in `first`, then in each search folder: the first existing regular
    /// file (or folder, with `folder`). Every candidate goes into `tried`; without a
    /// match the first candidate is returned. An absolute `rel` is returned as it is.
    Path find(const Path& rel, const Path& first, bool folder, std::vector<Path>& tried) const;

    /// A file name property (<string name="filename">, <spectrum filename>): the file
    /// in the first search folder that has it, as an absolute path. Kept as written when
    /// no search folder has it, or when it is the same file as the one next to the file
    /// naming it (`fileDir`), to which Properties::getPath resolves relative names.
    std::string resolveName(const std::string& name, const Path& fileDir) const;

private:
    std::vector<Path> m_dirs;
};

/// "a, b, c": the candidates a lookup tried, for error messages.
std::string joinPaths(const std::vector<std::filesystem::path>& paths);

} // namespace effigi::xml::detail
