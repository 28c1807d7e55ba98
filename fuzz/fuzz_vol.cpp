// Fuzz target: Mitsuba's binary grid volumes (.vol, src/render/vol_reader.cpp), read for
// the `sdfgrid` shape.
//
// Why: a 48-byte header declares three resolutions and a channel count whose product sizes
// the allocation and the read; the reader must refuse any header that the bytes after it
// cannot back, and non-finite values, before it allocates. The input goes through the
// in-memory entry point readVolFromMemory; an input it accepts is also written to a file
// and built into the `sdfgrid` shape, which checks the grid (one channel, at least two
// points per axis) and precomputes from it (bounds, area estimate).
#include "fuzz_common.hpp"

#include "effigi/render/vol_reader.hpp"

using namespace effigi;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    fuzz::quiet();
    fuzz::preload({{"shape", "sdfgrid"}});
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    bool accepted = false;
    fuzz::expectCleanRejection([&] {
        readVolFromMemory(bytes, "fuzz.vol");
        accepted = true;
    });
    if (accepted) {
        const std::filesystem::path file = fuzz::writeInput(fuzz::scratchDir("vol") / "grid.vol", data, size);
        fuzz::expectCleanRejection([&] { fuzz::createWithFile("shape", "sdfgrid", file); });
    }
    return 0;
}
