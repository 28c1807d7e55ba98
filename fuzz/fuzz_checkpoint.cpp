// Fuzz target: checkpoint files (effigi render --resume DIR reads DIR/checkpoint.effigi;
// src/render/checkpoint.cpp), and the sums in them put back into a film and a renderer.
//
// Why: a checkpoint is a binary file of lengths and arrays. Its checksum refuses a file
// damaged by accident, so mutated whole files mostly stop there; to reach the fields
// behind it, an input that does not start with the magic "EFFIGICK" is taken as a payload
// and framed with a valid header (checkpointHeader). Then the film's and the renderer's
// sums are loaded into those of a small scene (fuzz/checkpoint_scene.xml, as the resume
// does after the identity check), and the film is developed: its pixels must be finite.
#include "fuzz_common.hpp"

#include "effigi/interfaces/iaccumulator.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/render/checkpoint.hpp"
#include "effigi/render/scene.hpp"
#include "effigi/xml/loader.hpp"

#include <cmath>
#include <memory>

using namespace effigi;

namespace {

std::unique_ptr<Scene>& scene() {
    static std::unique_ptr<Scene> s;
    return s;
}

void load(IComponent& c, const AccumulatorSums& sums) {
    IAccumulator* a = query<IAccumulator>(&c);
    if (!a) {
        std::fprintf(stderr, "fuzz: %s keeps no sums\n", c.typeName().c_str());
        std::exit(2);  // the harness's scene is wrong, not the input
    }
    a->loadSums(sums);
}

} // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    fuzz::quiet();
    scene() = loadSceneFile(EFFIGI_FUZZ_DIR "/checkpoint_scene.xml");
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::filesystem::path& dir = fuzz::scratchDir("checkpoint");
    const std::string_view input(reinterpret_cast<const char*>(data), size);
    std::string file(input);
    if (!input.starts_with("EFFIGICK")) file.insert(0, checkpointHeader(input));
    fuzz::writeInput(checkpointFile(dir), reinterpret_cast<const std::uint8_t*>(file.data()), file.size());
    fuzz::expectCleanRejection([&] {
        const Checkpoint c = readCheckpoint(dir);
        IFilm& film = scene()->camera().film();
        load(film, c.film);
        load(scene()->renderer(), c.renderer);
        const Image img = film.develop();
        for (float v : img.pixels)
            if (!std::isfinite(v)) {
                std::fputs("fuzz: a loaded checkpoint developed a pixel that is not finite\n", stderr);
                std::abort();
            }
    });
    return 0;
}
