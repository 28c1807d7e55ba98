#pragma once
// What every fuzz target shares: the rule that decides between a clean rejection and a
// finding, a private scratch folder for inputs that a reader only takes as a file, and a
// way to build one component the way the scene loader does.
//
// The rule (issue 12, "Nothing breaks"): bad input must end in an effigi::Error whose
// message is one printable line. So a target catches effigi::Error, checks that line and
// returns; everything else is left to escape as a finding: a crash or sanitizer report,
// an allocation over libFuzzer's limit, a hang (libFuzzer's -timeout), any other
// exception (std::terminate aborts), or a message that is not one line (abort below).
#include "../tests/printable_line.hpp"
#include "effigi/core/error.hpp"
#include "effigi/core/log.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ishape.hpp"
#include "effigi/render/scene_range.hpp"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <unistd.h>
#include <utility>
#include <vector>

namespace effigi::fuzz {

/// A non-empty message that is one printable line (tests/printable_line.hpp).
inline bool isOnePrintableLine(std::string_view s) { return !s.empty() && test::printableLine(s); }

/// A clean rejection, or a finding: aborts (so libFuzzer saves the input) when the message
/// is not one printable line. The message is printed with every byte outside printable
/// ASCII written as \xNN, so the report itself stays readable.
inline void checkRejection(const Error& e) {
    const std::string_view msg = e.what();
    if (isOnePrintableLine(msg)) return;
    std::fputs("fuzz: effigi::Error whose message is not one printable line: ", stderr);
    for (unsigned char c : msg) {
        if (c >= 0x20 && c < 0x7f) std::fputc(c, stderr);
        else std::fprintf(stderr, "\\x%02X", c);
    }
    std::fputc('\n', stderr);
    std::abort();
}

/// Runs `f`; an effigi::Error is the expected answer to bad input (checked, then
/// swallowed), anything else propagates.
template <typename F> void expectCleanRejection(F&& f) {
    try {
        std::forward<F>(f)();
    } catch (const Error& e) {
        checkRejection(e);
    }
}

/// Once per process: no log output (the fuzzer runs millions of inputs).
inline void quiet() { log::setLevel(log::Level::Error); }

/// Loads the modules of these components (tag, type) now, at start-up, rather than while
/// the first input runs: libFuzzer then knows their coverage counters from the start, and
/// no input is slow for loading them. An empty list loads every known component.
inline void preload(std::vector<std::pair<std::string, std::string>> components = {}) {
    Registry& r = Registry::instance();
    if (components.empty()) components = r.list();
    for (const auto& [tag, type] : components) r.info(tag, type);
}

/// A folder of this process's own, created on first use and removed at exit: inputs are
/// written here, so relative file names in them resolve to nothing but its contents. In
/// memory (/dev/shm) where there is one: rewriting a file on a disk mounted with `discard`
/// waits for the device on every input (ten times fewer executions per second).
inline const std::filesystem::path& scratchDir(const std::string& target) {
    static const std::filesystem::path dir = [&] {
        namespace fs = std::filesystem;
        std::error_code ec;
        const fs::path base = fs::is_directory("/dev/shm", ec) && ::access("/dev/shm", W_OK) == 0
                                  ? fs::path("/dev/shm")
                                  : fs::temp_directory_path();
        fs::path d = base / ("effigi-fuzz-" + target + "-" + std::to_string(::getpid()));
        fs::create_directories(d);
        static const fs::path removeAtExit = d;
        std::atexit([] {
            std::error_code ignored;
            fs::remove_all(removeAtExit, ignored);
        });
        return d;
    }();
    return dir;
}

/// Writes the fuzz input to `file` (replacing it) and returns the path.
inline std::filesystem::path writeInput(const std::filesystem::path& file, const std::uint8_t* data, std::size_t size) {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    out.close();
    if (!out) {  // the harness's own failure, not the input's: stop rather than report noise
        std::fprintf(stderr, "fuzz: cannot write %s\n", file.c_str());
        std::exit(2);
    }
    return file;
}

/// Creates the component (tag, type) from a file name and further string parameters, as
/// the loader would for <tag type="type"><string name="filename" .../></tag>, and applies
/// the loader's own check of a shape's coordinates.
inline Ref<IComponent> createWithFile(const std::string& tag, const std::string& type, const std::filesystem::path& file,
                                      std::vector<std::pair<std::string, PropertyValue>> more = {}) {
    Properties props(tag, type, SourceLocation{"fuzz.xml", 1});
    props.set("filename", file.string(), SourceLocation{"fuzz.xml", 2});
    for (auto& [name, value] : more) props.set(name, std::move(value), SourceLocation{"fuzz.xml", 3});
    Ref<IComponent> obj = Registry::instance().create(tag, type, props);
    if (tag == "shape")
        if (Ref<IShape> shape = query<IShape>(obj))
            if (std::string why = shapeRangeProblem(*shape); !why.empty()) fail("{}", why);
    return obj;
}

} // namespace effigi::fuzz
