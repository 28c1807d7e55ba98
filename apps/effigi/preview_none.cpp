// The live preview of a build without cpp-httplib (Debian libcpp-httplib-dev was absent
// when CMake configured): --preview is refused with one line (previewPortOption()).
#include "preview_server.hpp"

namespace effigi::app {

bool previewAvailable() { return false; }

std::unique_ptr<Preview> startPreview(int, PreviewJob) {
    fail("--preview: this effigi was built without the live preview (Debian: libcpp-httplib-dev)");
}

} // namespace effigi::app
