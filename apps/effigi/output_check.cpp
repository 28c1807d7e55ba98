// Writability probes for output files (output_check.hpp).
#include "output_check.hpp"

#include "effigi/core/error.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace effigi::app {

namespace fs = std::filesystem;

void requireWritable(const fs::path& path, bool create) {
    auto refuse = [&](const std::string& reason) { fail("cannot write {}: {}", path.string(), reason); };
    std::error_code ec;
    const fs::path dir = path.parent_path();
    if (!dir.empty()) {
        // The nearest existing folder on the way must be a folder (a regular file used as
        // one is the common mistake); below it the folders are created now.
        fs::path existing = dir;
        while (!existing.empty() && !fs::exists(existing, ec)) existing = existing.parent_path();
        if (!existing.empty() && !fs::is_directory(existing, ec))
            refuse(fmt::format("'{}' is not a folder", existing.string()));
        if (!create && existing != dir) {
            const fs::path at = existing.empty() ? fs::path(".") : existing;
            if (::access(at.c_str(), W_OK | X_OK) != 0)
                refuse(fmt::format("cannot create folders in '{}' ({})", at.string(), std::strerror(errno)));
            return;
        }
        fs::create_directories(dir, ec);
        if (ec) refuse(fmt::format("cannot create folder '{}' ({})", dir.string(), ec.message()));
    }
    if (fs::is_directory(path, ec)) refuse("it is a folder");
    if (fs::exists(path, ec)) {
        const int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
        if (fd < 0) refuse(std::strerror(errno));
        ::close(fd);
        return;
    }
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0) {
        const int err = errno;
        // Pseudo file systems (/proc) say "no such file" for a file they will not create.
        if (err == ENOENT)
            refuse(fmt::format("folder '{}' does not take new files ({})", dir.empty() ? "." : dir.string(),
                               std::strerror(err)));
        refuse(std::strerror(err));
    }
    ::close(fd);
    ::unlink(path.c_str());
}

} // namespace effigi::app
