// Fuzz target: Stanford PLY meshes (src/render/ply_header.cpp, ply_reader.cpp,
// ply_attributes.cpp), the reader effigi wrote itself for the `ply` shape.
//
// Why: PLY is the mesh format of most Mitsuba scenes, binary and hand-parsed: a header
// declares element counts, property types and list-length types that the body then has
// to honour, so lying counts, odd types, either byte order and truncation are where a
// hand-written reader over-reads or allocates what the file cannot back.
// The input goes through the in-memory entry point readPlyFromMemory; an input it accepts
// is also written to a file and built into the `ply` shape, so the mesh checks after
// reading (indices, NaN, coordinate range, normals, sampling tables) see accepted meshes.
#include "fuzz_common.hpp"

#include "effigi/render/ply_reader.hpp"

using namespace effigi;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    fuzz::quiet();
    fuzz::preload({{"shape", "ply"}});
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    bool accepted = false;
    fuzz::expectCleanRejection([&] {
        readPlyFromMemory(bytes, "fuzz.ply");
        accepted = true;
    });
    if (accepted) {
        const std::filesystem::path file = fuzz::writeInput(fuzz::scratchDir("ply") / "mesh.ply", data, size);
        fuzz::expectCleanRejection([&] { fuzz::createWithFile("shape", "ply", file); });
    }
    return 0;
}
