#pragma once
// effigi render --preview [PORT]: a page on http://127.0.0.1:PORT/ that shows the image as
// it converges (refreshed about every second), the progress, samples/s and the renderer's
// own relMSE estimate against time, with an exposure slider and a tone map choice. The
// server listens on the loopback interface only and answers from a copy of the image
// taken between passes, in the render thread: it never reads the film while the renderer
// writes it.
//
// The server (cpp-httplib, preview_server.cpp) is a module of its own, lib/effigi/
// preview.so, that the app dlopens for --preview only (preview_load.cpp): cpp-httplib
// brings OpenSSL and Brotli, six shared libraries that no other render should load (see
// tests/test_startup.cpp). A build without cpp-httplib has preview_none.cpp instead.
//
// A render nobody watches is the render without --preview: the same passes (--preview
// renders progressively, as --spp does), the same samples, the same image. While a page
// polls, passes are cut to about a second so that it has something new to show.
#include "effigi/core/error.hpp"
#include "effigi/render/progressive.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace effigi::app {

inline constexpr int DefaultPreviewPort = 8080;

/// What the page says of the job besides its progress.
struct PreviewJob {
    std::string scene, renderer;
    std::uint64_t spp = 0;      ///< the budgets progress is measured against (0: none)
    double timeBudget = 0.0, targetRelMSE = 0.0;
};

class Preview {
public:
    virtual ~Preview() = default;
    /// The port it listens on: the one asked for, or the one the system chose for 0.
    virtual int port() const = 0;
    /// In the render thread after each pass (the film is not being written): a copy of
    /// the image so far and the report's numbers for the page. `maxPassSeconds` (null
    /// where the passes must not change, as under MPI, whose ranks agree on every pass)
    /// is lowered to about a second while a page polls and set back when none does.
    virtual void afterPass(const Scene& scene, const PassReport& report, double* maxPassSeconds) = 0;
    /// The render ended: a last copy of the film (the job's, after the ranks' reduction)
    /// and "finished" for the page. Unless it was interrupted, a page that is watching
    /// gets up to 3 s to fetch the final image before the process goes on (and exits).
    virtual void finish(const Scene& scene, const PassReport& last) = 0;
};

/// The contract between the app and the module: one C entry point, looked up with dlsym,
/// that never throws (both are built together, so the C++ types are safe to pass).
namespace preview_module {
inline constexpr const char* ModuleFile = "preview.so";  ///< in <libdir>/effigi
inline constexpr const char* StartSymbol = "effigiStartPreview";
/// A server listening on 127.0.0.1:port (0: a free one), or null with a one-line message
/// in `error`. Its afterPass() and finish() throw nothing either: a failure of the page
/// is a warning, once, and the render goes on.
using Start = Preview* (*)(int port, const PreviewJob& job, std::string& error) noexcept;
} // namespace preview_module

/// Whether this build has the preview (cpp-httplib was found when it was configured).
bool previewAvailable();

/// Listen on 127.0.0.1:`port` (0: a free port the system picks) and say where on stderr;
/// an effigi::Error when it cannot (port taken, or a build without the preview).
std::unique_ptr<Preview> startPreview(int port, PreviewJob job);

/// `--preview [PORT]` at args[i]: the port when the next argument is a number (it is then
/// consumed), DefaultPreviewPort otherwise. Fails in a build without the preview.
inline int previewPortOption(const std::vector<std::string>& args, std::size_t& i) {
    if (!previewAvailable())
        fail("--preview: this effigi was built without the live preview (cpp-httplib was not found when it was "
             "configured; Debian: libcpp-httplib-dev)");
    if (i + 1 >= args.size() || args[i + 1].empty() || args[i + 1].find_first_not_of("0123456789") != std::string::npos)
        return DefaultPreviewPort;
    const std::string& v = args[++i];
    if (v.size() > 5 || std::stol(v) > 65535) fail("option --preview expects a port in 0..65535, got '{}'", v);
    return int(std::stol(v));
}

} // namespace effigi::app
