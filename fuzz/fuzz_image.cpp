// Fuzz target: image files as bitmap textures and environment maps read them
// (src/render/bitmap.cpp: effigi's PNG chunk and OpenEXR header checks, then OpenImageIO's
// readers for PNG, OpenEXR, JPEG, Radiance HDR, ...), and the components built from an
// accepted image.
//
// Why: images are the largest untrusted binary input of a scene. Bitmap::load must turn
// every refusal of OpenImageIO (multi-line, from libpng, libjpeg or OpenEXR) into one
// line, refuse headers that claim absurd sizes before allocating, and never hand NaN on.
// OpenImageIO picks its reader by the file's extension (then tries the others), so the
// input is written to a file named after its magic bytes. The system's image libraries
// are not instrumented: the fuzzer sees coverage only in effigi's code, but crashes and
// hangs inside the libraries are still caught. An accepted image is also built into the
// `envmap` emitter (importance-sampling tables, peak checks) and the `bitmap` texture.
// Slow (tens of inputs per second): OpenImageIO 2.4 allocates a 64 MB conversion buffer for
// every image it reads as float, whatever its size (ImageInput::read_scanlines), which
// costs tens of milliseconds under AddressSanitizer.
#include "fuzz_common.hpp"

#include "effigi/render/bitmap.hpp"

#include <OpenImageIO/imageio.h>

#include <cstring>

using namespace effigi;

namespace {

/// The extension a scene would give a file with these first bytes.
const char* extensionFor(const std::uint8_t* d, std::size_t n) {
    auto starts = [&](const char* magic, std::size_t len) { return n >= len && std::memcmp(d, magic, len) == 0; };
    if (starts("\x89PNG", 4)) return ".png";
    if (starts("v/1\x01", 4)) return ".exr";
    if (starts("\xff\xd8\xff", 3)) return ".jpg";
    if (starts("#?", 2)) return ".hdr";
    if (starts("PF", 2) || starts("Pf", 2)) return ".pfm";
    if (n >= 2 && d[0] == 'P' && d[1] >= '1' && d[1] <= '6') return ".ppm";
    if (starts("BM", 2)) return ".bmp";
    if (starts("II*\0", 4) || starts("MM\0*", 4)) return ".tif";
    if (starts("GIF8", 4)) return ".gif";
    return ".tga";  // TGA has no magic number
}

} // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    fuzz::quiet();
    fuzz::preload({{"emitter", "envmap"}, {"texture", "bitmap"}});
    OIIO::attribute("threads", 1);  // one thread: libFuzzer's timing and leak checks stay simple
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::filesystem::path dir = fuzz::scratchDir("image");
    const std::filesystem::path file = fuzz::writeInput(dir / (std::string("image") + extensionFor(data, size)), data, size);
    bool accepted = false;
    fuzz::expectCleanRejection([&] {
        Bitmap::load(file);
        accepted = true;
    });
    if (accepted) {
        fuzz::expectCleanRejection([&] { fuzz::createWithFile("emitter", "envmap", file); });
        fuzz::expectCleanRejection([&] { fuzz::createWithFile("texture", "bitmap", file); });
    }
    std::error_code ec;
    std::filesystem::remove(file, ec);  // the next input may pick another extension
    return 0;
}
