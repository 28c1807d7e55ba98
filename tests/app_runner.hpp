#pragma once
// Runs the effigi executable from tests: exit code and everything it printed.
#include <cstdio>
#include <filesystem>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace effigi::test {

struct AppResult {
    int exitCode = -1;
    std::string out;  // stdout and stderr together
};

inline AppResult runApp(const std::string& args) {
    std::string cmd = std::string(EFFIGI_APP) + " " + args + " 2>&1";
    AppResult r;
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return r;
    char buf[4096];
    std::size_t n;
    while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
    int status = pclose(p);
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

/// A fresh directory under the system temp dir, unique to this process (ctest runs test
/// cases in parallel processes); the caller removes it.
inline std::filesystem::path tempDir(const std::string& name) {
    auto dir = std::filesystem::temp_directory_path() / ("effigi-test-" + name + "-" + std::to_string(getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

} // namespace effigi::test
