// effigi render --frames A:B — an animated sequence: one image per frame f = A … B, each a
// whole render of the scene with its $frame default set to f (`-D frame=f`), so a scene
// animates whatever it likes by frame: shutter_open="$frame", a keyframe time, a
// position. The output name is a pattern: `-o out/shot_{frame:03}.exr` (fmt's syntax),
// or, without {frame}, the frame number is added before the extension (out_0007.exr).
//
// Under mpirun the frames are dealt out over the ranks (rank r renders frames A + r,
// A + r + N, ...), each rendered as by a single process: frames are independent, so no
// film needs reducing and no rank waits for another. Checkpoints and the live preview
// belong to one render and are refused with --frames.
#include "commands.hpp"
#include "render_ranks.hpp"

#include "effigi/core/error.hpp"
#include "effigi/core/log.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>

namespace effigi::app {

namespace {

struct FrameRange {
    long first = 0, last = -1;
};

FrameRange parseFrames(const std::string& text) {
    FrameRange r;
    const auto colon = text.find(':');
    char* end = nullptr;
    const std::string a = text.substr(0, colon), b = colon == std::string::npos ? a : text.substr(colon + 1);
    r.first = std::strtol(a.c_str(), &end, 10);
    const bool aOk = !a.empty() && *end == '\0';
    r.last = std::strtol(b.c_str(), &end, 10);
    const bool bOk = !b.empty() && *end == '\0';
    if (!aOk || !bOk || r.first < 0 || r.last < r.first || r.last - r.first >= 1000000)
        fail("--frames expects A:B with 0 <= A <= B (at most a million frames), got '{}'", text);
    return r;
}

/// The output file of frame f: the {frame} pattern, or the number before the extension.
std::string framePath(const std::string& pattern, long f) {
    if (pattern.find("{frame") != std::string::npos) {
        try {
            return fmt::format(fmt::runtime(pattern), fmt::arg("frame", f));
        } catch (const fmt::format_error& e) {
            fail("-o '{}': not a valid {{frame}} pattern ({})", pattern, e.what());
        }
    }
    std::filesystem::path p(pattern);
    const std::string ext = p.has_extension() ? p.extension().string() : ".exr";
    p.replace_extension();
    return fmt::format("{}_{:04}{}", p.string(), f, ext);
}

/// This process's rank and the job's size under mpirun (0 and 1 on its own).
std::pair<int, int> rankAndSize() {
    const int size = std::max(1, launchedRanks());
    for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMI_RANK"})
        if (const char* v = std::getenv(name)) return {std::max(0, std::atoi(v)), size};
    return {0, size};
}

} // namespace

bool hasFramesOption(const std::vector<std::string>& args) {
    for (const std::string& a : args)
        if (a == "--frames") return true;
    return false;
}

int renderFrames(const std::vector<std::string>& args) {
    std::vector<std::string> rest;
    std::string range, out, scene;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto value = [&]() -> const std::string& {
            if (i + 1 >= args.size()) fail("{} needs a value", a);
            return args[++i];
        };
        if (a == "--frames") range = value();
        else if (a == "-o") out = value();
        else if (a == "--checkpoint" || a == "--resume" || a == "--preview")
            fail("{} belongs to one render: it cannot be combined with --frames", a);
        else if (a == "-D") {
            const std::string& kv = value();
            if (kv.rfind("frame=", 0) == 0) fail("-D {}: --frames sets $frame itself", kv);
            rest.push_back(a), rest.push_back(kv);
        } else {
            if (!a.empty() && a[0] != '-' && scene.empty()) scene = a;
            rest.push_back(a);
        }
    }
    const FrameRange frames = parseFrames(range);
    if (out.empty()) out = std::filesystem::path(scene).stem().string() + ".exr";
    (void)framePath(out, frames.first);  // a bad pattern fails before any render
    const auto [rank, size] = rankAndSize();
    for (long f = frames.first + rank; f <= frames.last; f += size) {
        std::vector<std::string> one = rest;
        one.insert(one.end(), {"-D", fmt::format("frame={}", f), "-o", framePath(out, f)});
        if (size == 1) log::info("frame {} of {}:{}", f, frames.first, frames.last);
        if (const int rc = renderOne(one, false); rc != 0) return rc;
    }
    return 0;
}

} // namespace effigi::app
