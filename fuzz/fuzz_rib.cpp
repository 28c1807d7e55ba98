// Fuzz target: RenderMan RIB scenes — the RIB lexer (strings, escapes, arrays, numbers,
// comments), the request interpreter with its attribute and transform stacks, the
// tessellation of quadrics, polygons and patches (src/rib), and the scene built from them
// through the loader's instantiate() (schemas, constructors, range checks, the
// accelerator), without rendering.
//
// Why: a RIB file is a program of requests whose arguments are checked one by one; the
// interesting inputs are the ones that reach the geometry with degenerate values (zero
// sweeps, flat or self-intersecting polygons, singular transforms) or break the block
// structure in the middle of a request.
// Bounded work: a RIB file names no other file, so no scratch folder is needed; inputs
// over 16 KB are skipped (each quadric or patch becomes up to a few thousand triangles,
// so 16 KB of requests stays well within libFuzzer's memory limit).
#include "fuzz_common.hpp"

#include "effigi/rib/loader.hpp"

using namespace effigi;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    fuzz::quiet();
    fuzz::preload({{"camera", "perspective"}, {"camera", "orthographic"}, {"film", "hdrfilm"},
                   {"sampler", "independent"}, {"rfilter", "gaussian"}, {"bsdf", "diffuse"}, {"bsdf", "plastic"},
                   {"bsdf", "roughplastic"}, {"bsdf", "conductor"}, {"bsdf", "roughconductor"}, {"bsdf", "twosided"},
                   {"bsdf", "mask"}, {"emitter", "point"}, {"emitter", "directional"}, {"emitter", "constant"},
                   {"shape", "sphere"}, {"shape", "cylinder"}, {"shape", "disk"}, {"renderer", "path"},
                   {"accelerator", "embree"}});
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > 16384) return -1;
    const std::string text(reinterpret_cast<const char*>(data), size);
    fuzz::expectCleanRejection([&] { std::unique_ptr<Scene> scene = rib::loadString(text, "fuzz.rib"); });
    return 0;
}
