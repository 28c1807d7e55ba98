// Fuzz target: Wavefront OBJ meshes (components/shape/obj.cpp over tinyobjloader).
//
// Why: OBJ is text that anyone edits by hand; tinyobjloader accepts a lot and leaves the
// range checks of face indices (absolute, relative, v/vt/vn triples, polygons) to its
// caller, which is effigi's code. The OBJ reader has no in-memory entry point (it lives
// inside the `obj` module), so the input is written to a file in this process's scratch
// folder and the `obj` shape is built from it through the registry, exactly as a scene's
// <shape type="obj"> is: read, fan-triangulate, validate, transform, prepare sampling.
#include "fuzz_common.hpp"

using namespace effigi;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    fuzz::quiet();
    fuzz::preload({{"shape", "obj"}});
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::filesystem::path file = fuzz::writeInput(fuzz::scratchDir("obj") / "mesh.obj", data, size);
    fuzz::expectCleanRejection([&] { fuzz::createWithFile("shape", "obj", file); });
    return 0;
}
