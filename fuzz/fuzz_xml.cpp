// Fuzz target: scene files — the XML parser (src/xml: grammar, $variables, <include>,
// <path>, typed values, transforms, version < 3 names) and the loader that instantiates
// every component the scene names (schemas, constructors, the scene's own checks,
// building the accelerator), without rendering.
//
// Why: a scene is the one input that reaches everything; each component's constructor
// checks its own parameters, and the combinations (nesting, references, ids, defaults,
// unusual but valid values) are what the fuzzer is good at finding.
// Bounded work: inputs over 64 KB are skipped, and so are inputs that could name a file
// outside this process's scratch folder ('/' other than in "</" and "/>", "..", and
// character references "&#" that could spell either): a scene may name any file, and
// some files on this machine are large regular files (a 1 GB file is a legitimately slow
// scene, not a finding). The scratch folder holds a copy of the other targets' seeds
// (meshes, images, spectra, grids, scenes), so that scenes can name real files by their
// bare names; devices and FIFOs are refused by every reader anyway (core/input.hpp).
#include "fuzz_common.hpp"

#include "effigi/xml/loader.hpp"
#include "effigi/xml/parser.hpp"

#include <OpenImageIO/imageio.h>

using namespace effigi;

namespace {

/// Whether the scene text can only name files inside the scratch folder.
bool staysInScratch(std::string_view s) {
    if (s.find("..") != s.npos || s.find("&#") != s.npos) return false;
    for (std::size_t i = s.find('/'); i != s.npos; i = s.find('/', i + 1)) {
        const bool closing = i > 0 && s[i - 1] == '<', empty = i + 1 < s.size() && s[i + 1] == '>';
        if (!closing && !empty) return false;
    }
    return true;
}

} // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    fuzz::quiet();
    fuzz::preload();
    OIIO::attribute("threads", 1);
    // Every seed of every target, by its bare name: quad.ply, tri.obj, ramp.spd, tiny.exr, ...
    namespace fs = std::filesystem;
    const fs::path& dir = fuzz::scratchDir("xml");
    std::error_code ec;
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(EFFIGI_FUZZ_CORPUS, ec))
        if (e.is_regular_file() && e.path().filename().string()[0] != '.')
            fs::copy_file(e.path(), dir / e.path().filename(), fs::copy_options::overwrite_existing, ec);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > 65536) return -1;
    const std::string text(reinterpret_cast<const char*>(data), size);
    if (!staysInScratch(text)) return -1;  // -1: libFuzzer keeps it out of the corpus
    const std::string file = (fuzz::scratchDir("xml") / "fuzz-scene.xml").string();
    fuzz::expectCleanRejection([&] {
        std::unique_ptr<xml::Node> root = xml::parseString(text, file);
        std::unique_ptr<Scene> scene = loadScene(*root, Registry::instance());
    });
    return 0;
}
