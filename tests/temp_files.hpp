#pragma once
// Scratch files for the tests that write input files (test_ply, test_serialized,
// test_mesh_flags): one directory per test process, removed when the process exits, and
// a little-endian byte appender for the binary formats those tests write by hand.
#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <unistd.h>

namespace effigi::test {

/// A directory effigi_test_<tag>_<pid> under the system temp directory, created on
/// construction and removed (with everything written into it) on destruction. The pid
/// keeps parallel ctest runs of different executables from sharing a directory.
class ScratchDir {
public:
    explicit ScratchDir(const std::string& tag)
        : m_dir(std::filesystem::temp_directory_path() / fmt::format("effigi_test_{}_{}", tag, ::getpid())) {
        std::filesystem::create_directories(m_dir);
    }
    ~ScratchDir() {
        std::error_code ec;  // a failed cleanup must not throw from a destructor
        std::filesystem::remove_all(m_dir, ec);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;

    const std::filesystem::path& dir() const { return m_dir; }

    /// Writes `bytes` verbatim to dir()/name and returns that path.
    std::filesystem::path write(const std::string& name, const std::string& bytes) const {
        std::filesystem::path p = m_dir / name;
        std::ofstream(p, std::ios::binary) << bytes;
        return p;
    }

private:
    std::filesystem::path m_dir;
};

/// Appends the in-memory bytes of v (little-endian on every platform effigi builds for).
template <typename T> void put(std::string& s, T v) { s.append(reinterpret_cast<const char*>(&v), sizeof(T)); }

}  // namespace effigi::test
