// Fuzz target: Mitsuba's .serialized meshes (components/shape/serialized.cpp: zlib
// streams, an end-of-file dictionary of mesh offsets).
//
// Why: the format is binary and compressed: vertex and triangle counts inside the stream
// size the allocations, the dictionary's offsets and count decide where the reader seeks,
// and zlib may end early or report corruption at any point. The reader lives inside the
// `serialized` module, so the input is written to a file and the shape is built through
// the registry, twice: shape_index 0 reads the first mesh straight from the start, and
// shape_index 1 goes through the dictionary (seek, header check) to the second.
#include "fuzz_common.hpp"

using namespace effigi;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    fuzz::quiet();
    fuzz::preload({{"shape", "serialized"}});
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::filesystem::path file = fuzz::writeInput(fuzz::scratchDir("serialized") / "mesh.serialized", data, size);
    for (std::int64_t index : {0, 1})
        fuzz::expectCleanRejection([&] {
            fuzz::createWithFile("shape", "serialized", file, {{"shape_index", PropertyValue(index)}});
        });
    return 0;
}
