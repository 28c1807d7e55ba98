// The app's side of the live preview (effigi render --preview): the server lives in the
// module lib/effigi/preview.so (preview_server.cpp), loaded here on first use only, so
// that cpp-httplib and the OpenSSL and Brotli libraries it links are loaded by no other
// render (as the OpenImageIO reader is loaded only for non-EXR references, image_io.cpp).
#include "preview_server.hpp"

#include "effigi/core/module.hpp"

#include <csignal>
#include <cstdio>
#include <dlfcn.h>

namespace effigi::app {

bool previewAvailable() { return true; }

std::unique_ptr<Preview> startPreview(int port, PreviewJob job) {
    const std::filesystem::path module = libraryDirectory() / "effigi" / preview_module::ModuleFile;
    void* handle = dlopen(module.c_str(), RTLD_NOW | RTLD_LOCAL);  // kept loaded: the Preview's code is in it
    if (!handle) fail("--preview: the live preview module did not load ({})", dlerror());
    const auto start = reinterpret_cast<preview_module::Start>(dlsym(handle, preview_module::StartSymbol));
    if (!start) fail("--preview: {} has no entry point {}", module.string(), preview_module::StartSymbol);
    // A browser that goes away mid-response must not end the render (SIGPIPE's default).
    std::signal(SIGPIPE, SIG_IGN);
    std::string error;
    std::unique_ptr<Preview> preview(start(port, job, error));
    if (!preview) fail("{}", error);
    std::fprintf(stderr, "preview: http://127.0.0.1:%d/\n", preview->port());
    std::fflush(stderr);
    return preview;
}

} // namespace effigi::app
